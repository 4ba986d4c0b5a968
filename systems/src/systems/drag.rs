//! Drag system: a grabbed tree follows the controller ray; the anchor ball shows the plane
//! below it; releasing the Trigger snaps the tree onto that plane when the ball is white.
//!
//! Reads: `Resources::interaction.drag`, `Resources::edges` (Trigger going up), `Water`,
//! `Resources::config` (`snap_threshold`), `Resources::catalogue`, `Resources::spatial`
//! (planes), `Controller` (ray, buttons), `Tree`, `Scale`.
//! Writes: `Transform`, `Grounded`, `AnchorBall`, `Resources::interaction` (the drag: moved
//! flag, end on release), `Resources::spatial` (marked dirty on release),
//! `Resources::log` (snap_armed, snap_disarmed, snapped, released_green, moved).
//!
//! While the Trigger is held the tree's origin is kept at the point on the ray at the grab
//! distance plus the offset taken at the grab. The tree moves only once that target is more
//! than 0.1 mm from where it stands; from then on the drag counts as a move and the tree is not
//! grounded. A press and release with the ray still is a click: it selects (select system) and
//! changes nothing else.
//!
//! Every tick of a drag, the plane under the tree is found by casting straight down on the
//! tree's axis from `snap_threshold` above its lowest point (`origin.y + lowest_point × scale`,
//! from the catalogue). The anchor ball sits at that plane point; its `distance` is the lowest
//! point's height minus the plane's height; it is white (`armed`) exactly when
//! `|distance| < snap_threshold` (see `interact::is_armed`) and green otherwise. Without a plane
//! under the tree (a hole, or off every edge), or when the plane found lies under water (a
//! pond's bed, `water::dry_ground`), the ball is hidden and not armed. Once the drag
//! has moved the tree, SnapArmed and SnapDisarmed are logged whenever `armed` changes.
//!
//! On release after a move: if armed, the origin is set so that the lowest point lies exactly
//! on the plane point below, the tree is grounded and Snapped is logged; otherwise it stays where
//! it is, ungrounded, and ReleasedGreen is logged. Then Moved is logged, the ball hides and the
//! spatial index is marked dirty (once per drag, not every tick).

use hecs::World;

use crate::components::{AnchorBall, Controller, Grounded, Scale, Transform, Tree};
use crate::events::Happening;
use crate::interact;
use crate::resources::Resources;
use crate::single;

/// How far the drag target must be from the tree's origin before the tree moves, metres.
pub const MOVE_EPSILON: f32 = 1.0e-4;

fn hide_ball(world: &mut World, singles: &single::Singles) {
    single::for_each_mut::<AnchorBall>(world, singles, |b| {
        if b.visible || b.armed {
            *b = AnchorBall::default();
        }
    });
}

/// Runs the drag system.
pub fn run(world: &mut World, res: &mut Resources) {
    let Some(mut drag) = res.interaction.drag else {
        hide_ball(world, &res.singles);
        return;
    };
    let Some(c) = single::get::<Controller>(world, &res.singles) else { return };
    let found = interact::entity(drag.tree).and_then(|e| {
        let model = world.get::<&Tree>(e).ok()?.model;
        Some((e, res.catalogue.get(model)?.lowest_point()))
    });
    let Some((e, lowest)) = found else {
        res.interaction.drag = None;
        hide_ball(world, &res.singles);
        return;
    };
    let tick = res.tick;
    let threshold = res.config.snap_threshold;
    let released = res.edges.up.trigger || !c.buttons.trigger;

    let water = single::water(world, &res.singles);
    let Ok((t, g, s)) = world.query_one_mut::<(&mut Transform, &mut Grounded, &Scale)>(e) else { return };
    let target = c.ray_origin() + c.ray_dir() * drag.grab_distance + drag.offset;
    if drag.moved || target.distance(t.translation) > MOVE_EPSILON {
        t.translation = target;
        g.0 = false;
        drag.moved = true;
    }
    let ground =
        crate::water::dry_ground(&water, interact::ground_under(&res.spatial, t.translation, lowest, s.0, threshold));
    let ball = match ground {
        Some(h) => {
            let distance = interact::lowest_point_y(t.translation.y, lowest, s.0) - h.point.y;
            AnchorBall { visible: true, position: h.point, distance, armed: interact::is_armed(distance, threshold) }
        }
        None => AnchorBall::default(),
    };

    if released && drag.moved {
        match (ball.armed, ground) {
            (true, Some(h)) => {
                t.translation.y = interact::snapped_origin_y(h.point.y, lowest, s.0);
                g.0 = true;
                res.log.push(tick, Happening::Snapped { tree: drag.tree, position: t.translation });
            }
            _ => {
                g.0 = false;
                res.log.push(tick, Happening::ReleasedGreen { tree: drag.tree });
            }
        }
    }
    let position = t.translation;

    let mut was_armed = false;
    single::for_each_mut::<AnchorBall>(world, &res.singles, |b| {
        was_armed = b.armed;
        *b = if released { AnchorBall::default() } else { ball };
    });
    if drag.moved && !released && ball.armed != was_armed {
        let what = if ball.armed {
            Happening::SnapArmed { tree: drag.tree }
        } else {
            Happening::SnapDisarmed { tree: drag.tree }
        };
        res.log.push(tick, what);
    }
    if released {
        if drag.moved {
            res.log.push(tick, Happening::Moved { tree: drag.tree, position });
            res.spatial.mark_trees_dirty();
        }
        res.interaction.drag = None;
    } else {
        res.interaction.drag = Some(drag);
    }
}
