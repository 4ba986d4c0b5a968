//! A recording re-simulated once more for the HTML report, keeping what the study's numbers do
//! not: where the controller's ray hit, the path of every tree moved from grab to release, the
//! interaction log and the button presses; at the moments a filmstrip shows (the task's start,
//! each planting and snap, its end, and any tick asked for) it hands the world to a callback.
//!
//! The re-simulation steps exactly as the verifying replay does (the events of tick T applied
//! with the step from T), so it sees the worlds the study measured.

use std::collections::BTreeMap;
use std::path::Path;

use glam::Vec2;
use grove_systems::Sim;
use grove_systems::bank::Banks;
use grove_systems::events::{Happening, LogEntry};
use grove_systems::input::InputEvent;
use grove_systems::replay::Player;
use grove_systems::resources::Override;

use super::HtmlError;

/// The edge of a heatmap cell, metres.
pub const CELL_M: f32 = 0.5;

/// A point of a moved tree's path is kept when it is this far from the previous one, metres.
const PATH_STEP_M: f32 = 0.05;

/// A button going down.
#[derive(Clone, Debug)]
pub struct Press {
    /// The tick of the event.
    pub tick: u64,
    /// The button, as the recording names it (`trigger`, `bumper`, …).
    pub button: String,
}

/// One tree moved from grab to release (a drag, or a touchpad gesture).
#[derive(Clone, Debug)]
pub struct TreePath {
    /// The tree, by entity id bits.
    pub tree: u64,
    /// The first and last tick of the move.
    pub ticks: (u64, u64),
    /// Its origin's (X, Z) along the way, metres.
    pub points: Vec<Vec2>,
}

/// A moment the filmstrip shows: the world at `tick`, after the step that led to it.
#[derive(Clone, Debug)]
pub struct Moment {
    /// The tick.
    pub tick: u64,
    /// What happened, in words ("task started", "planted", …).
    pub label: String,
}

/// What one re-simulation kept.
#[derive(Clone, Debug, Default)]
pub struct Trace {
    /// Ticks the ray's hit point spent in each cell (X and Z divided by [`CELL_M`], floored),
    /// until the task ended (all ticks when the recording runs no task).
    pub hits: BTreeMap<(i32, i32), u32>,
    /// Every tree moved, in order.
    pub paths: Vec<TreePath>,
    /// The interaction log at the end.
    pub log: Vec<LogEntry>,
    /// Every button press.
    pub presses: Vec<Press>,
    /// The moments handed to the callback.
    pub moments: Vec<Moment>,
}

/// Whether a log entry is a moment the filmstrip shows, and its words.
fn moment_label(what: &Happening) -> Option<&'static str> {
    match what {
        Happening::TaskStarted { .. } => Some("task started"),
        Happening::Planted { .. } => Some("planted"),
        Happening::Snapped { .. } => Some("snapped"),
        Happening::TaskCompleted => Some("task completed"),
        Happening::TaskEnded => Some("task ended"),
        _ => None,
    }
}

fn tree_xz(sim: &Sim, tree: u64) -> Option<Vec2> {
    sim.tree(tree).map(|t| Vec2::new(t.transform.translation.x, t.transform.translation.z))
}

/// Re-simulates `path` to `end_tick` under `overrides`, calling `shoot` with the world at each
/// moment (the ticks in `extra` with their words included; at most one call per tick).
pub fn trace(
    path: &Path,
    overrides: &[Override],
    banks: &Banks,
    end_tick: u64,
    extra: &[Moment],
    shoot: &mut dyn FnMut(&Sim, &Moment) -> Result<(), HtmlError>,
) -> Result<Trace, HtmlError> {
    let mut player = Player::open(path, overrides, banks)?;
    let mut out = Trace::default();
    let mut moving: Option<TreePath> = None;
    let mut take = |sim: &Sim, labels: Vec<String>, out: &mut Trace| -> Result<(), HtmlError> {
        if labels.is_empty() {
            return Ok(());
        }
        let m = Moment { tick: sim.tick(), label: labels.join(", ") };
        shoot(sim, &m)?;
        out.moments.push(m);
        Ok(())
    };
    let at_start: Vec<String> = extra.iter().filter(|m| m.tick == 0).map(|m| m.label.clone()).collect();
    take(player.sim(), at_start, &mut out)?;
    while player.sim().tick() < end_tick {
        let logged = player.sim().log().entries.len();
        // The events of this tick are applied with its step, as the verifying replay does.
        for e in player.step() {
            if let InputEvent::ButtonDown { button } = &e.event {
                let name = serde_json::to_value(button)
                    .ok()
                    .and_then(|v| v.as_str().map(str::to_string))
                    .unwrap_or_else(|| format!("{button:?}"));
                out.presses.push(Press { tick: e.tick, button: name });
            }
        }
        let sim = player.sim();

        // The ray, until the task is over.
        if sim.task().is_none_or(|t| !t.is_over())
            && let Some(hit) = Some(sim.hit_marker()).filter(|h| h.visible)
        {
            let cell = ((hit.position.x / CELL_M).floor() as i32, (hit.position.z / CELL_M).floor() as i32);
            *out.hits.entry(cell).or_insert(0) += 1;
        }
        // The tree being moved, from grab to release.
        let i = sim.interaction();
        let now = i.drag.map(|d| d.tree).or(i.touchpad.map(|g| g.tree));
        if moving.as_ref().is_some_and(|p| Some(p.tree) != now)
            && let Some(done) = moving.take()
            && done.points.len() > 1
        {
            out.paths.push(done);
        }
        if let Some(tree) = now
            && let Some(p) = tree_xz(sim, tree)
        {
            let m =
                moving.get_or_insert_with(|| TreePath { tree, ticks: (sim.tick(), sim.tick()), points: Vec::new() });
            m.ticks.1 = sim.tick();
            if m.points.last().is_none_or(|q| q.distance(p) >= PATH_STEP_M) {
                m.points.push(p);
            }
        }
        // The moments.
        let mut labels: Vec<String> = Vec::new();
        for e in &sim.log().entries[logged..] {
            if let Some(l) = moment_label(&e.what)
                && !labels.iter().any(|x| x == l)
            {
                labels.push(l.to_string());
            }
        }
        labels.extend(extra.iter().filter(|m| m.tick == sim.tick() && m.tick > 0).map(|m| m.label.clone()));
        take(sim, labels, &mut out)?;
    }
    if let Some(done) = moving.take().filter(|p| p.points.len() > 1) {
        out.paths.push(done);
    }
    out.log = player.sim().log().entries.clone();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_filmstrip_moments_are_the_task_marks_plantings_and_snaps() {
        assert_eq!(moment_label(&Happening::TaskStarted { task: "t".into() }), Some("task started"));
        assert_eq!(moment_label(&Happening::Snapped { tree: 1, position: glam::Vec3::ZERO }), Some("snapped"));
        assert_eq!(moment_label(&Happening::MenuOpened), None);
        assert_eq!(moment_label(&Happening::Deselected), None);
    }
}
