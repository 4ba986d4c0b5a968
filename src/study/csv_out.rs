//! The study's CSV files: `trial_results.csv` (one row per recording, in the style of the Unity
//! Experiment Framework's trial results), `trees.csv` (one row per tree, in planting order) and
//! `sweep.csv` (one row per swept value). `docs/reports.md` defines every column.

use std::path::Path;

use super::report::usable_time;
use super::whatif::{Sweep, WhatIf};
use super::{StudyError, Trial};

/// The columns of `trial_results.csv`.
pub const TRIAL_COLUMNS: &[&str] = &[
    "experiment", "ppid", "session_num", "trial_num", "block_num", "trial_num_in_block", "start_time", "end_time", "session_start", "task", "mode", "completed",
    "time_s", "trees", "model_types", "errors", "removals", "off_target", "released_green", "menu_opens", "ray_path_m", "aiming_s", "menu_s", "manipulating_s",
    "status", "synthetic", "file", "what_if_kind", "parameter", "default_value", "new_value", "baseline_time_s", "difference_s", "layout",
    "device", "target_ray_mode", "input_profile",
];

/// The columns of `trees.csv`.
pub const TREE_COLUMNS: &[&str] =
    &["ppid", "trial_num", "task", "mode", "order", "target", "model", "tick", "time_since_start_s", "time_since_previous_s", "x", "y", "z", "status", "synthetic"];

fn f(x: f64) -> String {
    format!("{x:.4}")
}

fn of(x: Option<f64>) -> String {
    x.map(f).unwrap_or_default()
}

/// Runs `write` on a CSV writer of `path` (every cell written by [`crate::csv_cells`]'s rule);
/// errors name the file.
pub(crate) fn with_writer(path: &Path, write: impl FnOnce(&mut crate::csv_cells::Writer<std::fs::File>) -> csv::Result<()>) -> Result<(), StudyError> {
    let csv = |source| StudyError::Csv { path: path.to_path_buf(), source };
    let mut w = crate::csv_cells::Writer::from_path(path).map_err(csv)?;
    write(&mut w).and_then(|()| Ok(w.flush()?)).map_err(csv)
}

/// The layout a trial's targets had: `task file`, the room's (`room:SCALE:WIDTHxDEPTH`, the task
/// file's spacing scaled into a floor of that size in metres), and any targets the scene's ground
/// moved (a room without the study scene's terrace), each as `TARGET:FROM_Y>TO_Y` (0-based
/// target, heights in metres); separated by `;`.
pub fn layout(k: &grove_systems::task::TaskReport) -> String {
    let room = k.layout.iter().map(|p| format!("room:{:.4}:{:.2}x{:.2}", p.scale, p.floor_size[0], p.floor_size[1]));
    let moved = k.moved_targets.iter().map(|m| format!("{}:{:.2}>{:.2}", m.target, m.from[1], m.to[1]));
    let all: Vec<String> = room.chain(moved).collect();
    if all.is_empty() { "task file".into() } else { all.join(";") }
}

/// Writes `trial_results.csv`. With a what-if, its rows are the what-if trials and the last
/// columns give the baseline and the difference.
pub fn write_trial_results(path: &Path, trials: &[Trial], what_if: Option<&WhatIf>) -> Result<(), StudyError> {
    with_writer(path, |w| {
        w.write_record(TRIAL_COLUMNS)?;
        let join = |g: &dyn Fn(&super::whatif::ParamChange) -> String| what_if.map(|x| x.parameters.iter().map(g).collect::<Vec<_>>().join(";")).unwrap_or_default();
        for t in trials {
            let k = t.task.as_ref();
            let c = what_if.and_then(|x| x.comparison_for(t));
            let s = |g: &dyn Fn(&grove_systems::task::TaskReport) -> String| k.map(g).unwrap_or_default();
            w.write_record([
                "grove-study".to_string(),
                t.participant.clone(),
                "1".into(),
                t.trial_num.to_string(),
                t.block_num.to_string(),
                t.trial_num_in_block.to_string(),
                of(t.start_time_s),
                of(t.end_time_s),
                t.session_start.clone().unwrap_or_default(),
                s(&|k| k.id.clone()),
                s(&|k| k.mode.clone()),
                s(&|k| k.completed.to_string()),
                of(usable_time(t)),
                s(&|k| k.trees.len().to_string()),
                s(&|k| k.model_types.to_string()),
                s(&|k| k.errors.to_string()),
                s(&|k| k.error_kinds.removals.to_string()),
                s(&|k| k.error_kinds.off_target.to_string()),
                s(&|k| k.error_kinds.released_green.to_string()),
                s(&|k| k.menu_opens.to_string()),
                s(&|k| f(k.ray_path_m as f64)),
                s(&|k| f(k.aiming_s)),
                s(&|k| f(k.menu_s)),
                s(&|k| f(k.manipulating_s)),
                t.status.word().into(),
                t.synthetic.to_string(),
                t.file.clone(),
                what_if.map(|x| x.kind.clone()).unwrap_or_default(),
                join(&|p| p.name.clone()),
                join(&|p| p.default_value.clone()),
                join(&|p| p.new_value.clone()),
                of(c.and_then(|c| c.baseline_time_s)),
                of(c.and_then(|c| c.difference_s)),
                s(&layout),
                t.device.mapping.clone(),
                t.device.target_ray_mode.clone(),
                t.device.profile.clone(),
            ])?;
        }
        Ok(())
    })
}

/// Writes `trees.csv`: one row per satisfied target, in planting order within each trial.
pub fn write_trees(path: &Path, trials: &[Trial]) -> Result<(), StudyError> {
    with_writer(path, |w| {
        w.write_record(TREE_COLUMNS)?;
        for t in trials {
            let Some(k) = &t.task else { continue };
            let mut trees: Vec<_> = k.trees.iter().collect();
            trees.sort_by(|a, b| (a.tick, a.target).cmp(&(b.tick, b.target)));
            let mut previous = 0.0;
            for (i, tree) in trees.iter().enumerate() {
                w.write_record([
                    t.participant.clone(),
                    t.trial_num.to_string(),
                    k.id.clone(),
                    k.mode.clone(),
                    (i + 1).to_string(),
                    tree.target.to_string(),
                    tree.model.clone(),
                    tree.tick.to_string(),
                    f(tree.time_s),
                    f(tree.time_s - previous),
                    f(tree.position[0] as f64),
                    f(tree.position[1] as f64),
                    f(tree.position[2] as f64),
                    t.status.word().into(),
                    t.synthetic.to_string(),
                ])?;
                previous = tree.time_s;
            }
        }
        Ok(())
    })
}

/// The columns of `sweep.csv`.
pub fn sweep_columns() -> Vec<String> {
    let mut cols: Vec<String> = ["what_if_kind", "parameter", "default_value", "value", "is_default"].iter().map(|s| s.to_string()).collect();
    for m in ["ray_casting", "manual"] {
        for c in ["completed", "mean_s", "baseline_mean_s", "difference_s", "pairs"] {
            cols.push(format!("{m}_{c}"));
        }
    }
    cols.push("ray_casting_faster_for_all".into());
    cols.push("missing_comparisons".into());
    cols.push("synthetic".into());
    cols
}

/// Writes `sweep.csv`: one row per value.
pub fn write_sweep(path: &Path, sweep: &Sweep) -> Result<(), StudyError> {
    with_writer(path, |w| {
        w.write_record(sweep_columns())?;
        for r in &sweep.rows {
            let mut rec = vec![sweep.kind.clone(), sweep.parameter.clone(), sweep.default_value.clone(), r.value.clone(), r.is_default.to_string()];
            for m in ["ray-casting", "manual"] {
                let c = r.modes.get(m);
                rec.push(r.completed.get(m).copied().unwrap_or(0).to_string());
                rec.push(of(c.and_then(|c| c.what_if_mean_s)));
                rec.push(of(c.and_then(|c| c.baseline_mean_s)));
                rec.push(of(c.and_then(|c| c.difference_s)));
                rec.push(c.map_or(0, |c| c.pairs).to_string());
            }
            rec.push(r.ray_casting_faster_for_all.map(|b| b.to_string()).unwrap_or_default());
            rec.push(r.missing_comparisons.join(";"));
            rec.push(sweep.baseline.synthetic.to_string());
            w.write_record(rec)?;
        }
        Ok(())
    })
}
