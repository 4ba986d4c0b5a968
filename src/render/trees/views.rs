//! The trees each pass draws: the main view and each water view only the trees whose bands may
//! reach into their [`ClipRegion`](crate::render::clip::ClipRegion), the sun's shadow map only
//! those whose shadows may fall into one of those views ([`shadow_box`]). A culled tree lies
//! wholly outside the pass's region, so no pixel changes: the pass is spared its vertices and its
//! triangles, which on a software rasteriser cost as much as the pixels of a small tree.
//!
//! A tree is where its model's height bands can reach in this frame's wind ([`super::sweep`]).
//!
//! Units: metres.

use glam::Vec3;
use grove_systems::wind_model::WindParams;

use super::instances::{BucketRanges, Gathered, Instance};
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
pub(crate) fn cull(every: &Gathered, models: &[Option<GpuModel>], wind: &WindParams, keep: impl Fn(Vec3, Vec3) -> bool) -> Gathered {
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

    use super::shadow_box;

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
