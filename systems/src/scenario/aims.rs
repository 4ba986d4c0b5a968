//! What a button step after an aim meets, checked before the press counts (as a browser test
//! checks that an element can take a click before it clicks).
//!
//! Reads: the [`HitMarker`] (what the ray met in the tick the button went down: what the
//! interaction systems acted on), the controller's ray, the spatial index (which tree holds a
//! point, which plane lies under it), the catalogue, the task's tolerance and the script's
//! [`Names`]. Writes nothing: the checks observe, so a scenario that passes them runs the very
//! same ticks as before.
//!
//! When an aim is taken ([`Aimed::new`], after `PointAt` or at the end of a `Sweep`), what it
//! names is decided from the world at that moment ([`Intent`]): a tree (a `Tree(…)` aim, or a
//! point inside a tree's pick shape), a ground point (a task target, or a point within
//! [`ON_GROUND`] of a plane), or a point in the air. A Trigger or Bumper going down then fails
//! the step, naming what the ray met and where, when
//! - a ground aim's ray meets anything but a plane at the point (a tree in front, another
//!   plane, water, a handle, nothing);
//! - a tree aim's ray does not meet that tree;
//! - an aim in the air meets something before the point;
//! - the ray meets nothing, unless the scenario says it means to press on nothing
//!   (`press_on_nothing: true`, or a `PressOnNothing(…)` step, which fails when the ray meets
//!   something).

use glam::Vec3;

use crate::components::{Controller, HitMarker, HitTarget, Plane};
use crate::script::Script;
use crate::sim::Sim;
use crate::targets::{ground_distance, Aim, Names};

use super::Btn;
use super::failed::StepFailed;

/// What the runner carries from step to step: the last aim, for the button steps after it.
#[derive(Clone, Debug, Default)]
pub struct RunState {
    /// The aim of the last `PointAt` or `Sweep` (cleared by a `Controller` step).
    pub aimed: Option<Aimed>,
    /// The scenario's `press_on_nothing`.
    pub press_on_nothing: bool,
}

/// Whether a button acts on what the ray meets (plants, selects, grabs, removes).
fn aimed_button(b: Btn) -> bool {
    matches!(b, Btn::Trigger | Btn::Bumper)
}

/// Puts a button down and checks, in the tick it went down, what the ray met against the last
/// aim.
pub fn hold_checked(s: &mut Script, state: &RunState, b: Btn) -> Result<(), StepFailed> {
    s.hold(b.into());
    match &state.aimed {
        Some(aimed) if aimed_button(b) => check(s.sim(), s.names(), aimed, state.press_on_nothing),
        _ => Ok(()),
    }
}

/// How near a plane an aimed point lies to count as a point on the ground, metres.
pub const ON_GROUND: f32 = 0.1;

/// How near a ground point, along the ground, its ray must meet the plane under it when no task
/// tolerance applies, metres: the study tasks' tolerance. (The ground is not quite flat, so a
/// ray aimed at a point at height 0 meets it a little before or beyond.)
pub const GROUND_TOLERANCE: f32 = 0.5;

/// How much nearer than the aimed point a hit must be to lie "before" it, metres.
const BEFORE: f32 = 0.05;

/// What an aim names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Intent {
    /// A point on the ground: the ray must meet the plane under it within `within` metres of it
    /// (along the ground).
    Ground {
        /// The point.
        point: Vec3,
        /// How far from it, metres.
        within: f32,
        /// The plane under it, by entity id bits (`None` over a hole).
        plane: Option<u64>,
    },
    /// A tree, by entity id bits: the ray must meet it.
    Tree(u64),
    /// A point in the air: the ray must meet nothing before it.
    Air(Vec3),
}

/// An aim as the runner keeps it until the next button step.
#[derive(Clone, Debug, PartialEq)]
pub struct Aimed {
    /// The aim as the file writes it, e.g. `Target(6)`.
    pub label: String,
    /// The point aimed at.
    pub point: Vec3,
    /// What it names.
    pub intent: Intent,
}

impl Aimed {
    /// What `aim` (now pointing at `point`) names in the world as it is.
    pub fn new(sim: &Sim, names: &Names, aim: &Aim, point: Vec3) -> Aimed {
        let intent = match aim {
            Aim::Tree { tree, .. } => match names.tree(sim, tree) {
                Ok(id) => Intent::Tree(id),
                Err(_) => classify(sim, point),
            },
            Aim::Target(_) => Intent::Ground { point, within: sim.res.task.as_ref().map_or(GROUND_TOLERANCE, |t| t.def.tolerance), plane: plane_under(sim, point) },
            Aim::Point(..) | Aim::Mark { .. } => classify(sim, point),
        };
        Aimed { label: aim.text(), point, intent }
    }
}

/// A point inside a tree's pick shape names that tree; within [`ON_GROUND`] of a plane, the
/// ground; otherwise the air.
fn classify(sim: &Sim, point: Vec3) -> Intent {
    let spatial = &sim.res.spatial;
    if let Some(inside) = spatial.cast_trees(point, Vec3::Y, 0.0, None).filter(|h| h.distance <= 0.0) {
        return Intent::Tree(inside.entity.to_bits().get());
    }
    match spatial.ground_below(point, ON_GROUND) {
        Some(g) if g.distance <= 2.0 * ON_GROUND => Intent::Ground { point, within: GROUND_TOLERANCE, plane: Some(g.entity.to_bits().get()) },
        _ => Intent::Air(point),
    }
}

/// The plane under a point (from 1 m above it), by entity id bits.
fn plane_under(sim: &Sim, point: Vec3) -> Option<u64> {
    sim.res.spatial.ground_below(point, 1.0).map(|g| g.entity.to_bits().get())
}

/// "1st", "2nd", "3rd", "4th", …, "11th", "21st".
pub fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// A tree in words: its model and how the scenario knows it, e.g. `broadleaf-mesh (planted
/// 1st)`, `birch-mesh (named "oak")`, `conifer-mesh (the scene's, at (-11.0, -13.0))`.
pub fn tree_words(sim: &Sim, names: &Names, id: u64) -> String {
    let standing = sim.tree(id);
    // A tree the press itself removed is found in the log.
    let model = standing.map(|t| t.tree.model).or_else(|| {
        sim.res.log.entries.iter().rev().find_map(|e| match e.what {
            crate::events::Happening::Removed { tree, model } | crate::events::Happening::Planted { tree, model, .. } if tree == id => Some(model),
            _ => None,
        })
    });
    let model = model.and_then(|m| sim.res.catalogue.get(m)).map_or("a tree", |m| m.name.as_str());
    let mut who = match (names.name_of(id), names.planted(sim).iter().position(|p| *p == id), standing) {
        (Some(name), _, _) => format!("named \"{name}\""),
        (None, Some(i), _) => format!("planted {}", ordinal(i + 1)),
        (None, None, Some(t)) => format!("standing at ({:.1}, {:.1})", t.transform.translation.x, t.transform.translation.z),
        (None, None, None) => "one of the scene's".into(),
    };
    if standing.is_none() {
        who.push_str(", removed by this press");
    }
    format!("{model} ({who})")
}

/// What the ray met, in words (without the distance): a tree, a plane, water, a handle.
pub fn met_words(sim: &Sim, names: &Names, marker: &HitMarker) -> String {
    match marker.target {
        HitTarget::None => "nothing".into(),
        HitTarget::Tree(id) => tree_words(sim, names, id),
        HitTarget::Plane(id) => {
            let name = hecs::Entity::from_bits(id).and_then(|e| sim.world.get::<&Plane>(e).ok().map(|p| p.name.clone()));
            format!("the plane \"{}\"", name.unwrap_or_default())
        }
        HitTarget::Water(id) => {
            let name = hecs::Entity::from_bits(id).and_then(|e| sim.world.get::<&crate::water::Water>(e).ok().map(|w| w.name.clone()));
            format!("the water \"{}\"", name.unwrap_or_default())
        }
        HitTarget::Handle(h) => {
            let which = match h {
                crate::components::Handle::Corner(_) => "a corner handle (scale)",
                crate::components::Handle::Edge(_) => "an edge handle (rotate)",
            };
            match sim.selection().tree {
                Some(id) => format!("{which} of the selected {}", tree_words(sim, names, id)),
                None => which.to_string(),
            }
        }
    }
}

fn p3(p: Vec3) -> String {
    format!("({:.2}, {:.2}, {:.2})", p.x, p.y, p.z)
}

/// What the ray met and where, e.g. `broadleaf-mesh (planted 1st) at 7.9 m (point (-6.10,
/// 2.30, -1.60))`, or `nothing within 100 m`.
pub fn met(sim: &Sim, names: &Names, marker: &HitMarker) -> String {
    if !marker.visible {
        return format!("nothing within {} m", sim.res.config.max_ray_length);
    }
    format!("{} at {:.1} m (point {})", met_words(sim, names, marker), marker.distance, p3(marker.position))
}

fn ray_origin(sim: &Sim) -> Vec3 {
    sim.world.query::<&Controller>().iter().next().map_or(Vec3::ZERO, |c| c.ray_origin())
}

/// Checks what the ray met in the last tick against the aim. `nothing_ok`: the scenario means
/// to press on nothing (`press_on_nothing: true`), so a ray that meets nothing passes.
pub fn check(sim: &Sim, names: &Names, aimed: &Aimed, nothing_ok: bool) -> Result<(), StepFailed> {
    let m = sim.hit_marker();
    if !m.visible && nothing_ok {
        return Ok(());
    }
    let d = ray_origin(sim).distance(aimed.point);
    let before = m.visible && m.distance < d - BEFORE;
    let passes = match aimed.intent {
        Intent::Ground { point, within, plane } => {
            let on_plane = match m.target {
                HitTarget::Plane(p) => plane.is_none_or(|q| p == q),
                _ => false,
            };
            on_plane && ground_distance(m.position, point) <= within
        }
        Intent::Tree(id) => m.target == HitTarget::Tree(id),
        Intent::Air(_) => m.visible && !before,
    };
    if passes {
        return Ok(());
    }
    let aimed_at = match aimed.intent {
        Intent::Tree(id) => format!("{} aimed at {}", tree_words(sim, names, id), aimed.label),
        _ => aimed.label.clone(),
    };
    Err(StepFailed::Missed { met: met(sim, names, &m), before, aimed: aimed_at, distance: d, met_nothing: !m.visible })
}

/// Checks that the ray met nothing in the last tick (a `PressOnNothing` step).
pub fn check_nothing(sim: &Sim, names: &Names) -> Result<(), StepFailed> {
    let m = sim.hit_marker();
    if m.visible {
        Err(StepFailed::NotNothing(met(sim, names, &m)))
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::ordinal;

    #[test]
    fn ordinals_read_as_english() {
        let words: Vec<String> = [1, 2, 3, 4, 11, 12, 13, 21, 22, 101, 111].into_iter().map(ordinal).collect();
        assert_eq!(words, ["1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "22nd", "101st", "111th"]);
    }
}
