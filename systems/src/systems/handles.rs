//! Handles system: dragging a bounding-box handle scales (corners) or rotates (edges) the
//! selected tree, continuously while the Trigger is held.
//!
//! Reads: `Resources::interaction.handle_drag`, `Resources::edges` (Trigger going up),
//! `Resources::config` (`min_scale`, `max_scale`), `Resources::task` (a room layout's scale),
//! `Resources::catalogue`, `Controller` (ray), `Selection`, `Tree`.
//! Writes: `Transform` (yaw; origin height while scaling), `Scale`, `Resources::interaction`
//! (the handle drag ends on release), `Resources::spatial` (marked dirty on release),
//! `Resources::log` (scaled, rotated, on release).
//!
//! Every tick the grab point is the point on the current ray at the grab distance.
//! - A corner scales uniformly by the ratio of the grab point's horizontal distance to the
//!   tree's vertical axis now and at the grab, clamped to `[min_scale, max_scale]` times a room
//!   layout's scale. The tree scales about its lowest point, so a grounded tree stays on the
//!   ground.
//! - An edge turns the tree about +Y by the change in the grab point's angle around the axis.
//!
//! The spatial index is marked dirty once, at the release, not every tick.

use hecs::World;

use crate::components::{Controller, Handle, Scale, Transform, Tree};
use crate::events::Happening;
use crate::interact;
use crate::resources::Resources;
use crate::single;

/// Runs the handles system.
pub fn run(world: &mut World, res: &mut Resources) {
    let Some(hd) = res.interaction.handle_drag else { return };
    let Some(c) = single::get::<Controller>(world, &res.singles) else { return };
    let tree = interact::selected_tree(world, &res.singles);
    let found = tree.and_then(interact::entity).and_then(|e| {
        let model = world.get::<&Tree>(e).ok()?.model;
        Some((e, res.catalogue.get(model)?.lowest_point()))
    });
    let Some((e, lowest)) = found else {
        res.interaction.handle_drag = None;
        return;
    };
    let id = e.to_bits().get();
    let grab = c.ray_origin() + c.ray_dir() * hd.grab_distance;
    let cfg = &res.config;
    let Ok((t, s)) = world.query_one_mut::<(&mut Transform, &mut Scale)>(e) else { return };
    match hd.handle {
        Handle::Corner(_) => {
            let radius = interact::horizontal_radius(grab, t.translation);
            let (min, max) = cfg.scale_bounds(crate::task::layout_scale(res.task.as_ref()));
            let new = interact::corner_scale(hd.start_scale, hd.start_radius, radius, min, max);
            t.translation.y = interact::rescaled_origin_y(t.translation.y, lowest, s.0, new);
            s.0 = new;
        }
        Handle::Edge(_) => {
            t.yaw = interact::edge_yaw(hd.start_yaw, hd.start_angle, interact::angle_around(grab, t.translation));
        }
    }
    let (scale, yaw) = (s.0, t.yaw);

    if res.edges.up.trigger || !c.buttons.trigger {
        let tick = res.tick;
        match hd.handle {
            Handle::Corner(_) if scale != hd.start_scale => res.log.push(tick, Happening::Scaled { tree: id, scale }),
            Handle::Edge(_) if yaw != hd.start_yaw => res.log.push(tick, Happening::Rotated { tree: id, yaw }),
            _ => {}
        }
        res.interaction.handle_drag = None;
        res.spatial.mark_trees_dirty();
    }
}
