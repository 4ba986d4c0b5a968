//! Study reports: the terminal table, `trial_results.csv`, `trees.csv` and `summary.json`.

use std::collections::BTreeMap;
use std::path::Path;

use grove_systems::resources::Override;
use serde::Serialize;

use super::{Trial, TrialStatus};

/// Per-mode statistics of task times.
#[derive(Clone, Debug, Serialize)]
pub struct ModeStats {
    /// Number of trials with a task in this mode.
    pub trials: usize,
    /// Completed trials.
    pub completed: usize,
    /// Mean task time of completed trials, seconds.
    pub mean_time_s: f64,
    /// Sample standard deviation of the task time, seconds.
    pub sd_time_s: f64,
    /// Mean number of errors.
    pub mean_errors: f64,
}

/// One participant's two task times.
#[derive(Clone, Debug, Serialize)]
pub struct ParticipantTimes {
    /// Participant id.
    pub participant: String,
    /// Ray-casting task time, seconds, if completed.
    pub ray_casting_s: Option<f64>,
    /// Manual task time, seconds, if completed.
    pub manual_s: Option<f64>,
    /// Whether ray-casting was faster.
    pub ray_casting_faster: Option<bool>,
}

/// `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Number of trials (recordings).
    pub trials: usize,
    /// Trials by status.
    pub status: BTreeMap<String, usize>,
    /// Trials whose task completed.
    pub completed: usize,
    /// Distinct participants.
    pub participants: usize,
    /// The `--set` overrides of a what-if run (empty otherwise).
    pub overrides: BTreeMap<String, String>,
    /// Statistics by mode name.
    pub modes: BTreeMap<String, ModeStats>,
    /// Both task times per participant.
    pub per_participant: Vec<ParticipantTimes>,
    /// Whether ray-casting was faster than manual for every participant with both tasks completed.
    pub ray_casting_faster_for_all: bool,
    /// Wall-clock seconds for re-simulating and evaluating every recording.
    pub wall_seconds: f64,
}

fn mean_sd(xs: &[f64]) -> (f64, f64) {
    if xs.is_empty() {
        return (0.0, 0.0);
    }
    let m = xs.iter().sum::<f64>() / xs.len() as f64;
    let var = if xs.len() > 1 { xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (xs.len() - 1) as f64 } else { 0.0 };
    (m, var.sqrt())
}

/// Builds the summary of a set of trials.
pub fn summarize(trials: &[Trial], overrides: &[Override], wall_seconds: f64) -> Summary {
    let mut status = BTreeMap::new();
    for t in trials {
        *status.entry(t.status.word().to_string()).or_insert(0) += 1;
    }
    let mut modes: BTreeMap<String, ModeStats> = BTreeMap::new();
    for mode in ["ray-casting", "manual"] {
        let tasks: Vec<_> = trials.iter().filter_map(|t| t.task.as_ref()).filter(|t| t.mode == mode).collect();
        let times: Vec<f64> = tasks.iter().filter(|t| t.completed).map(|t| t.time_s).collect();
        let (mean, sd) = mean_sd(&times);
        let errors: Vec<f64> = tasks.iter().map(|t| t.errors as f64).collect();
        modes.insert(
            mode.to_string(),
            ModeStats { trials: tasks.len(), completed: times.len(), mean_time_s: mean, sd_time_s: sd, mean_errors: mean_sd(&errors).0 },
        );
    }
    let mut by_participant: BTreeMap<String, ParticipantTimes> = BTreeMap::new();
    for t in trials {
        let Some(task) = &t.task else { continue };
        let entry = by_participant.entry(t.participant.clone()).or_insert_with(|| ParticipantTimes {
            participant: t.participant.clone(),
            ray_casting_s: None,
            manual_s: None,
            ray_casting_faster: None,
        });
        let time = task.completed.then_some(task.time_s);
        match task.mode.as_str() {
            "ray-casting" => entry.ray_casting_s = time,
            "manual" => entry.manual_s = time,
            _ => {}
        }
    }
    let mut per_participant: Vec<ParticipantTimes> = by_participant.into_values().collect();
    for p in &mut per_participant {
        if let (Some(r), Some(m)) = (p.ray_casting_s, p.manual_s) {
            p.ray_casting_faster = Some(r < m);
        }
    }
    let compared: Vec<bool> = per_participant.iter().filter_map(|p| p.ray_casting_faster).collect();
    Summary {
        trials: trials.len(),
        status,
        completed: trials.iter().filter(|t| t.task.as_ref().is_some_and(|k| k.completed)).count(),
        participants: per_participant.len(),
        overrides: overrides.iter().map(|o| (o.name.to_string(), o.text.clone())).collect(),
        modes,
        ray_casting_faster_for_all: !compared.is_empty() && compared.iter().all(|x| *x),
        per_participant,
        wall_seconds,
    }
}

/// The terminal table: participant, task, mode, time_s, trees, errors, verified.
pub fn table(trials: &[Trial]) -> String {
    let mut out = format!("{:<12} {:<15} {:<12} {:>8} {:>6} {:>7}  {}\n", "participant", "task", "mode", "time_s", "trees", "errors", "verified");
    for t in trials {
        let (task, mode, time, trees, errors) = match &t.task {
            Some(k) => (
                k.id.clone(),
                k.mode.clone(),
                if k.completed { format!("{:.2}", k.time_s) } else { "-".into() },
                k.trees.len().to_string(),
                k.errors.to_string(),
            ),
            None => ("-".into(), "-".into(), "-".into(), "-".into(), "-".into()),
        };
        let status = match (&t.status, &t.error) {
            (TrialStatus::Failed, Some(e)) => format!("failed: {e}"),
            (s, _) => s.word().to_string(),
        };
        out.push_str(&format!("{:<12} {:<15} {:<12} {:>8} {:>6} {:>7}  {}\n", t.participant, task, mode, time, trees, errors, status));
    }
    out
}

/// Writes `trial_results.csv`: one row per participant × task, in the style of the Unity
/// Experiment Framework's trial results (`experiment, ppid, session_num, trial_num, block_num,
/// trial_num_in_block, start_time, end_time`, then this study's measures).
pub fn write_trial_results(path: &Path, trials: &[Trial]) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    w.write_record([
        "experiment", "ppid", "session_num", "trial_num", "block_num", "trial_num_in_block", "start_time", "end_time", "task", "mode", "completed", "time_s",
        "trees", "model_types", "errors", "removals", "off_target", "released_green", "menu_opens", "ray_path_m", "aiming_s", "menu_s", "manipulating_s",
        "status", "synthetic", "file",
    ])?;
    let mut trial_num: BTreeMap<&str, u32> = BTreeMap::new();
    for t in trials {
        let n = trial_num.entry(t.participant.as_str()).or_insert(0);
        *n += 1;
        let k = t.task.as_ref();
        let block = match k.map(|k| k.mode.as_str()) {
            Some("ray-casting") => "1",
            Some("manual") => "2",
            _ => "0",
        };
        let f = |x: f64| format!("{x:.4}");
        w.write_record([
            "grove-study".to_string(),
            t.participant.clone(),
            "1".into(),
            n.to_string(),
            block.into(),
            "1".into(),
            "0".into(),
            k.map_or("".into(), |k| f(k.time_s)),
            k.map_or("".into(), |k| k.id.clone()),
            k.map_or("".into(), |k| k.mode.clone()),
            k.map_or("".into(), |k| k.completed.to_string()),
            k.map_or("".into(), |k| f(k.time_s)),
            k.map_or("".into(), |k| k.trees.len().to_string()),
            k.map_or("".into(), |k| k.model_types.to_string()),
            k.map_or("".into(), |k| k.errors.to_string()),
            k.map_or("".into(), |k| k.error_kinds.removals.to_string()),
            k.map_or("".into(), |k| k.error_kinds.off_target.to_string()),
            k.map_or("".into(), |k| k.error_kinds.released_green.to_string()),
            k.map_or("".into(), |k| k.menu_opens.to_string()),
            k.map_or("".into(), |k| f(k.ray_path_m as f64)),
            k.map_or("".into(), |k| f(k.aiming_s)),
            k.map_or("".into(), |k| f(k.menu_s)),
            k.map_or("".into(), |k| f(k.manipulating_s)),
            t.status.word().into(),
            t.synthetic.to_string(),
            t.file.clone(),
        ])?;
    }
    w.flush()?;
    Ok(())
}

/// Writes `trees.csv`: one row per placed tree.
pub fn write_trees(path: &Path, trials: &[Trial]) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    w.write_record(["ppid", "task", "mode", "target", "model", "time_s", "x", "y", "z", "status"])?;
    for t in trials {
        let Some(k) = &t.task else { continue };
        for tree in &k.trees {
            w.write_record([
                t.participant.clone(),
                k.id.clone(),
                k.mode.clone(),
                tree.target.to_string(),
                tree.model.clone(),
                format!("{:.4}", tree.time_s),
                format!("{:.4}", tree.position[0]),
                format!("{:.4}", tree.position[1]),
                format!("{:.4}", tree.position[2]),
                t.status.word().into(),
            ])?;
        }
    }
    w.flush()?;
    Ok(())
}
