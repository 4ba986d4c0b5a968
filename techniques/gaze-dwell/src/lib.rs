//! Gaze-dwell: an example grove interaction technique, written against grove-systems' public
//! API only (`docs/techniques.md` walks through it).
//!
//! The head's gaze aims: the controller ray is laid along the head's forward direction, so the
//! hit marker follows where the user looks. Holding the gaze on one spot of the ground for
//! [`DWELL_S`] seconds plants the current model there, as a Trigger press would; Trigger still
//! plants at once. After a planting the gaze must leave the spot (by more than [`DWELL_RADIUS_M`])
//! before the next dwell can start, so one long look plants one tree.
//!
//! Everything else (the menu, removing with Bumper, the task clock) is ray-casting's: the
//! technique's [`Technique::base`] is [`Mode::RayCasting`].

use glam::Vec3;
use grove_systems::components::{Controller, Head, HitMarker, HitTarget};
use grove_systems::input::Button;
use grove_systems::mode::Mode;
use grove_systems::resources::Resources;
use grove_systems::technique::{Control, HashedComponent, Operator, Stage, Technique};
use hecs::World;
use serde::{Deserialize, Serialize};

/// The technique's name in files, menus and reports.
pub const NAME: &str = "gaze-dwell";
/// The technique's version; recordings name it.
pub const VERSION: u32 = 1;
/// How long the gaze must rest on one spot to plant, seconds.
pub const DWELL_S: f32 = 0.8;
/// How far the gaze point may wander and still count as the same spot, metres.
pub const DWELL_RADIUS_M: f32 = 0.15;

/// The dwell in progress: one entity has it while the technique is active.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Dwell {
    /// Where on the ground the gaze rests, metres.
    pub anchor: Vec3,
    /// How long it has rested there, seconds.
    pub held_s: f32,
    /// Whether this spot may still plant (false once it has, until the gaze moves away).
    pub armed: bool,
}

/// The registration: one call in the app's list of techniques.
pub fn technique() -> Technique {
    Technique {
        name: NAME,
        version: VERSION,
        about: "look at the ground and hold the gaze for 0.8 s (or pull Trigger) to plant",
        base: Mode::RayCasting,
        systems: vec![(Stage::Input, "gaze_aims", gaze_aims), (Stage::Ray, "dwell", dwell)],
        components: vec![HashedComponent::of::<Dwell>("Dwell")],
        controls: vec![
            Control {
                button: Button::Trigger,
                desktop: "left mouse button",
                action: "plant where the gaze rests, at once",
            },
            Control { button: Button::Bumper, desktop: "right mouse button", action: "remove the tree under the gaze" },
            Control { button: Button::Menu, desktop: "Tab or M", action: "open the model menu" },
        ],
        participant: vec![Operator::Mental, Operator::Menu, Operator::AimHead, Operator::Dwell(DWELL_S)],
    }
}

/// Stage `input`: the ray starts at the head and points where the head looks.
pub fn gaze_aims(world: &mut World, _res: &mut Resources) {
    let Some(head) = world.query::<&Head>().iter().next().map(|h| h.pose) else { return };
    for c in world.query_mut::<&mut Controller>() {
        c.pose = head;
    }
}

/// Stage `ray`, after the ray cast: a gaze resting on the ground for [`DWELL_S`] becomes a
/// Trigger press for the interaction stage, where ray-casting's planting system plants.
pub fn dwell(world: &mut World, res: &mut Resources) {
    let hit = world.query::<&HitMarker>().iter().next().copied().unwrap_or_default();
    let found = world.query_mut::<&mut Dwell>().into_iter().next().map(|d| *d);
    let mut d = match found {
        Some(d) => d,
        None => {
            // The first tick of the technique: its one entity, spawned through a command
            // buffer like every structural change inside a system.
            let mut cmd = hecs::CommandBuffer::new();
            cmd.spawn((Dwell { anchor: hit.position, held_s: 0.0, armed: true },));
            cmd.run_on(world);
            return;
        }
    };
    let on_ground = hit.visible && matches!(hit.target, HitTarget::Plane(_));
    if !on_ground {
        d = Dwell { anchor: hit.position, held_s: 0.0, armed: true };
    } else if hit.position.distance(d.anchor) > DWELL_RADIUS_M {
        d = Dwell { anchor: hit.position, held_s: 0.0, armed: true };
    } else {
        d.held_s += res.dt;
        if d.armed && d.held_s >= DWELL_S - 1e-4 && !res.edges.down.trigger {
            res.edges.down.trigger = true;
            d.armed = false;
        }
    }
    for x in world.query_mut::<&mut Dwell>() {
        *x = d;
    }
}
