//! The study: re-simulating a folder of recordings, evaluating their tasks, and the reports.
//!
//! Nothing here trusts what a recording says about itself: every timing comes from
//! re-simulating its input events. This module knows nothing about rendering or windows.

pub mod chart;
pub mod conditions;
pub mod csv_out;
pub mod error;
pub mod friedman;
pub use crate::protocol::latin;
pub mod participant;
pub mod questionnaire;
pub mod report;
pub mod shard;
pub mod stats;
pub mod synth;
pub mod synth_plugin;
pub mod table;
pub mod whatif;
pub mod write;

pub use error::{StudyError, SynthError};
pub use shard::ShardError;

use std::path::{Path, PathBuf};
use std::time::Instant;

use grove_systems::replay::{replay_file, ReplayOptions};
use grove_systems::resources::Override;
use grove_systems::task::TaskReport;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// How a trial's recording fared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TrialStatus {
    /// Every checkpoint matched.
    Verified,
    /// Valid, but the file has no checkpoint to compare (for example an event-only file).
    Unverified,
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
            TrialStatus::Unverified => "unverified",
            TrialStatus::WhatIf => "what-if",
            TrialStatus::Diverged => "diverged",
            TrialStatus::Failed => "failed",
        }
    }
}

/// One recording, re-simulated and evaluated.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Trial {
    /// The recording's file name.
    pub file: String,
    /// Participant id from the header (or the file stem).
    pub participant: String,
    /// Whether the header marks the session as synthetic.
    pub synthetic: bool,
    /// The header's session start (UTC, RFC 3339), if it has one.
    pub session_start: Option<String>,
    /// The header's block, if it has one.
    pub header_block: Option<u32>,
    /// The header's configuration overrides.
    pub config: grove_systems::resources::Overrides,
    /// Position of this recording in the participant's session (1-based), see [`assign_order`].
    pub trial_num: u32,
    /// The block: the header's, or else the position of the task's first trial.
    pub block_num: u32,
    /// Position within the block (1-based).
    pub trial_num_in_block: u32,
    /// Seconds from the participant's first session start (or, without one, from the start of
    /// this recording) to the task start.
    pub start_time_s: Option<f64>,
    /// `start_time_s` plus the task time.
    pub end_time_s: Option<f64>,
    /// Seconds from the start of the recording to the task start (its tick / ticks per second).
    pub task_start_s: Option<f64>,
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
    /// The input device the header names (a controller of unknown profile without one).
    #[serde(default = "grove_systems::replay::HeaderDevice::unknown")]
    pub device: grove_systems::replay::HeaderDevice,
}

/// Every recording file (`*.jsonl`) in a folder, sorted by name; a folder without any is refused.
pub fn recordings_in(dir: &Path) -> Result<Vec<PathBuf>, StudyError> {
    let files = list_recordings(dir)?;
    if files.is_empty() {
        return Err(StudyError::NoRecordings(dir.to_path_buf()));
    }
    Ok(files)
}

/// Every recording file (`*.jsonl`) in a folder, sorted by name, perhaps none (a shard's folder
/// may hold no participant).
pub fn list_recordings(dir: &Path) -> Result<Vec<PathBuf>, StudyError> {
    if !dir.exists() {
        return Err(StudyError::NoSuchFolder(dir.to_path_buf()));
    }
    if !dir.is_dir() {
        return Err(StudyError::NotAFolder(dir.to_path_buf()));
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|source| StudyError::Folder { path: dir.to_path_buf(), source })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "jsonl"))
        // A protocol's answers lie beside its recordings (docs/protocol.md).
        .filter(|p| !p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.ends_with(questionnaire::ANSWERS_SUFFIX)))
        .collect();
    files.sort();
    // A pipe, device or folder among them is bad input, refused before anything runs (reading
    // a pipe would block); a damaged recording, by contrast, becomes a failed trial.
    for f in &files {
        grove_systems::files::check(f, grove_systems::files::Kind::Recording).map_err(grove_systems::Error::from)?;
    }
    Ok(files)
}

/// Re-simulates and evaluates one recording. Never fails: a bad file becomes a failed trial.
pub fn evaluate(path: &Path, overrides: &[Override]) -> Trial {
    let file = path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
    let stem = path.file_stem().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
    let options = ReplayOptions { until: None, overrides: overrides.to_vec(), ..Default::default() };
    match replay_file(path, &options) {
        Err(e) => Trial {
            file,
            participant: stem,
            synthetic: false,
            session_start: None,
            header_block: None,
            config: Default::default(),
            trial_num: 0,
            block_num: 0,
            trial_num_in_block: 0,
            start_time_s: None,
            end_time_s: None,
            task_start_s: None,
            status: TrialStatus::Failed,
            error: Some(e.to_string()),
            complete: false,
            ticks: 0,
            task: None,
            device: grove_systems::replay::HeaderDevice::unknown(),
        },
        Ok(o) => trial_from_outcome(file, stem, &o),
    }
}

/// The trial a replay's outcome makes: `file` the recording's file name, `stem` the participant
/// when the header names none. Its place in the session is set by [`assign_order`].
pub fn trial_from_outcome(file: String, stem: String, o: &grove_systems::replay::ReplayOutcome) -> Trial {
    let sim = &o.sim;
    let status = if !o.verifying {
        TrialStatus::WhatIf
    } else if o.first_divergence.is_some() {
        TrialStatus::Diverged
    } else if o.checkpoints_checked == 0 {
        TrialStatus::Unverified
    } else {
        TrialStatus::Verified
    };
    Trial {
        file,
        participant: o.header.participant.clone().unwrap_or(stem),
        synthetic: o.header.synthetic,
        session_start: o.header.session_start.clone(),
        header_block: o.header.block,
        config: o.header.config.clone(),
        trial_num: 0,
        block_num: 0,
        trial_num_in_block: 0,
        start_time_s: None,
        end_time_s: None,
        task_start_s: sim.task().map(|t| grove_systems::task::ticks_to_seconds(t.started_tick, sim.dt())),
        status,
        error: o.first_divergence.as_ref().map(|d| format!("diverged at tick {}", d.tick)),
        complete: o.complete,
        ticks: sim.tick(),
        task: sim.task().map(|t| technique_report(TaskReport::new(t, sim.dt(), sim.tick(), sim.catalogue()), sim)),
        device: o.header.device_or_unknown(),
    }
}

/// A task report whose mode is the technique that ran it: a plug-in's name in place of its base
/// mode, so that reports tell the conditions apart.
pub fn technique_report(mut report: TaskReport, sim: &grove_systems::Sim) -> TaskReport {
    report.moved_targets = sim.moved_targets();
    let t = sim.active_technique();
    if !t.is_builtin() {
        report.mode = t.name.to_string();
    }
    report
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
    assign_order(&mut trials);
    (trials, start.elapsed().as_secs_f64())
}

/// Seconds since the Unix epoch of an RFC 3339 time.
fn epoch_seconds(time: &str) -> Option<f64> {
    chrono::DateTime::parse_from_rfc3339(time).ok().map(|t| t.timestamp_millis() as f64 / 1000.0)
}

/// Orders each participant's trials as they were recorded and numbers them.
///
/// The order is by the header's `session_start`, then its `block`, then the file name; trials
/// are sorted by participant and that order. `block_num` is the header's block, or else the
/// position of the first trial of the same task; `trial_num_in_block` counts within a block.
/// `start_time_s` is measured from the participant's earliest `session_start` when every one of
/// their recordings has one, and otherwise from the start of each recording.
pub fn assign_order(trials: &mut [Trial]) {
    let key = |t: &Trial| (t.participant.clone(), t.session_start.as_deref().and_then(epoch_seconds).map(|s| (s * 1000.0) as i64), t.header_block, t.file.clone());
    // Recordings without a session start sort after those with one (None < Some, so flip it).
    trials.sort_by(|a, b| {
        let (ka, kb) = (key(a), key(b));
        (ka.0, ka.1.is_none(), ka.1, ka.2, ka.3).cmp(&(kb.0, kb.1.is_none(), kb.1, kb.2, kb.3))
    });
    let mut i = 0;
    while i < trials.len() {
        let mut j = i;
        while j < trials.len() && trials[j].participant == trials[i].participant {
            j += 1;
        }
        let group = &mut trials[i..j];
        let origin = if group.iter().all(|t| t.session_start.is_some()) {
            group.iter().filter_map(|t| t.session_start.as_deref().and_then(epoch_seconds)).reduce(f64::min)
        } else {
            None
        };
        let mut first_of_task: Vec<(String, u32)> = Vec::new();
        let mut in_block: std::collections::BTreeMap<u32, u32> = Default::default();
        for (n, t) in group.iter_mut().enumerate() {
            t.trial_num = n as u32 + 1;
            let task = t.task.as_ref().map_or_else(|| t.file.clone(), |k| k.id.clone());
            t.block_num = t.header_block.unwrap_or_else(|| match first_of_task.iter().find(|(id, _)| *id == task) {
                Some((_, b)) => *b,
                None => {
                    let b = first_of_task.len() as u32 + 1;
                    first_of_task.push((task.clone(), b));
                    b
                }
            });
            let c = in_block.entry(t.block_num).or_insert(0);
            *c += 1;
            t.trial_num_in_block = *c;
            if let Some(k) = &t.task {
                let offset = match (origin, t.session_start.as_deref().and_then(epoch_seconds)) {
                    (Some(o), Some(s)) => s - o,
                    _ => 0.0,
                };
                let start = offset + t.task_start_s.unwrap_or(0.0);
                t.start_time_s = Some(start);
                t.end_time_s = Some(start + k.time_s);
            }
        }
        i = j;
    }
}
