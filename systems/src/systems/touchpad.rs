//! Touchpad system: front/back moves the selected tree out/in along the controller ray,
//! left/right turns it counter-clockwise/clockwise.
//!
//! Reads: `Controller` (ray, touchpad axes), `Selection`, `Tree`, `Grounded`, `Water`,
//! `Resources::config` (`touchpad_dead_zone`, `touchpad_move_rate`, `touchpad_turn_rate_deg`,
//! `snap_threshold`), `Resources::catalogue`, `Resources::spatial` (planes, for grounded moves),
//! `Resources::interaction` (drag, handle drag, touchpad gesture).
//! Writes: `Transform`, `Grounded`, `Resources::interaction` (touchpad gesture; the drag's grab
//! distance), `Resources::spatial` (marked dirty when a gesture ends),
//! `Resources::log` (moved, rotated, when a gesture ends).
//!
//! An axis counts only when strictly beyond `touchpad_dead_zone`; its deflection scales the rate
//! (`touchpad_move_rate` m/s, `touchpad_turn_rate_deg` deg/s at full deflection).
//! - y > 0 moves the tree away from the controller, y < 0 towards it. While the tree is being
//!   dragged, the grab distance changes instead (never below 0.1 m) and the drag system moves it.
//!   Otherwise a tree that is not grounded moves along the ray direction; a grounded tree moves
//!   along the ray's horizontal direction and follows the plane under it (its height changes by
//!   the change of the plane's height under its axis, so it stands on the plane as it did),
//!   becoming ungrounded if it leaves every plane (a hole or an edge) or walks onto water.
//! - x < 0 turns the tree counter-clockwise seen from above, x > 0 clockwise.
//!
//! A gesture runs from the first tick an axis is beyond the dead zone until both are back inside
//! it (or the selection changes, or a handle is grabbed); Moved and Rotated are logged once, at
//! its end, and the spatial index is marked dirty then, not every tick. Nothing happens while a
//! handle is being dragged.

use glam::Vec3;
use hecs::World;

use crate::components::{Controller, Grounded, Transform, Tree};
use crate::events::Happening;
use crate::interact;
use crate::resources::{Resources, TouchpadGesture};
use crate::single;

/// The smallest grab distance the touchpad can pull a dragged tree to, metres.
pub const MIN_GRAB_DISTANCE: f32 = 0.1;

/// Runs the touchpad system.
pub fn run(world: &mut World, res: &mut Resources) {
    let Some(c) = single::get::<Controller>(world, &res.singles) else { return };
    let dz = res.config.touchpad_dead_zone;
    let (x, y) = (interact::touchpad_axis(c.touchpad.x, dz), interact::touchpad_axis(c.touchpad.y, dz));
    let active = (x != 0.0 || y != 0.0) && res.interaction.handle_drag.is_none();
    if !active && res.interaction.touchpad.is_none() {
        // No gesture to go on with or to end.
        return;
    }
    let selected = interact::selected_tree(world, &res.singles);

    if let Some(g) = res.interaction.touchpad
        && (!active || selected != Some(g.tree))
    {
        finish(world, res, g);
    }
    if !active {
        return;
    }
    let Some(e) = selected.and_then(interact::entity) else { return };
    let Some(lowest) = world.get::<&Tree>(e).ok().and_then(|t| res.catalogue.get(t.model)).map(|m| m.lowest_point())
    else {
        return;
    };
    let id = e.to_bits().get();
    let mut g = res.interaction.touchpad.unwrap_or(TouchpadGesture { tree: id, moved: false, rotated: false });
    let dt = res.dt;
    let step = y * res.config.touchpad_move_rate * dt;
    let turn = interact::touchpad_turn(x, res.config.touchpad_turn_rate_deg, dt);
    let dragged = res.interaction.drag.as_mut().filter(|d| d.tree == id);
    let lift = res.config.snap_threshold;
    let water = single::water(world, &res.singles);
    let dry = |spatial: &crate::spatial::SpatialIndex, at: Vec3, scale: f32| {
        crate::water::dry_ground(&water, interact::ground_under(spatial, at, lowest, scale, lift))
    };

    let Ok((t, grounded, s)) = world.query_one_mut::<(&mut Transform, &mut Grounded, &crate::components::Scale)>(e)
    else {
        return;
    };
    if step != 0.0 {
        if let Some(d) = dragged {
            d.grab_distance = (d.grab_distance + step).max(MIN_GRAB_DISTANCE);
        } else if grounded.0 {
            let dir = c.ray_dir();
            let flat = Vec3::new(dir.x, 0.0, dir.z).normalize_or_zero();
            if flat != Vec3::ZERO {
                let before = dry(&res.spatial, t.translation, s.0);
                t.translation += flat * step;
                match (before, dry(&res.spatial, t.translation, s.0)) {
                    (Some(b), Some(a)) => t.translation.y += a.point.y - b.point.y,
                    (None, Some(a)) => t.translation.y = interact::snapped_origin_y(a.point.y, lowest, s.0),
                    (_, None) => grounded.0 = false,
                }
                g.moved = true;
            }
        } else {
            t.translation += c.ray_dir() * step;
            g.moved = true;
        }
    }
    if turn != 0.0 {
        t.yaw = interact::wrap_angle(t.yaw + turn);
        g.rotated = true;
    }
    res.interaction.touchpad = Some(g);
}

/// Ends a gesture: logs what it did and marks the spatial index dirty.
fn finish(world: &World, res: &mut Resources, g: TouchpadGesture) {
    res.interaction.touchpad = None;
    let Some(t) = interact::entity(g.tree).and_then(|e| world.get::<&Transform>(e).ok().map(|t| *t)) else { return };
    let tick = res.tick;
    if g.moved {
        res.log.push(tick, Happening::Moved { tree: g.tree, position: t.translation });
    }
    if g.rotated {
        res.log.push(tick, Happening::Rotated { tree: g.tree, yaw: t.yaw });
    }
    if g.moved || g.rotated {
        res.spatial.mark_trees_dirty();
    }
}
