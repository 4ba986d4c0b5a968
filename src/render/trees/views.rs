//! The trees each pass draws: the main view and each water view only the trees whose bands may
//! reach into their [`ClipRegion`](crate::render::clip::ClipRegion), the sun's shadow map only
//! those that may reach into its own clip volume and whose shadows may fall into one of those
//! views ([`shadow_box`]). A culled tree lies
//! wholly outside the pass's region, so no pixel changes: the pass is spared its vertices and its
//! triangles, which on a software rasteriser cost as much as the pixels of a small tree.
//!
//! A tree is where its model's height bands can reach in this frame's wind ([`super::sweep`]).
//!
//! Units: metres.

use glam::Vec3;
use grove_systems::wind_model::WindParams;

use super::instances::{BucketRanges, Gathered, Instance, bucket_ranges};
use super::lod;
use super::model::GpuModel;
use super::sweep::Placement;

/// What a tree's bands' boxes depend on, of its instance.
fn placement(i: &Instance) -> Placement {
    Placement { origin: i.origin, scale: i.scale, yaw: i.yaw, bend: i.bend, gain: i.gain, keep: i.keep }
}

/// The box an impostor of `model` at `instance` can cover: its bounding sphere's square facing
/// any direction, world metres.
fn impostor_box(model: &GpuModel, instance: &Instance) -> Option<(Vec3, Vec3)> {
    let atlas = model.impostor.as_ref()?;
    let (s, c) = instance.yaw.sin_cos();
    let m = atlas.centre * instance.scale;
    let centre = Vec3::from(instance.origin) + Vec3::new(c * m.x + s * m.z, m.y, -s * m.x + c * m.z);
    let half = Vec3::splat(atlas.radius * instance.scale * std::f32::consts::SQRT_2);
    Some((centre - half, centre + half))
}

/// The trees of `every` (as [`super::instances::gather`] groups them; `models` by the same index) with a
/// band box ([`super::sweep`], in `wind`) for which `keep` holds, in the same order; impostors
/// by their square's box.
pub(crate) fn cull(
    every: &Gathered,
    models: &[Option<GpuModel>],
    wind: &WindParams,
    keep: impl Fn(Vec3, Vec3) -> bool,
) -> Gathered {
    let mut out = Gathered::default();
    for (m, buckets) in every.ranges.iter().enumerate() {
        let model = models.get(m).and_then(Option::as_ref);
        let mut ranges: BucketRanges = Default::default();
        for (b, range) in buckets.iter().enumerate() {
            let start = out.instances.len() as u32;
            if let Some(model) = model {
                let kept = every.instances[range.start as usize..range.end as usize]
                    .iter()
                    .filter(|i| model.sweep.boxes(&placement(i), wind).any(|(lo, hi)| keep(lo, hi)));
                out.instances.extend(kept);
            }
            ranges[b] = start..out.instances.len() as u32;
        }
        out.ranges.push(ranges);
    }
    for (m, range) in every.impostor_ranges.iter().enumerate() {
        let start = out.impostors.len() as u32;
        if let Some(model) = models.get(m).and_then(Option::as_ref) {
            let kept = every.impostors[range.start as usize..range.end as usize]
                .iter()
                .filter(|i| impostor_box(model, i).is_none_or(|(lo, hi)| keep(lo, hi)));
            out.impostors.extend(kept);
        }
        out.impostor_ranges.push(start..out.impostors.len() as u32);
    }
    out
}

/// The smallest area, in shadow-map texels, that a leaf drawn into the shadow map should cover:
/// 4 × 4 texels, a little over the 3 × 3 texels each shadow lookup filters.
pub const SHADOW_LEAF_TEXELS: f32 = 16.0;

/// `casters` (grouped as [`super::instances::gather`] groups them) with each mesh tree's share
/// of leaves lowered to what the shadow map can show: a leaf should cover
/// [`SHADOW_LEAF_TEXELS`] texels at `texels_per_metre` ([`lod::keep_fraction`] in the light's
/// orthographic view), and no tree draws more leaves than the camera's view keeps. `leaf_area`
/// gives a model's mean leaf area in square metres (by model index). Trees move to their new
/// keep buckets, in the order they had within each model; impostors are unchanged.
pub(crate) fn shadow_detail(
    casters: &Gathered,
    leaf_area: impl Fn(usize) -> Option<f32>,
    texels_per_metre: f32,
) -> Gathered {
    let mut out = Gathered {
        impostors: casters.impostors.clone(),
        impostor_ranges: casters.impostor_ranges.clone(),
        ..Default::default()
    };
    for (m, buckets) in casters.ranges.iter().enumerate() {
        let area = leaf_area(m);
        let mut list: Vec<(usize, Instance)> = buckets
            .iter()
            .flat_map(|r| casters.instances[r.start as usize..r.end as usize].iter().copied())
            .map(|mut i| {
                if let Some(a) = area {
                    i.keep = i.keep.min(lod::keep_fraction(
                        a * i.scale * i.scale,
                        1.0,
                        texels_per_metre,
                        SHADOW_LEAF_TEXELS,
                    ));
                }
                (lod::bucket(i.keep), i)
            })
            .collect();
        // A stable sort: each bucket keeps its trees in the order they had.
        list.sort_by_key(|e| e.0);
        out.ranges.push(bucket_ranges(out.instances.len() as u32, &list, |e| e.0));
        out.instances.extend(list.iter().map(|e| e.1));
    }
    out
}

/// The box that holds the box `lo..hi` and its shadow, cast away from the sun (`sun`, a unit
/// vector towards it) down to the height `floor`: the box and its copy moved along the light
/// until its top reaches `floor`. `None` where the sun is too low to bound the shadow.
pub fn shadow_box(lo: Vec3, hi: Vec3, sun: Vec3, floor: f32) -> Option<(Vec3, Vec3)> {
    if !(sun.y > 1e-3) {
        return None;
    }
    let moved = sun * ((hi.y - floor).max(0.0) / sun.y);
    Some((lo.min(lo - moved), hi.max(hi - moved)))
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::{SHADOW_LEAF_TEXELS, bucket_ranges, shadow_box, shadow_detail};
    use crate::render::trees::instances::{Gathered, Instance};
    use crate::render::trees::lod;

    fn tree(x: f32, scale: f32, keep: f32) -> Instance {
        Instance {
            origin: [x, 0.0, 0.0],
            scale,
            yaw: 0.0,
            bend: [0.0; 2],
            gain: 1.0,
            phase: 0.0,
            keep,
            fade: 0.0,
            handoff: 0.0,
        }
    }

    /// Trees of model 0 (with leaves) and 1 (without), grouped by their keep buckets.
    fn gathered(trees: &[(usize, Instance)]) -> Gathered {
        let mut g =
            Gathered { impostors: vec![tree(99.0, 1.0, 1.0)], impostor_ranges: vec![0..1, 1..1], ..Default::default() };
        for m in 0..2 {
            let mut list: Vec<Instance> = trees.iter().filter(|t| t.0 == m).map(|t| t.1).collect();
            list.sort_by_key(|i| lod::bucket(i.keep));
            g.ranges.push(bucket_ranges(g.instances.len() as u32, &list, |i| lod::bucket(i.keep)));
            g.instances.extend(list);
        }
        g
    }

    #[test]
    fn the_shadow_map_draws_no_more_leaves_than_its_texels_show() {
        // Leaves of 0.01 m² on trees at full size: at 40 texels a metre a leaf covers 16 texels
        // (all of it kept), at 20 texels a metre 4 (a quarter).
        assert!((lod::keep_fraction(0.01, 1.0, 40.0, SHADOW_LEAF_TEXELS) - 1.0).abs() < 1e-6);
        let trees =
            [(0, tree(1.0, 1.0, 1.0)), (0, tree(2.0, 1.0, 0.1)), (0, tree(3.0, 0.5, 1.0)), (1, tree(4.0, 1.0, 1.0))];
        let g = gathered(&trees);
        let area = |m: usize| (m == 0).then_some(0.01);
        // At 40 texels a metre only the half-size tree, whose leaves cover 4 texels, is thinned.
        let fine = shadow_detail(&g, area, 40.0);
        let keeps = |g: &Gathered| g.instances.iter().map(|i| (i.origin[0], i.keep)).collect::<Vec<_>>();
        let mut before = keeps(&g);
        let mut after = keeps(&fine);
        before.sort_by(|a, b| a.0.total_cmp(&b.0));
        after.sort_by(|a, b| a.0.total_cmp(&b.0));
        let expected = [(1.0, 1.0), (2.0, 0.1), (3.0, 0.25), (4.0, 1.0)];
        assert!(after.iter().zip(&expected).all(|(a, e)| a.0 == e.0 && (a.1 - e.1).abs() < 1e-5), "{after:?}");
        // Coarse texels: the near tree keeps a quarter, the half-size one 1/16, the one the
        // camera already thinned keeps its 0.1, the model without leaves is left alone.
        let coarse = shadow_detail(&g, area, 20.0);
        let at = |x: f32| coarse.instances.iter().find(|i| i.origin[0] == x).unwrap().keep;
        assert!((at(1.0) - 0.25).abs() < 1e-6 && (at(3.0) - 0.0625).abs() < 1e-6, "{:?}", keeps(&coarse));
        assert_eq!((at(2.0), at(4.0)), (0.1, 1.0));
        // Each tree lies in its model's range, in the range of its new bucket.
        for (m, buckets) in coarse.ranges.iter().enumerate() {
            for (b, r) in buckets.iter().enumerate() {
                for i in &coarse.instances[r.start as usize..r.end as usize] {
                    assert_eq!(lod::bucket(i.keep), b);
                    assert_eq!(trees.iter().find(|t| t.1.origin == i.origin).unwrap().0, m);
                }
            }
        }
        assert_eq!(coarse.instances.len(), 4);
        assert_eq!((coarse.impostors.len(), coarse.impostor_ranges.clone()), (1, vec![0..1, 1..1]));
    }

    #[test]
    fn a_shadow_box_reaches_down_the_light_to_the_floor() {
        // The sun at 45° in the south (+Z): shadows fall north (-Z) as long as the height.
        let sun = Vec3::new(0.0, 1.0, 1.0).normalize();
        let (lo, hi) = shadow_box(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 10.0, 1.0), sun, 0.0).unwrap();
        assert!((lo - Vec3::new(-1.0, -10.0, -11.0)).length() < 1e-4, "{lo}");
        assert!((hi - Vec3::new(1.0, 10.0, 1.0)).length() < 1e-4, "{hi}");
        // A sun at the horizon casts shadows without end.
        assert_eq!(shadow_box(Vec3::ZERO, Vec3::ONE, Vec3::X, 0.0), None);
    }
}
