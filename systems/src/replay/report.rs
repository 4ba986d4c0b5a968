//! [`ReplayReport`]: what a verifying replay reports, field for field what `grove replay --json`
//! prints and what the WebAssembly module's replay returns (`web/sim`). Built here once from a
//! [`ReplayOutcome`]; the wall-clock figures are the caller's, since this crate reads no clock.

use std::collections::BTreeMap;

use serde::Serialize;

use super::{Divergence, ReplayOutcome};
use crate::hash::hex;
use crate::task::{ticks_to_seconds, TaskReport};

/// What a replay of one recording found.
#[derive(Clone, Debug, Serialize)]
pub struct ReplayReport {
    /// The file replayed, as the caller names it.
    pub file: String,
    /// Its format version.
    pub format_version: u32,
    /// Ticks simulated.
    pub ticks: u64,
    /// Simulated seconds.
    pub sim_seconds: f64,
    /// Wall-clock seconds the replay took (0 until the caller sets it, [`ReplayReport::timed`]).
    pub wall_seconds: f64,
    /// Simulated seconds per wall second (0 until the caller sets it).
    pub speedup: f64,
    /// Every checkpoint compared matched (and at least one was compared).
    pub verified: bool,
    /// "verified", "unverified" (no checkpoint compared), "incomplete" (no footer; verified to
    /// its last checkpoint) or "diverged", as `grove serve` says it ([`super::verdict::Verdict`]).
    pub status: &'static str,
    /// The file has its footer.
    pub complete: bool,
    /// Checkpoints compared, the footer's final hash included.
    pub checkpoints_checked: u64,
    /// The first divergence, if any.
    pub first_divergence: Option<Divergence>,
    /// Input events by kind.
    pub events: BTreeMap<String, u64>,
    /// The world hash at the end of the replay.
    pub final_hash: String,
    /// The participant id from the header.
    pub participant: Option<String>,
    /// Whether the header marks the session as synthetic.
    pub synthetic: bool,
    /// The input device the header names (`profile`, `target_ray_mode`, `mapping`); a
    /// controller of unknown profile for a recording without one.
    pub device: super::HeaderDevice,
    /// The task outcome, recomputed by the simulation, if the session ran a task.
    pub task: Option<TaskReport>,
}

impl ReplayReport {
    /// The report of a replay's outcome; `file` names the recording. The wall-clock figures are 0.
    pub fn new(file: String, outcome: &ReplayOutcome) -> ReplayReport {
        let sim = &outcome.sim;
        let ticks = sim.tick();
        let verified = outcome.verifying && outcome.first_divergence.is_none() && outcome.checkpoints_checked > 0;
        ReplayReport {
            file,
            format_version: outcome.header.format_version,
            ticks,
            sim_seconds: ticks_to_seconds(ticks, sim.dt()),
            wall_seconds: 0.0,
            speedup: 0.0,
            verified,
            status: super::verdict::Verdict::of(outcome.first_divergence.is_some(), outcome.complete, if outcome.verifying { outcome.checkpoints_checked } else { 0 }).as_str(),
            complete: outcome.complete,
            checkpoints_checked: outcome.checkpoints_checked,
            first_divergence: outcome.first_divergence.clone(),
            events: outcome.events.clone(),
            final_hash: hex(sim.hash().total),
            participant: outcome.header.participant.clone(),
            synthetic: outcome.header.synthetic,
            device: outcome.header.device_or_unknown(),
            task: sim.task_report(),
        }
    }

    /// The report with the replay's wall-clock time: `wall_seconds` and the speed-up it gives
    /// (infinite for a replay too quick to measure).
    pub fn timed(mut self, wall_seconds: f64) -> ReplayReport {
        self.wall_seconds = wall_seconds;
        self.speedup = if wall_seconds > 0.0 { self.sim_seconds / wall_seconds } else { f64::INFINITY };
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::InputEvent;
    use crate::replay::{record_events, replay_reader, Header, ReplayOptions};

    #[test]
    fn a_recorded_task_reports_verified_with_its_task_and_the_caller_s_time() {
        let scene = crate::scene::Scene::builtin("study").unwrap();
        let mut header = Header::new("study", 3, scene.dt);
        header.participant = Some("R01".into());
        let events = vec![crate::input::StampedEvent { tick: 0, event: InputEvent::StartTask { task: "ray-casting-7".into(), layout: None } }];
        let bytes = record_events(Vec::new(), &header, &events, 130, serde_json::json!({})).unwrap();
        let outcome = replay_reader(&bytes[..], "r.jsonl", None, &ReplayOptions::default()).unwrap();
        let report = ReplayReport::new("r.jsonl".into(), &outcome);
        assert_eq!((report.status, report.verified, report.complete), ("verified", true, true));
        assert_eq!(report.ticks, 130);
        assert_eq!(report.checkpoints_checked, 3, "ticks 60 and 120, and the footer");
        assert_eq!(report.participant.as_deref(), Some("R01"));
        assert_eq!(report.task.as_ref().map(|t| (t.id.as_str(), t.completed)), Some(("ray-casting-7", false)));
        assert_eq!((report.wall_seconds, report.speedup), (0.0, 0.0), "no clock read here");
        let timed = report.clone().timed(0.5);
        assert!((timed.speedup - 130.0 * scene.dt as f64 / 0.5).abs() < 1e-6, "{}", timed.speedup);
        assert!(report.timed(0.0).speedup.is_infinite());
    }
}
