//! The tree instances of a frame: one per tree, grouped by model and keep bucket, nearest first.

use glam::Vec3;

use super::{impostor, lod};
use super::model::GpuModel;
use super::extract::TreeDraw;
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
    /// The share of the tree drawn as an impostor, 0..1 ([`impostor::fade`]; location 13).
    pub fade: f32,
    /// Padding to 48 bytes.
    pub pad: f32,
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
}

/// Whether a tree whose model has bounds `bounds` (model space), at `scale` and `distance`
/// metres, covers fewer than `far_pixels` pixels with its bounding sphere's diameter, so that
/// its far model stands in for it.
pub fn uses_far(bounds: (glam::Vec3, glam::Vec3), scale: f32, distance: f32, pixels_per_radian: f32, far_pixels: f32) -> bool {
    let radius = bounds.0.abs().max(bounds.1.abs()).length() * scale;
    far_pixels > 0.0 && 2.0 * radius / distance.max(1e-3) * pixels_per_radian < far_pixels
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
/// that model wherever its bounding sphere covers fewer than `far_pixels` ([`uses_far`]).
pub(crate) fn gather(trees: &[TreeDraw], models: &[Option<GpuModel>], far: &[Option<usize>], camera: &Camera, height: u32, detail: Detail) -> Gathered {
    let Detail { leaf_pixels, impostor_pixels, far_pixels } = detail;
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
        // A tree small on screen is drawn as its model's far model, where it has one.
        let index = match far.get(t.model).copied().flatten() {
            Some(f) if matches!(models.get(f), Some(Some(_))) && uses_far(near.bounds, scale, distance, pixels_per_radian, far_pixels) => f,
            _ => t.model,
        };
        let Some(Some(model)) = models.get(index) else {
            continue;
        };
        let keep = lod::keep_fraction(model.leaf_area * scale * scale, distance, pixels_per_radian, leaf_pixels);
        let fade = model.impostor.as_ref().map_or(0.0, |a| impostor::fade(2.0 * a.radius * scale, distance, pixels_per_radian, impostor_pixels));
        let instance = Instance {
            origin: t.origin.to_array(),
            scale,
            yaw: t.yaw,
            bend: t.bend.to_array(),
            gain: t.gain,
            phase: t.phase,
            keep,
            fade,
            pad: 0.0,
        };
        if fade < 1.0 {
            per_model[index].push((lod::bucket(keep), d2, instance));
        }
        if fade > 0.0 {
            impostors[index].push((d2, instance));
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
        list.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.origin[0].total_cmp(&q.1.origin[0])).then(p.1.origin[2].total_cmp(&q.1.origin[2])));
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

    use super::uses_far;

    #[test]
    fn a_far_model_stands_in_below_its_size_on_screen() {
        // A model 10 m tall and 2 m wide: its bounding sphere about the base has a radius of
        // |(1, 10, 1)| = 10.0995 m. At 720 lines and 60° the view has 623.5 pixels per radian,
        // so the sphere covers 2 × 10.0995 / 50 × 623.5 = 251.9 pixels at 50 m, 419.8 at 30 m.
        let bounds = (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 10.0, 1.0));
        let ppr = 720.0 * 0.5 / (30f32.to_radians()).tan();
        assert!(uses_far(bounds, 1.0, 50.0, ppr, 400.0));
        assert!(!uses_far(bounds, 1.0, 30.0, ppr, 400.0));
        // Half the size at 30 m is the whole size at 60 m.
        assert!(uses_far(bounds, 0.5, 30.0, ppr, 400.0));
        assert!(!uses_far(bounds, 1.0, 50.0, ppr, 250.0));
        // 0 never uses the far model.
        assert!(!uses_far(bounds, 1.0, 1e6, ppr, 0.0));
    }
}
