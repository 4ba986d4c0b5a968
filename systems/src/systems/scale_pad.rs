//! Scale pad system: the Scale pad (a phone's touch bar, `docs/headset.md`) grows the selected
//! tree while its value is above 0 and shrinks it while below, about the tree's lowest point.
//!
//! Reads: `ScalePad` (on the controller's entity), `Selection`, `Tree`,
//! `Resources::config` (`touchpad_dead_zone`, `min_scale`, `max_scale`), `Resources::task` (a room
//! layout's scale), `Resources::catalogue`, `Resources::interaction` (handle drag).
//! Writes: `ScalePad` (the gesture), `Transform` (origin height), `Scale`,
//! `Resources::spatial` (marked dirty when a gesture that changed the scale ends),
//! `Resources::log` (scaled, when such a gesture ends).
//!
//! The value counts only when strictly beyond `touchpad_dead_zone`; at full deflection the scale
//! doubles or halves each second ([`OCTAVES_PER_S`]), clamped to `[min_scale, max_scale]` times
//! the layout's scale (a room layout's trees stand at its scale). A gesture runs from the first
//! tick the value is beyond the dead zone until it is back inside (or the selection changes, or a
//! handle is grabbed); Scaled is logged once, at its end, and the spatial index is marked dirty
//! then. A world without a `ScalePad` (every world before its first `scale_axis` event) does
//! nothing here.

use hecs::World;

use crate::components::{Controller, Scale, ScalePad, Transform, Tree};
use crate::events::Happening;
use crate::interact;
use crate::resources::Resources;

/// Octaves of scale per second at full deflection: +1 doubles the scale each second.
pub const OCTAVES_PER_S: f32 = 1.0;

/// Runs the Scale pad system.
pub fn run(world: &mut World, res: &mut Resources) {
    let Some(pad_entity) = res.singles.entity::<Controller>() else { return };
    let Ok(pad) = world.query_one_mut::<&ScalePad>(pad_entity).map(|p| *p) else { return };
    let value = interact::touchpad_axis(pad.value, res.config.touchpad_dead_zone);
    let active = value != 0.0 && res.interaction.handle_drag.is_none();
    if !active && pad.gesture.is_none() {
        return;
    }
    let selected = interact::selected_tree(world, &res.singles);
    let mut gesture = pad.gesture;
    if let Some((tree, start)) = gesture
        && (!active || selected != Some(tree))
    {
        finish(world, res, tree, start);
        gesture = None;
    }
    if active
        && let Some(e) = selected.and_then(interact::entity)
        && let Some(lowest) =
            world.get::<&Tree>(e).ok().and_then(|t| res.catalogue.get(t.model)).map(|m| m.lowest_point())
        && let Ok((t, s)) = world.query_one_mut::<(&mut Transform, &mut Scale)>(e)
    {
        let (min, max) = res.config.scale_bounds(crate::task::layout_scale(res.task.as_ref()));
        gesture.get_or_insert((e.to_bits().get(), s.0));
        let new = interact::pad_scale(s.0, value, OCTAVES_PER_S, res.dt, min, max);
        t.translation.y = interact::rescaled_origin_y(t.translation.y, lowest, s.0, new);
        s.0 = new;
    }
    if let Ok(p) = world.query_one_mut::<&mut ScalePad>(pad_entity) {
        p.gesture = gesture;
    }
}

/// Ends a gesture: where the scale changed, logs it and marks the spatial index dirty (as the
/// touchpad does only for a gesture that moved or turned its tree).
fn finish(world: &World, res: &mut Resources, tree: u64, start: f32) {
    let Some(scale) = interact::entity(tree).and_then(|e| world.get::<&Scale>(e).ok().map(|s| s.0)) else { return };
    if scale != start {
        res.log.push(res.tick, Happening::Scaled { tree, scale });
        res.spatial.mark_trees_dirty();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_deflection_doubles_in_a_second_of_ticks_and_stays_within_the_bounds() {
        let dt = 1.0 / 60.0;
        let mut s = 1.0_f32;
        for _ in 0..60 {
            s = interact::pad_scale(s, 1.0, OCTAVES_PER_S, dt, 0.25, 4.0);
        }
        assert!((s - 2.0).abs() < 1e-4, "{s}");
        for _ in 0..600 {
            s = interact::pad_scale(s, -1.0, OCTAVES_PER_S, dt, 0.25, 4.0);
        }
        assert_eq!(s, 0.25);
        // A room layout's bounds (scale 0.06): the tree never jumps to the full-size minimum.
        assert_eq!(interact::pad_scale(0.06, 0.5, OCTAVES_PER_S, dt, 0.015, 0.24), 0.06 * libm::exp2f(0.5 * dt));
    }
}
