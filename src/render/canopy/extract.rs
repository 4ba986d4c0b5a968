//! The canopy's extract: the photographed crowns (their `AerialCrown` components), sorted by
//! entity, and those in the camera's view.

use glam::{Vec2, Vec3};
use grove_systems::Sim;

use crate::render::feature::ExtractContext;
use crate::render::view::camera_matrix;

/// A photographed crown's tree as the canopy draws it (from its `AerialCrown` component).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CrownDraw {
    /// The tree's foot: its current position, world metres.
    pub foot: Vec3,
    /// World (X, Z) of the crown's centre in the photograph, metres.
    pub photo_centre: Vec2,
    /// The crown's radius, metres.
    pub radius_m: f32,
    /// The crown's base over the foot, metres.
    pub base_m: f32,
    /// The crown's top over the foot, metres.
    pub top_m: f32,
}

/// The canopy's data of a frame.
pub(crate) struct Crowns {
    /// Whether the world has any photographed crown (the canopy then casts shadows).
    pub any: bool,
    /// The crowns in the camera's view, sorted by entity.
    pub visible: Vec<CrownDraw>,
}

/// The photographed crowns, sorted by entity, and those in view; none when the canopy does not
/// draw them this frame.
pub(crate) fn crowns(sim: &Sim, cx: &ExtractContext<'_>) -> Crowns {
    if !cx.canopy {
        return Crowns { any: false, visible: Vec::new() };
    }
    let mut all: Vec<(u64, CrownDraw)> = Vec::new();
    sim.for_each_tree(|v| {
        if let Some(c) = v.crown {
            all.push((
                v.id,
                CrownDraw {
                    foot: v.transform.translation,
                    photo_centre: c.photo_centre,
                    radius_m: c.radius_m,
                    base_m: c.base_m,
                    top_m: c.top_m,
                },
            ));
        }
    });
    all.sort_by_key(|c| c.0);
    let view_proj = camera_matrix(&cx.common.camera, cx.size.0.max(1) as f32 / cx.size.1.max(1) as f32);
    Crowns { any: !all.is_empty(), visible: all.into_iter().map(|c| c.1).filter(|c| in_view(&view_proj, c)).collect() }
}

/// Whether a crown's layers, or the shadows they cast nearby, may be seen through `view_proj`:
/// its bounding sphere, grown by twice its height for the shadows, against the frustum's planes.
pub(crate) fn in_view(view_proj: &glam::Mat4, c: &CrownDraw) -> bool {
    let centre = c.foot + glam::Vec3::Y * (0.5 * (c.base_m + c.top_m));
    let r = 1.8 * c.radius_m + 0.5 * (c.top_m - c.base_m) + 2.0 * c.top_m;
    let m = view_proj.transpose();
    let (x, y, z, w) = (m.x_axis, m.y_axis, m.z_axis, m.w_axis);
    // Left, right, bottom, top, near (depth 0..1) and far planes of a wgpu projection.
    [w + x, w - x, w + y, w - y, z, w - z].iter().all(|p| {
        let n = p.truncate();
        let len = n.length().max(1e-12);
        (n.dot(centre) + p.w) / len >= -r
    })
}
