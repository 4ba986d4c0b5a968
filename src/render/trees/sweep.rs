//! Where a tree's vertices can be: its model cut into height bands, each band's box at rest and
//! the largest wind channels of its vertices, so that a band's box can be widened by the most
//! the wind moves those vertices. A tree is the union of its bands' boxes; the low bands of a
//! tree (the trunk's foot) stay narrow even when its crown sways far.
//!
//! The reach follows `wind.wgsl` (the twin of `grove_systems::wind_model`) term by term, each at
//! its largest (a sine at ±1, the noise at 0 or 1): the trunk's lean `|bend| × h² / trunk
//! stiffness` (horizontal), the branch's bob `s × r² / branch stiffness` (vertical, 0.4 of it
//! along the wind), the leaves' flutter `s × leaf_flutter × b` on each axis and the noise
//! model's `s × noise_amplitude × (h + r) / 2` along the wind; `s` is strength × gust × gain.
//! Leaves that the level of detail grows about their centres ([`lod::leaf_scale`]) move by at
//! most their radius times the growth.
//!
//! Units: model-space metres in a [`Sweep`]; world metres out of [`Sweep::boxes`].

use glam::{Vec2, Vec3};
use grove_systems::wind_model::WindParams;

use super::lod;
use crate::models::Vertex;

/// How many height bands a model is cut into.
pub const BANDS: usize = 8;

/// One height band of a model: its vertices' box at rest and their largest wind channels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    /// The least corner of the box of the band's vertices at rest, model space.
    pub lo: Vec3,
    /// The greatest corner of that box.
    pub hi: Vec3,
    /// The largest squared height to the root (`_WIND` x), m².
    pub h2: f32,
    /// The largest squared distance to the trunk (`_WIND` y), m².
    pub r2: f32,
    /// The largest distance to the branch (`_WIND` z), m.
    pub b: f32,
    /// The largest height plus distance to the trunk (the noise model's weight), m.
    pub hr: f32,
    /// The largest distance of a leaf's vertex from the leaf's centre (0 where no primitive is
    /// simplified), m.
    pub leaf: f32,
}

/// Where a tree of a model stands and how the wind and the level of detail take it: what
/// [`Sweep::boxes`] reads of a tree instance (`instances::Instance`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The tree's base, world metres.
    pub origin: [f32; 3],
    /// Uniform scale.
    pub scale: f32,
    /// Rotation about +Y, radians.
    pub yaw: f32,
    /// The trunk's lean, metres per metre of height, world X and Z.
    pub bend: [f32; 2],
    /// The wind's gain at the tree.
    pub gain: f32,
    /// The share of the leaves drawn (the rest grown to keep the crown's area).
    pub keep: f32,
}

/// A model's bands (empty for a model without vertices).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sweep {
    /// The bands that hold vertices, lowest first.
    pub bands: Vec<Band>,
}

impl Sweep {
    /// The bands of a model's primitives: each primitive's vertices and, per vertex, its leaf's
    /// centre and rank (`lod`'s leaf order; a negative rank where it is not simplified).
    pub fn new<'a>(primitives: impl IntoIterator<Item = (&'a [Vertex], &'a [[f32; 4]])>) -> Sweep {
        let primitives: Vec<_> = primitives.into_iter().collect();
        let ys = primitives.iter().flat_map(|(v, _)| v.iter().map(|v| v.position[1]));
        let (y0, y1) = ys.fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), y| (a.min(y), b.max(y)));
        if !(y0 <= y1) {
            return Sweep::default();
        }
        let band_of = |y: f32| (((y - y0) / (y1 - y0).max(1e-6) * BANDS as f32) as usize).min(BANDS - 1);
        let mut bands: Vec<Option<Band>> = vec![None; BANDS];
        for (vertices, leaves) in primitives {
            for (i, v) in vertices.iter().enumerate() {
                let p = Vec3::from(v.position);
                let [h, r, b, _] = v.wind.map(f32::abs);
                let leaf =
                    leaves.get(i).filter(|l| l[3] >= 0.0).map_or(0.0, |l| p.distance(Vec3::new(l[0], l[1], l[2])));
                let e = Band { lo: p, hi: p, h2: h * h, r2: r * r, b, hr: h + r, leaf };
                let slot = &mut bands[band_of(p.y)];
                *slot = Some(match *slot {
                    None => e,
                    Some(a) => Band {
                        lo: a.lo.min(p),
                        hi: a.hi.max(p),
                        h2: a.h2.max(e.h2),
                        r2: a.r2.max(e.r2),
                        b: a.b.max(e.b),
                        hr: a.hr.max(e.hr),
                        leaf: a.leaf.max(e.leaf),
                    },
                });
            }
        }
        Sweep { bands: bands.into_iter().flatten().collect() }
    }

    /// The world boxes the bands of a tree at `instance` can reach under `wind`, one per band.
    pub fn boxes<'a>(
        &'a self,
        instance: &'a Placement,
        wind: &'a WindParams,
    ) -> impl Iterator<Item = (Vec3, Vec3)> + 'a {
        let k = instance.scale;
        let (sin, cos) = instance.yaw.sin_cos();
        let origin = Vec3::from(instance.origin);
        let growth = (lod::leaf_scale(0.0, instance.keep) - 1.0).max(0.0);
        self.bands.iter().map(move |band| {
            // The band's box turned by the yaw (trees.wgsl's rotate_y), scaled and placed.
            let c = (band.lo + band.hi) * 0.5 * k;
            let e = (band.hi - band.lo) * 0.5 * k;
            let centre = origin + Vec3::new(cos * c.x + sin * c.z, c.y, -sin * c.x + cos * c.z);
            let half = Vec3::new(cos.abs() * e.x + sin.abs() * e.z, e.y, sin.abs() * e.x + cos.abs() * e.z);
            let reach = reach(band, k, instance.bend, instance.gain, wind) + Vec3::splat(band.leaf * k * growth);
            (centre - half - reach, centre + half + reach)
        })
    }
}

/// The most the wind moves a vertex of `band`, per world axis, for a tree at scale `k` with
/// the trunk's lean `bend` and the wind's `gain` at the tree.
pub fn reach(band: &Band, k: f32, bend: [f32; 2], gain: f32, wind: &WindParams) -> Vec3 {
    let s = (wind.strength * wind.gust * gain).abs();
    let lean = Vec2::from(bend).abs() * band.h2 * k * k / wind.trunk_stiffness.max(1e-6);
    let bob = s * band.r2 * k * k / wind.branch_stiffness.max(1e-6);
    let flutter = s * wind.leaf_flutter.abs() * band.b * k;
    let noise = s * wind.noise_amplitude.abs() * band.hr * k * 0.5;
    let horizontal = |lean: f32| lean + 0.4 * bob + flutter + noise;
    Vec3::new(horizontal(lean.x), bob + flutter, horizontal(lean.y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use grove_systems::wind_model::displace;

    /// The default wind response at `strength`, gust factor 1.
    fn wind(strength: f32) -> WindParams {
        WindParams {
            direction: [0.928, 0.371],
            strength,
            gust: 1.0,
            density: 0.15,
            noise_speed: 3.0,
            noise_amplitude: 0.06,
            time: 0.0,
            trunk_stiffness: 5.0,
            branch_stiffness: 20.0,
            branch_frequency: 0.7,
            leaf_flutter: 0.08,
            leaf_frequency: 2.5,
            model: 1,
            pad: [0; 2],
        }
    }

    fn vertex(p: [f32; 3], wind: [f32; 4]) -> Vertex {
        Vertex { position: p, wind, ..Default::default() }
    }

    #[test]
    fn bands_split_a_model_by_height_and_keep_each_bands_largest_channels() {
        // A trunk from 0 to 8 m and a branch tip at 7.5 m, 3 m out.
        let vertices = [
            vertex([0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0]),
            vertex([0.0, 8.0, 0.0], [8.0, 0.0, 0.0, 0.0]),
            vertex([3.0, 7.5, 0.0], [7.5, 3.0, 0.5, 0.2]),
        ];
        let leaves = lod::unsimplified(vertices.len());
        let sweep = Sweep::new([(&vertices[..], &leaves[..])]);
        assert_eq!(sweep.bands.len(), 2, "{:?}", sweep.bands);
        let (foot, top) = (sweep.bands[0], sweep.bands[1]);
        assert_eq!((foot.lo, foot.hi, foot.r2), (Vec3::ZERO, Vec3::ZERO, 0.0));
        assert_eq!((top.lo, top.hi), (Vec3::new(0.0, 7.5, 0.0), Vec3::new(3.0, 8.0, 0.0)));
        assert_eq!((top.h2, top.r2, top.b, top.hr, top.leaf), (64.0, 9.0, 0.5, 10.5, 0.0));
        // In a wind the foot does not move and the crown does.
        let w = wind(1.0);
        let at = Placement { origin: [1.0, 0.0, 2.0], scale: 2.0, yaw: 0.0, bend: [0.05, 0.0], gain: 1.0, keep: 1.0 };
        let boxes: Vec<_> = sweep.boxes(&at, &w).collect();
        assert_eq!(boxes[0], (Vec3::new(1.0, 0.0, 2.0), Vec3::new(1.0, 0.0, 2.0)));
        assert!(boxes[1].1.x > 1.0 + 6.0 && boxes[1].0.y < 15.0);
    }

    #[test]
    fn a_turned_band_box_holds_the_turned_vertices() {
        let vertices = [vertex([2.0, 1.0, 1.0], [0.0; 4]), vertex([3.0, 1.5, -1.0], [0.0; 4])];
        let leaves = lod::unsimplified(vertices.len());
        let sweep = Sweep::new([(&vertices[..], &leaves[..])]);
        let w = wind(0.0);
        for yaw in [0.3f32, 1.7, 3.0, -2.2] {
            let at = Placement { origin: [5.0, 0.5, -3.0], scale: 1.5, yaw, bend: [0.0; 2], gain: 1.0, keep: 1.0 };
            let (lo, hi): (Vec3, Vec3) =
                sweep.boxes(&at, &w).fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), (l, h)| (a.min(l), b.max(h)));
            let (s, c) = yaw.sin_cos();
            for v in &vertices {
                let p = Vec3::from(v.position) * 1.5;
                let world = Vec3::from(at.origin) + Vec3::new(c * p.x + s * p.z, p.y, -s * p.x + c * p.z);
                assert!(
                    world.cmpge(lo - 1e-5).all() && world.cmple(hi + 1e-5).all(),
                    "{world} outside {lo}..{hi} at yaw {yaw}"
                );
            }
        }
    }

    #[test]
    fn the_reach_bounds_the_cpu_wind_models() {
        // Both wind models of grove_systems (the shader's twins), at many times and channels
        // within a band's largest, never move a vertex farther on any axis than the reach.
        let band = Band { lo: Vec3::ZERO, hi: Vec3::ONE, h2: 100.0, r2: 9.0, b: 1.5, hr: 12.0, leaf: 0.0 };
        let (k, bend, gain) = (0.8f32, [0.08f32, -0.03], 1.3f32);
        let mut w = wind(2.0);
        w.gust = 1.5;
        let r = reach(&band, k, bend, gain, &w);
        let mut worst = Vec3::ZERO;
        for model in [0, 1] {
            for step in 0..2000 {
                w.time = step as f32 * 0.0173;
                let f = (step % 37) as f32 / 36.0;
                let g = (step % 11) as f32 / 10.0;
                let v0 = Vec3::new(3.0 * f, 10.0 * g, -2.0 * f) * k;
                let ch = glam::Vec4::new(10.0 * g * k, 3.0 * f * k, 1.5 * g * k, f);
                let moved = displace(model, v0, ch, Vec2::from(bend), gain, 0.3 * step as f32, &w);
                worst = worst.max((moved - v0).abs());
            }
        }
        assert!(worst.min_element() > 0.0, "the wind left an axis still: {worst}");
        assert!(worst.cmple(r).all(), "the wind moved a vertex by {worst}, more than the reach {r}");
    }

    #[test]
    fn grown_leaves_widen_the_boxes() {
        let vertices = [vertex([0.0, 0.0, 0.0], [0.0; 4]), vertex([1.0, 1.0, 0.0], [0.0; 4])];
        let leaves = vec![[0.5, 0.5, 0.0, 0.5], [0.5, 0.5, 0.0, 0.5]];
        let sweep = Sweep::new([(&vertices[..], &leaves[..])]);
        let w = wind(0.0);
        let at = |keep| Placement { origin: [0.0; 3], scale: 1.0, yaw: 0.0, bend: [0.0; 2], gain: 1.0, keep };
        let width = |keep| sweep.boxes(&at(keep), &w).fold(0.0f32, |m, (l, h)| m.max(h.x - l.x));
        assert!(width(0.1) > width(1.0) + 0.5, "{} vs {}", width(0.1), width(1.0));
    }
}
