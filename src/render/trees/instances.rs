//! The tree instances of a frame: one per tree, grouped by model and keep bucket, nearest first.

use glam::Vec3;

use super::extract::TreeDraw;
use super::model::GpuModel;
use super::{impostor, lod};
use crate::render::view::Camera;

/// One tree instance (vertex buffer slot 1; matches `VertexIn` in trees.wgsl, locations 5–11).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Instance {
    /// The tree's base, world metres.
    pub origin: [f32; 3],
    /// Uniform scale.
    pub scale: f32,
    /// Rotation about +Y, radians.
    pub yaw: f32,
    /// The trunk's lean, metres per metre of height, world X and Z (`WindState::bend`).
    pub bend: [f32; 2],
    /// The wind's gain at the tree (`WindState::gain`).
    pub gain: f32,
    /// The tree's wind phase, radians (`WindState::phase`).
    pub phase: f32,
    /// The share of the leaves drawn, 0..1 ([`lod::keep_fraction`]).
    pub keep: f32,
    /// The share of the tree drawn as an impostor, 0..1 ([`impostor::fade`]; location 13): the
    /// mesh drops the fragments whose dither is below it. The far model of a tree in the
    /// cross-fade from its model also drops those below `1 -` [`far_share`] here.
    pub fade: f32,
    /// The share of the tree handed to its far model, 0..1 ([`far_share`]; location 15): the
    /// mesh drops the fragments whose dither is at least `1 - handoff`, which the far model
    /// keeps. 0 on far models and on models without one.
    pub handoff: f32,
}

/// The on-screen sizes, in pixels, that choose how a tree is drawn (see [`gather`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Detail {
    /// The smallest area a drawn leaf should cover ([`lod::keep_fraction`]).
    pub leaf_pixels: f32,
    /// Below this bounding-sphere size a tree is an impostor ([`impostor::fade`]).
    pub impostor_pixels: f32,
    /// Below this bounding-sphere size a tree is drawn as its model's far model, if it has one.
    pub far_pixels: f32,
    /// Cross-fade between levels of detail over a band ([`FAR_BAND`], [`impostor::BAND`]);
    /// without it, each level gives way to the next at once at its threshold.
    pub cross_fade: bool,
}

/// The width of the cross-fade band from a model to its far model: a tree is all model above
/// `FAR_BAND` times `far_pixels` and all far model below `far_pixels`; between, the two share
/// its pixels by the impostors' screen-door dither (`impostor_dither`), so the switch trades
/// pixels one by one instead of popping.
pub const FAR_BAND: f32 = 1.25;

/// The share of a tree handed to its model's far model, 0 (all model) to 1 (all far model): its
/// model has bounds `bounds` (model space), the tree is at `scale` and `distance` metres, and
/// its bounding sphere's diameter covers some pixels against `far_pixels` (0: never the far
/// model), with the band [`FAR_BAND`], or a hard switch at `far_pixels` without `cross_fade`.
pub fn far_share(
    bounds: (Vec3, Vec3),
    scale: f32,
    distance: f32,
    pixels_per_radian: f32,
    far_pixels: f32,
    cross_fade: bool,
) -> f32 {
    let radius = bounds.0.abs().max(bounds.1.abs()).length() * scale;
    let band = if cross_fade { FAR_BAND } else { 1.0 };
    impostor::fade_in_band(2.0 * radius, distance, pixels_per_radian, far_pixels, band)
}

/// A tree whose base lies this deep in the aerial perspective's haze
/// ([`haze_share`](crate::render::haze::haze_share), from about 566 m on) is not drawn:
/// trees fade into the haze as the ground does (`trees.wgsl`, `impostor.wgsl`), so it would
/// differ from the haze behind it by at most 3 % of its contrast, a few levels of 255.
pub const HIDDEN_IN_HAZE: f32 = 0.97;

/// The instance range of each keep bucket of one model.
pub(crate) type BucketRanges = [std::ops::Range<u32>; lod::BUCKETS];

/// A frame's tree instances, as [`gather`] sorts them; or the part of them one pass draws
/// (`views::cull`), in the same order.
#[derive(Clone, Debug, Default)]
pub(crate) struct Gathered {
    /// The mesh instances (trees not wholly impostors).
    pub instances: Vec<Instance>,
    /// The mesh instance range of each (model, keep bucket).
    pub ranges: Vec<BucketRanges>,
    /// The impostor instances (trees with a fade above 0), grouped by model, nearest first.
    pub impostors: Vec<Instance>,
    /// The impostor instance range of each model.
    pub impostor_ranges: Vec<std::ops::Range<u32>>,
}

/// The instances of every tree whose model is loaded and that is not lost in the haze
/// ([`HIDDEN_IN_HAZE`]), grouped by model and, within a model, by
/// keep bucket ([`lod::bucket`]), nearest first; and the instance range of each (model,
/// bucket). `height` is the target's height in pixels and
/// `leaf_pixels` the smallest area a drawn leaf should cover. Trees of a model with an impostor
/// atlas whose bounding sphere covers fewer than `impostor_pixels` pixels (times
/// [`impostor::BAND`] for the cross-fade) also go to the impostor list; those wholly impostors
/// leave the mesh list. A tree whose model has a far model (`far`, by model index) is drawn as
/// that model wherever its bounding sphere covers fewer than `far_pixels`, and as both, sharing
/// its pixels, up to [`FAR_BAND`] times as many ([`far_share`]).
pub(crate) fn gather(
    trees: &[TreeDraw],
    models: &[Option<GpuModel>],
    far: &[Option<usize>],
    camera: &Camera,
    height: u32,
    detail: Detail,
) -> Gathered {
    let Detail { leaf_pixels, impostor_pixels, far_pixels, cross_fade } = detail;
    let band = if cross_fade { impostor::BAND } else { 1.0 };
    let eye = camera.position;
    let pixels_per_radian = height as f32 * 0.5 / (camera.fov_y * 0.5).tan().max(1e-3);
    // Per model: (bucket, squared distance, instance).
    let mut per_model: Vec<Vec<(usize, f32, Instance)>> = (0..models.len()).map(|_| Vec::new()).collect();
    let mut impostors: Vec<Vec<(f32, Instance)>> = (0..models.len()).map(|_| Vec::new()).collect();
    for t in trees {
        let Some(Some(near)) = models.get(t.model) else {
            continue;
        };
        let scale = t.scale;
        let d2 = (t.origin - eye).length_squared();
        let distance = d2.sqrt();
        if crate::render::haze::haze_share(distance) >= HIDDEN_IN_HAZE {
            continue;
        }
        // A tree small on screen is drawn as its model's far model, where it has one, and as
        // both within the band: (model index, share handed to the far model).
        let share = match far.get(t.model).copied().flatten() {
            Some(f) if matches!(models.get(f), Some(Some(_))) => {
                Some((f, far_share(near.bounds, scale, distance, pixels_per_radian, far_pixels, cross_fade)))
            }
            _ => None,
        };
        let levels = match share {
            Some((f, s)) if s >= 1.0 => [Some((f, 0.0, 0.0)), None],
            // The model keeps the pixels whose dither is below 1 - s, the far model the others.
            Some((f, s)) if s > 0.0 => [Some((t.model, 0.0, s)), Some((f, 1.0 - s, 0.0))],
            _ => [Some((t.model, 0.0, 0.0)), None],
        };
        for (index, floor, handoff) in levels.into_iter().flatten() {
            let Some(Some(model)) = models.get(index) else {
                continue;
            };
            let keep = lod::keep_fraction(model.leaf_area * scale * scale, distance, pixels_per_radian, leaf_pixels);
            let fade = model.impostor.as_ref().map_or(0.0, |a| {
                impostor::fade_in_band(2.0 * a.radius * scale, distance, pixels_per_radian, impostor_pixels, band)
            });
            let instance = Instance {
                origin: t.origin.to_array(),
                scale,
                yaw: t.yaw,
                bend: t.bend.to_array(),
                gain: t.gain,
                phase: t.phase,
                keep,
                fade: fade.max(floor),
                handoff,
            };
            if fade < 1.0 {
                per_model[index].push((lod::bucket(keep), d2, instance));
            }
            if fade > 0.0 {
                impostors[index].push((d2, Instance { fade, ..instance }));
            }
        }
    }
    // Nearest first within each bucket, so that the early depth test of a software rasteriser
    // skips more hidden fragments of farther trees. Ties are broken by position, so the order
    // never depends on the world's storage order.
    let mut all = Vec::new();
    let mut ranges = Vec::new();
    for mut list in per_model {
        list.sort_by(|p, q| {
            p.0.cmp(&q.0)
                .then(p.1.total_cmp(&q.1))
                .then(p.2.origin[0].total_cmp(&q.2.origin[0]))
                .then(p.2.origin[2].total_cmp(&q.2.origin[2]))
        });
        ranges.push(bucket_ranges(all.len() as u32, &list, |e| e.0));
        all.extend(list.iter().map(|e| e.2));
    }
    let mut flat = Vec::new();
    let mut impostor_ranges = Vec::new();
    for mut list in impostors {
        list.sort_by(|p, q| {
            p.0.total_cmp(&q.0)
                .then(p.1.origin[0].total_cmp(&q.1.origin[0]))
                .then(p.1.origin[2].total_cmp(&q.1.origin[2]))
        });
        let base = flat.len() as u32;
        flat.extend(list.iter().map(|e| e.1));
        impostor_ranges.push(base..flat.len() as u32);
    }
    Gathered { instances: all, ranges, impostors: flat, impostor_ranges }
}

/// The range of each keep bucket of one model's instances, `sorted` by their bucket (`bucket`
/// of each), once they are placed from `base` in the instance list: each bucket is one run.
pub(crate) fn bucket_ranges<T>(base: u32, sorted: &[T], bucket: impl Fn(&T) -> usize) -> BucketRanges {
    let end = |b: usize| base + sorted.partition_point(|e| bucket(e) < b) as u32;
    std::array::from_fn(|b| end(b)..end(b + 1))
}

/// The bounds of every tree whose model is loaded, metres: each model's box turned to any yaw
/// (its widest horizontal extent both ways), scaled and placed.
pub(crate) fn bounds(trees: &[TreeDraw], models: &[Option<GpuModel>]) -> Option<(Vec3, Vec3)> {
    let mut bounds: Option<(Vec3, Vec3)> = None;
    for t in trees {
        let Some(Some(model)) = models.get(t.model) else {
            continue;
        };
        let scale = t.scale;
        let r = model.bounds.0.abs().max(model.bounds.1.abs());
        let ext = Vec3::new(r.x.max(r.z), 0.0, r.x.max(r.z)) * scale;
        let lo = t.origin + Vec3::new(-ext.x, model.bounds.0.y * scale, -ext.z);
        let hi = t.origin + Vec3::new(ext.x, model.bounds.1.y * scale, ext.z);
        bounds = Some(bounds.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
    }
    bounds
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::{FAR_BAND, far_share};

    #[test]
    fn a_far_model_stands_in_below_its_size_on_screen() {
        // A model 10 m tall and 2 m wide: its bounding sphere about the base has a radius of
        // |(1, 10, 1)| = 10.0995 m. At 720 lines and 60° the view has 623.5 pixels per radian,
        // so the sphere covers 2 × 10.0995 / 50 × 623.5 = 251.9 pixels at 50 m, 419.8 at 30 m.
        let bounds = (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 10.0, 1.0));
        let ppr = 720.0 * 0.5 / (30f32.to_radians()).tan();
        let hard = |scale: f32, d: f32, px: f32| far_share(bounds, scale, d, ppr, px, false);
        assert_eq!(hard(1.0, 50.0, 400.0), 1.0);
        assert_eq!(hard(1.0, 30.0, 400.0), 0.0);
        // Half the size at 30 m is the whole size at 60 m.
        assert_eq!(hard(0.5, 30.0, 400.0), 1.0);
        assert_eq!(hard(1.0, 50.0, 250.0), 0.0);
        // 0 never uses the far model.
        assert_eq!(hard(1.0, 1e6, 0.0), 0.0);
        assert_eq!(far_share(bounds, 1.0, 1e6, ppr, 0.0, true), 0.0);
        // With the cross-fade, 419.8 px lies in the band 400..500 px, a fifth of the way in; at
        // 50 m the far model has it all, and above 500 px the model.
        let soft = |d: f32| far_share(bounds, 1.0, d, ppr, 400.0, true);
        assert!((soft(30.0) - (500.0 - 419.8) / 100.0).abs() < 2e-3, "{}", soft(30.0));
        assert_eq!(soft(50.0), 1.0);
        assert_eq!(soft(2.0 * 10.0995 * ppr / (400.0 * FAR_BAND * 1.01)), 0.0);
    }
}
