//! The study: re-simulating a folder of recordings, evaluating their tasks, and the reports.
//!
//! Nothing here trusts what a recording says about itself: every timing comes from
//! re-simulating its input events. This module knows nothing about rendering or windows.

pub mod chart;
pub mod participant;
pub mod report;
pub mod synth;


use std::path::{Path, PathBuf};
use std::time::Instant;

use grove_systems::replay::{replay_file, ReplayOptions};
use grove_systems::resources::Override;
use grove_systems::task::TaskReport;
use rayon::prelude::*;
use serde::Serialize;

/// How a trial's recording fared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TrialStatus {
    /// Every checkpoint matched.
    Verified,
    /// Re-run with changed parameters (`--set`), so checkpoints were not compared.
    WhatIf,
    /// A checkpoint differed.
    Diverged,
    /// The file could not be read or replayed.
    Failed,
}

impl TrialStatus {
    /// The word used in tables and CSV files.
    pub fn word(self) -> &'static str {
        match self {
            TrialStatus::Verified => "verified",
            TrialStatus::WhatIf => "what-if",
            TrialStatus::Diverged => "diverged",
            TrialStatus::Failed => "failed",
        }
    }
}

/// One recording, re-simulated and evaluated.
#[derive(Clone, Debug, Serialize)]
pub struct Trial {
    /// The recording's file name.
    pub file: String,
    /// Participant id from the header (or the file stem).
    pub participant: String,
    /// Whether the header marks the session as synthetic.
    pub synthetic: bool,
    /// The outcome of verification.
    pub status: TrialStatus,
    /// The error, for failed trials.
    pub error: Option<String>,
    /// Whether the file had a footer.
    pub complete: bool,
    /// Ticks re-simulated.
    pub ticks: u64,
    /// The task outcome, if the recording ran a task.
    pub task: Option<TaskReport>,
}

/// Every recording file (`*.jsonl`) in a folder, sorted by name.
pub fn recordings_in(dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    if !dir.exists() {
        anyhow::bail!("{}: no such folder", dir.display());
    }
    if !dir.is_dir() {
        anyhow::bail!("{}: is not a folder of recordings", dir.display());
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| anyhow::anyhow!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "jsonl"))
        .collect();
    files.sort();
    if files.is_empty() {
        anyhow::bail!("{}: no recordings (*.jsonl) in this folder", dir.display());
    }
    Ok(files)
}

/// Re-simulates and evaluates one recording. Never fails: a bad file becomes a failed trial.
pub fn evaluate(path: &Path, overrides: &[Override]) -> Trial {
    let file = path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
    let stem = path.file_stem().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
    let options = ReplayOptions { until: None, overrides: overrides.to_vec() };
    match replay_file(path, &options) {
        Err(e) => Trial { file, participant: stem, synthetic: false, status: TrialStatus::Failed, error: Some(e.to_string()), complete: false, ticks: 0, task: None },
        Ok(o) => {
            let sim = &o.sim;
            let status = if !o.verifying {
                TrialStatus::WhatIf
            } else if o.first_divergence.is_some() || o.checkpoints_checked == 0 {
                TrialStatus::Diverged
            } else {
                TrialStatus::Verified
            };
            Trial {
                file,
                participant: o.header.participant.clone().unwrap_or(stem),
                synthetic: o.header.synthetic,
                status,
                error: o.first_divergence.as_ref().map(|d| format!("diverged at tick {}", d.tick)),
                complete: o.complete,
                ticks: sim.res.tick,
                task: sim.res.task.as_ref().map(|t| TaskReport::new(t, sim.res.dt, sim.res.tick, &sim.res.catalogue)),
            }
        }
    }
}

/// Re-simulates every recording in parallel (one recording per thread; each simulation is
/// single-threaded, so results do not depend on the thread count). `progress` is called once
/// per finished recording.
pub fn run_all(files: &[PathBuf], overrides: &[Override], progress: &(dyn Fn() + Sync)) -> (Vec<Trial>, f64) {
    let start = Instant::now();
    let mut trials: Vec<Trial> = files
        .par_iter()
        .map(|f| {
            let t = evaluate(f, overrides);
            progress();
            t
        })
        .collect();
    trials.sort_by(|a, b| (a.participant.as_str(), a.file.as_str()).cmp(&(b.participant.as_str(), b.file.as_str())));
    (trials, start.elapsed().as_secs_f64())
}
