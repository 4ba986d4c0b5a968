//! What-if runs with a baseline, and sweeps of one parameter.
//!
//! Two kinds, named in every output:
//! - **replayed hands** (`grove study --set NAME=VALUE`): the recorded input events are
//!   re-simulated under the new setting; what the same movements would have done.
//! - **re-simulated participants** (`grove synth --set NAME=VALUE --out DIR`, then
//!   `grove study --replays DIR --baseline replays/study`): the synthetic participants act again,
//!   closed-loop, under the new setting.
//!
//! Every what-if is compared with its baseline trial by trial (matched on participant and
//! task) and per mode; only trials whose task completed in both runs enter a difference.

use std::collections::BTreeMap;

use grove_systems::resources::{Override, Param};
use serde::Serialize;

use super::Trial;
use super::report::{Summary, summarize, usable_time};
use super::stats::{PairedStats, paired};

/// The name of the replayed-hands kind.
pub const REPLAYED_HANDS: &str = "replayed hands";
/// The name of the re-simulated-participants kind.
pub const RESIMULATED_PARTICIPANTS: &str = "re-simulated participants";

/// What each kind means, for the outputs.
pub fn kind_meaning(kind: &str) -> &'static str {
    if kind == REPLAYED_HANDS {
        "the recorded input events re-simulated under the new setting: what the same movements would have done"
    } else {
        "the synthetic participants acted again, closed-loop, under the new setting (grove synth --set)"
    }
}

/// One changed parameter.
#[derive(Clone, Debug, Serialize)]
pub struct ParamChange {
    /// The parameter's name, as `--set` takes it.
    pub name: String,
    /// Its default value.
    pub default_value: String,
    /// The value of the what-if.
    pub new_value: String,
}

/// The default value of a configuration parameter, as text (e.g. "0.3").
pub fn default_value(name: &str) -> String {
    let defaults = serde_json::to_value(grove_systems::resources::Config::default()).unwrap_or_default();
    match defaults.get(name) {
        Some(serde_json::Value::Number(n)) => n.as_f64().map_or_else(|| n.to_string(), |x| (x as f32).to_string()),
        Some(v) => v.to_string(),
        None => "?".into(),
    }
}

/// Builds the parameter list of a what-if from `name=value` overrides.
pub fn param_changes(overrides: &[Override]) -> Vec<ParamChange> {
    overrides
        .iter()
        .map(|o| ParamChange {
            name: o.name.to_string(),
            default_value: default_value(o.name),
            new_value: o.text.clone(),
        })
        .collect()
}

/// One trial of the what-if next to its baseline.
#[derive(Clone, Debug, Serialize)]
pub struct TrialComparison {
    /// Participant id.
    pub participant: String,
    /// Task id.
    pub task: String,
    /// Mode name.
    pub mode: String,
    /// Baseline task time, seconds (null when not completed there).
    pub baseline_time_s: Option<f64>,
    /// What-if task time, seconds (null when not completed there).
    pub what_if_time_s: Option<f64>,
    /// What-if − baseline, seconds, when both completed.
    pub difference_s: Option<f64>,
    /// The baseline trial's status.
    pub baseline_status: String,
    /// The what-if trial's status.
    pub what_if_status: String,
}

/// One mode of the what-if next to its baseline.
#[derive(Clone, Debug, Serialize)]
pub struct ModeComparison {
    /// Mean baseline task time over completed baseline trials, seconds.
    pub baseline_mean_s: Option<f64>,
    /// Mean what-if task time over completed what-if trials, seconds.
    pub what_if_mean_s: Option<f64>,
    /// Mean of the per-trial differences (what-if − baseline) over trials completed in both.
    pub difference_s: Option<f64>,
    /// Trials completed in both runs.
    pub pairs: usize,
    /// Trials of this mode without a difference (not completed in one of the runs).
    pub unpaired: usize,
    /// Paired statistics of what-if − baseline over those trials.
    pub paired: Option<PairedStats>,
}

/// A what-if run and its baseline (`what_if` in `summary.json`).
#[derive(Clone, Debug, Serialize)]
pub struct WhatIf {
    /// "replayed hands" or "re-simulated participants".
    pub kind: String,
    /// What the kind means.
    pub kind_meaning: String,
    /// The changed parameters with their default and new values.
    pub parameters: Vec<ParamChange>,
    /// Per mode: baseline, what-if and difference.
    pub modes: BTreeMap<String, ModeComparison>,
    /// Per trial: baseline, what-if and difference, in the order of the what-if trials.
    pub per_trial: Vec<TrialComparison>,
    /// The summary of the baseline run.
    pub baseline: Summary,
}

fn key(t: &Trial) -> (String, String) {
    (t.participant.clone(), t.task.as_ref().map_or_else(|| t.file.clone(), |k| k.id.clone()))
}

fn mean(xs: &[f64]) -> Option<f64> {
    (!xs.is_empty()).then(|| xs.iter().sum::<f64>() / xs.len() as f64)
}

impl WhatIf {
    /// Compares what-if trials with baseline trials of the same participant and task.
    pub fn compare(
        kind: &str,
        parameters: Vec<ParamChange>,
        baseline: &[Trial],
        what_if: &[Trial],
        baseline_wall: f64,
    ) -> WhatIf {
        let base: BTreeMap<(String, String), &Trial> = baseline.iter().map(|t| (key(t), t)).collect();
        let per_trial: Vec<TrialComparison> = what_if
            .iter()
            .map(|t| {
                let b = base.get(&key(t));
                let (bt, wt) = (b.and_then(|b| usable_time(b)), usable_time(t));
                TrialComparison {
                    participant: t.participant.clone(),
                    task: key(t).1,
                    mode: t.task.as_ref().map(|k| k.mode.clone()).unwrap_or_default(),
                    baseline_time_s: bt,
                    what_if_time_s: wt,
                    difference_s: bt.zip(wt).map(|(b, w)| w - b),
                    baseline_status: b.map_or_else(|| "missing".into(), |b| b.status.word().into()),
                    what_if_status: t.status.word().into(),
                }
            })
            .collect();
        let mut modes = BTreeMap::new();
        for mode in ["ray-casting", "manual"] {
            let rows: Vec<&TrialComparison> = per_trial.iter().filter(|c| c.mode == mode).collect();
            let base_times: Vec<f64> = baseline
                .iter()
                .filter(|t| t.task.as_ref().is_some_and(|k| k.mode == mode))
                .filter_map(usable_time)
                .collect();
            let what_times: Vec<f64> = rows.iter().filter_map(|c| c.what_if_time_s).collect();
            let diffs: Vec<f64> = rows.iter().filter_map(|c| c.difference_s).collect();
            modes.insert(
                mode.to_string(),
                ModeComparison {
                    baseline_mean_s: mean(&base_times),
                    what_if_mean_s: mean(&what_times),
                    difference_s: mean(&diffs),
                    pairs: diffs.len(),
                    unpaired: rows.len() - diffs.len(),
                    paired: paired(&diffs, "what-if − baseline", "s"),
                },
            );
        }
        WhatIf {
            kind: kind.to_string(),
            kind_meaning: kind_meaning(kind).to_string(),
            parameters,
            modes,
            per_trial,
            baseline: summarize(baseline, &[], baseline_wall),
        }
    }

    /// The comparison row of a what-if trial.
    pub fn comparison_for(&self, t: &Trial) -> Option<&TrialComparison> {
        let (p, task) = key(t);
        self.per_trial.iter().find(|c| c.participant == p && c.task == task)
    }

    /// "snap_threshold 0.3 (default) → 0.2", for tables and charts.
    pub fn parameters_text(&self) -> String {
        self.parameters
            .iter()
            .map(|p| format!("{} {} (default) → {}", p.name, p.default_value, p.new_value))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// One value of a sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepRow {
    /// The parameter's value.
    pub value: String,
    /// Whether it is the default value.
    pub is_default: bool,
    /// Per mode: baseline, what-if and difference at this value.
    pub modes: BTreeMap<String, ModeComparison>,
    /// Trials completed per mode at this value.
    pub completed: BTreeMap<String, usize>,
    /// Whether ray-casting was faster for every participant at this value (null when any
    /// comparison is missing).
    pub ray_casting_faster_for_all: Option<bool>,
    /// The participants without a ray-casting/manual comparison at this value.
    pub missing_comparisons: Vec<String>,
}

/// A sweep of one parameter (`sweep` in `summary.json`).
#[derive(Clone, Debug, Serialize)]
pub struct Sweep {
    /// Always "replayed hands": a sweep re-simulates the recorded input.
    pub kind: String,
    /// What the kind means.
    pub kind_meaning: String,
    /// The swept parameter.
    pub parameter: String,
    /// Its default value.
    pub default_value: String,
    /// Other parameters held at a changed value for every run of the sweep (not the baseline).
    pub fixed: Vec<ParamChange>,
    /// One row per value, in the order given.
    pub rows: Vec<SweepRow>,
    /// The summary of the baseline run (every parameter at its default).
    pub baseline: Summary,
}

impl Sweep {
    /// Builds the row of one value from its trials and the baseline's.
    pub fn row(value: &Override, baseline: &[Trial], trials: &[Trial]) -> SweepRow {
        let w = WhatIf::compare(REPLAYED_HANDS, Vec::new(), baseline, trials, 0.0);
        let s = summarize(trials, &[], 0.0);
        let is_default = Param::named(value.name).is_some_and(|p| p.default == value.value);
        SweepRow {
            value: value.text.clone(),
            is_default,
            completed: s.modes.iter().map(|(m, st)| (m.clone(), st.completed)).collect(),
            modes: w.modes,
            ray_casting_faster_for_all: s.ray_casting_faster_for_all,
            missing_comparisons: s.missing_comparisons,
        }
    }
}
