//! A verifying replay of a recording handed over as bytes: the same reader, checks and
//! re-simulation as `grove replay`, and the same report ([`ReplayReport`], the fields of
//! `grove replay --json`), less the wall-clock figures, which JavaScript measures.

use std::collections::BTreeMap;

use grove_systems::replay::verdict::Verdict;
use grove_systems::replay::{decode_line, replay_reader, Divergence, Line, ReplayOptions};
use grove_systems::task::{ticks_to_seconds, TaskReport};
use serde::{Deserialize, Serialize};

use crate::error::Error;

/// What a replay is asked.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReplayArgs {
    /// The recording's name in messages (its path, as `grove replay` names it).
    #[serde(default)]
    pub file: String,
    /// The text of the scene file the header names, when it is not a built-in scene.
    pub scene_text: Option<String>,
    /// Stop at this tick.
    pub until: Option<u64>,
}

/// What `grove replay --json` prints, field for field; `wall_seconds` and `speedup` are 0 here
/// (the module reads no clock): the caller measures and fills them.
#[derive(Debug, Serialize)]
pub struct ReplayReport {
    /// The file replayed.
    pub file: String,
    /// Its format version.
    pub format_version: u32,
    /// Ticks simulated.
    pub ticks: u64,
    /// Simulated seconds.
    pub sim_seconds: f64,
    /// Wall-clock seconds the replay took (filled by the caller).
    pub wall_seconds: f64,
    /// Simulated seconds per wall second (filled by the caller).
    pub speedup: f64,
    /// Every checkpoint compared matched (and at least one was compared).
    pub verified: bool,
    /// "verified", "unverified" (no checkpoint compared), "incomplete" (no footer) or
    /// "diverged", as `grove replay --json` says it.
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
    /// The task outcome, recomputed by the simulation, if the session ran a task.
    pub task: Option<TaskReport>,
}

/// The report and the task's one-line result, as `grove replay` prints it.
#[derive(Debug, Serialize)]
pub struct Replayed {
    /// The report.
    pub report: ReplayReport,
    /// `grove replay`'s line about the task, if the session ran one.
    pub task_line: Option<String>,
}

/// Replays `recording` and verifies its checkpoints.
pub fn replay(args: &ReplayArgs, recording: &[u8]) -> Result<Replayed, Error> {
    crate::install_techniques();
    let mut options = ReplayOptions { until: args.until, ..Default::default() };
    if let Some(text) = &args.scene_text {
        // Named as the header names it (a header that does not read is refused by the reader
        // below, with its line number).
        let first = recording.split(|b| *b == b'\n').next().unwrap_or_default();
        let name = match std::str::from_utf8(first).ok().map(decode_line) {
            Some(Ok(Line::Header(h))) => h.scene,
            _ => String::new(),
        };
        if !name.is_empty() {
            options.scene = Some(crate::options::scene(&name, Some(text))?);
        }
    }
    let outcome = replay_reader(recording, &args.file, None, &options)?;
    let snapshot = outcome.sim.snapshot();
    let verified = outcome.verifying && outcome.first_divergence.is_none() && outcome.checkpoints_checked > 0;
    let task = outcome.sim.task_report();
    let report = ReplayReport {
        file: args.file.clone(),
        format_version: outcome.header.format_version,
        ticks: snapshot.tick,
        sim_seconds: ticks_to_seconds(snapshot.tick, snapshot.dt),
        wall_seconds: 0.0,
        speedup: 0.0,
        verified,
        status: Verdict::of(outcome.first_divergence.is_some(), outcome.complete, if outcome.verifying { outcome.checkpoints_checked } else { 0 }).as_str(),
        complete: outcome.complete,
        checkpoints_checked: outcome.checkpoints_checked,
        first_divergence: outcome.first_divergence.clone(),
        events: outcome.events.clone(),
        final_hash: snapshot.hash,
        participant: outcome.header.participant.clone(),
        synthetic: outcome.header.synthetic,
        task: task.clone(),
    };
    Ok(Replayed { task_line: task.map(|t| t.result_line()), report })
}
