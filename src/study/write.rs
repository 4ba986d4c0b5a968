//! The reports of a study from the trials of its runs: the same for a run without shards and
//! for `grove study merge`, so both write the same files. Every file goes through a temporary
//! file and a rename ([`crate::atomic_write`]), so none is ever left half written. What the
//! terminal shows (the table, or the summary as JSON) comes back in [`Reports`] for the caller
//! to print, with what the HTML report needs.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use grove_systems::resources::{Override, Overrides};
use grove_systems::set_arg::{SetArgs, Sweep as SweptParam};

use crate::atomic_write::{via_temp, write_bytes};

use super::report::{self, Summary};
use super::shard::RunPart;
use super::whatif::{self, Sweep, WhatIf};
use super::{StudyError, Trial, TrialStatus, chart, csv_out, table};

/// Where and how the reports are written.
pub struct ReportTo {
    /// The folder of the reports.
    pub out: PathBuf,
    /// The `--replays` folder, for messages.
    pub replays: String,
    /// Whether the what-if compares with `--baseline` recordings (re-simulated participants).
    pub baseline: bool,
    /// Whether the caller writes the HTML report: [`Reports::charts`] then holds its charts.
    pub html: bool,
    /// The folder whose questionnaires (a protocol's answers, `docs/protocol.md`) join the reports.
    pub questionnaires: Option<PathBuf>,
}

/// The files `grove study` writes into `--out`.
pub const REPORT_FILES: &[&str] = &[
    "trial_results.csv",
    "trees.csv",
    "summary.json",
    "ablation.png",
    "sweep.csv",
    "sweep.png",
    "report.html",
    "questionnaire_long.csv",
    "questionnaire_wide.csv",
    "questionnaire_scores.csv",
];

/// What [`write_reports`] wrote, for the caller to show, and what the HTML report is made of.
pub struct Reports {
    /// The content of summary.json.
    pub json: serde_json::Value,
    /// The table for the terminal.
    pub text: String,
    /// Whether every recording was verified (none failed or diverged).
    pub ok: bool,
    /// For a study that is not a sweep: the recordings re-simulated and their seconds.
    pub resimulated: Option<(usize, f64)>,
    /// The trials the reports are of (a sweep's: its baseline).
    pub trials: Vec<Trial>,
    /// The summary of those trials.
    pub summary: Summary,
    /// The what-if, if any.
    pub what_if: Option<WhatIf>,
    /// The sweep, if any.
    pub sweep: Option<Sweep>,
    /// The charts as SVG, each with its title (only with [`ReportTo::html`]).
    pub charts: Vec<(String, String)>,
    /// The settings the trials ran under (a replayed-hands what-if's `--set`; none otherwise).
    pub overrides: Vec<Override>,
    /// The questionnaires of a protocol's folder, if any.
    pub questionnaires: Option<super::questionnaire::Questionnaires>,
}

/// Refuses an output folder that is a file, or that holds reports, unless `force`; makes it.
pub fn prepare_out(out: &Path, force: bool) -> Result<(), StudyError> {
    if out.exists() && !out.is_dir() {
        return Err(StudyError::OutIsAFile(out.to_path_buf()));
    }
    if !force && let Some(old) = REPORT_FILES.iter().map(|f| out.join(f)).find(|p| p.exists()) {
        return Err(StudyError::EarlierReports { out: out.to_path_buf(), old });
    }
    std::fs::create_dir_all(out).map_err(|source| StudyError::Folder { path: out.to_path_buf(), source })
}

fn write_json(path: &Path, value: &serde_json::Value) -> Result<(), StudyError> {
    Ok(write_bytes(path, serde_json::to_string_pretty(value)?.as_bytes())?)
}

fn all_ok(trials: &[Trial]) -> bool {
    trials.iter().all(|t| !matches!(t.status, TrialStatus::Failed | TrialStatus::Diverged))
}

/// The notes under a chart.
fn notes(what_if: Option<&WhatIf>, summary: &Summary) -> Vec<String> {
    let mut n = Vec::new();
    if let Some(w) = what_if {
        n.push(format!("What-if, {}: {}.", w.kind, w.kind_meaning));
        n.push("Filled bars: the what-if; black outlines: the baseline.".into());
    }
    if !summary.missing_comparisons.is_empty() {
        n.push(format!(
            "No comparison for {} (a red cross marks each missing bar).",
            summary.missing_comparisons.join(", ")
        ));
    }
    if summary.synthetic {
        n.push("Synthetic data: simulated participants (grove synth), not people.".into());
    }
    n
}

fn opt(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.2}"))
}

/// Writes the reports of a study from its runs, in the order a study makes them: a plain
/// study's one run; a what-if's run, then its baseline's; a sweep's baseline, then one run per
/// value. `ok` is false when a recording failed or diverged.
pub fn write_reports(to: &ReportTo, set: &SetArgs, runs: Vec<RunPart>) -> Result<Reports, StudyError> {
    if let Some(sweep) = &set.sweep {
        return write_sweep(to, &set.fixed, sweep, runs);
    }
    let given = runs.len();
    let mut runs = runs.into_iter();
    let main = runs.next().ok_or(StudyError::Runs { expected: 1, given })?;
    let (trials, wall) = (main.trials, main.wall_seconds);
    let what_if = match runs.next() {
        Some(base) if to.baseline => {
            // The recordings' headers were checked when read; together they must still agree.
            let params: Overrides = trials.iter().flat_map(|t| t.config.as_slice().iter().cloned()).collect();
            if params.is_empty() {
                return Err(StudyError::NoChangedSetting(to.replays.clone()));
            }
            params.config().map_err(|source| StudyError::Settings { replays: to.replays.clone(), source })?;
            let params = params.as_slice();
            Some(WhatIf::compare(
                whatif::RESIMULATED_PARTICIPANTS,
                whatif::param_changes(params),
                &base.trials,
                &trials,
                base.wall_seconds,
            ))
        }
        Some(base) => Some(WhatIf::compare(
            whatif::REPLAYED_HANDS,
            whatif::param_changes(&set.fixed),
            &base.trials,
            &trials,
            base.wall_seconds,
        )),
        None => None,
    };

    let out = &to.out;
    let summary = report::summarize(&trials, &set.fixed, wall);
    via_temp(&out.join("trial_results.csv"), |tmp| csv_out::write_trial_results(tmp, &trials, what_if.as_ref()))?;
    via_temp(&out.join("trees.csv"), |tmp| csv_out::write_trees(tmp, &trials))?;
    let questionnaires = match &to.questionnaires {
        Some(dir) => super::questionnaire::load(dir)?,
        None => None,
    };
    let mut json = serde_json::json!({"note": &summary.note, "summary": &summary, "what_if": &what_if, "sweep": null, "trials": &trials});
    if let Some(q) = &questionnaires {
        super::questionnaire::write(out, q)?;
        json["questionnaires"] = super::questionnaire::json(q);
    }
    write_json(&out.join("summary.json"), &json)?;
    let title = match &what_if {
        None => "Task time per participant: ray-casting vs manual".to_string(),
        // The chart font has no arrow.
        Some(w) => format!("What-if ({}): {}", w.kind, w.parameters_text().replace('→', "->")),
    };
    let baseline_rows = what_if.as_ref().map(|w| w.baseline.per_participant.as_slice());
    via_temp(&out.join("ablation.png"), |tmp| {
        chart::ablation_chart(
            tmp,
            &summary.per_participant,
            baseline_rows,
            &title,
            &notes(what_if.as_ref(), &summary),
            1100,
            640,
        )
    })?;
    let charts = if to.html {
        vec![(
            title.clone(),
            chart::ablation_svg(
                &summary.per_participant,
                baseline_rows,
                &title,
                &notes(what_if.as_ref(), &summary),
                1100,
                640,
            )?,
        )]
    } else {
        Vec::new()
    };

    let mut text = table::table(&trials, what_if.as_ref());
    if let Some(w) = &what_if {
        let _ = writeln!(text, "what-if kind: {} ({})", w.kind, w.kind_meaning);
        for (mode, m) in &w.modes {
            let _ = writeln!(
                text,
                "{mode:<12} baseline {} s, what-if {} s, difference {} s over {} trials completed in both ({} without a difference)",
                opt(m.baseline_mean_s),
                opt(m.what_if_mean_s),
                opt(m.difference_s),
                m.pairs,
                m.unpaired
            );
            if let Some(p) = &m.paired {
                let _ = write!(text, "  {}", table::paired_line(p));
            }
        }
        text.push_str("under the what-if:\n");
    }
    text.push_str(&table::summary_lines(&summary));
    if let Some(q) = &questionnaires {
        text.push_str(&super::questionnaire::lines(q));
    }
    let _ = writeln!(text, "reports in {}", out.display());
    let ok = all_ok(&trials)
        && what_if
            .as_ref()
            .is_none_or(|w| !w.baseline.status.contains_key("failed") && !w.baseline.status.contains_key("diverged"));
    // The what-if trials of replayed hands ran under --set; re-simulated participants carry
    // their setting in their headers.
    let overrides = if to.baseline { Vec::new() } else { set.fixed.clone() };
    Ok(Reports {
        json,
        text,
        ok,
        resimulated: Some((trials.len(), wall)),
        trials,
        summary,
        what_if,
        sweep: None,
        charts,
        overrides,
        questionnaires,
    })
}

/// A sweep's reports: the baseline (first run) and one replayed-hands run per value.
fn write_sweep(
    to: &ReportTo,
    fixed: &[Override],
    swept: &SweptParam,
    runs: Vec<RunPart>,
) -> Result<Reports, StudyError> {
    let (name, values) = (swept.param.name, &swept.values);
    if runs.len() != values.len() + 1 {
        return Err(StudyError::Runs { expected: values.len() + 1, given: runs.len() });
    }
    let mut runs = runs.into_iter();
    let base = runs.next().ok_or(StudyError::Runs { expected: values.len() + 1, given: 0 })?;
    let (baseline, bwall) = (base.trials, base.wall_seconds);
    let mut ok = all_ok(&baseline);
    let mut rows = Vec::new();
    for (v, run) in values.iter().zip(runs) {
        ok &= all_ok(&run.trials);
        rows.push(Sweep::row(v, &baseline, &run.trials));
    }
    let summary = report::summarize(&baseline, &[], bwall);
    let sweep = Sweep {
        kind: whatif::REPLAYED_HANDS.into(),
        kind_meaning: whatif::kind_meaning(whatif::REPLAYED_HANDS).into(),
        parameter: name.to_string(),
        default_value: whatif::default_value(name),
        fixed: whatif::param_changes(fixed),
        rows,
        baseline: summary.clone(),
    };
    let out = &to.out;
    via_temp(&out.join("trial_results.csv"), |tmp| csv_out::write_trial_results(tmp, &baseline, None))?;
    via_temp(&out.join("trees.csv"), |tmp| csv_out::write_trees(tmp, &baseline))?;
    via_temp(&out.join("sweep.csv"), |tmp| csv_out::write_sweep(tmp, &sweep))?;
    let json = serde_json::json!({"note": &summary.note, "summary": &summary, "what_if": null, "sweep": &sweep, "trials": &baseline});
    write_json(&out.join("summary.json"), &json)?;
    let mut n = vec![
        format!("Sweep, {}: {}.", sweep.kind, sweep.kind_meaning),
        format!("Default {} = {}; means are over the completed trials.", name, sweep.default_value),
    ];
    if !sweep.fixed.is_empty() {
        n.push(format!(
            "Held for every value: {}.",
            sweep
                .fixed
                .iter()
                .map(|p| format!("{} = {} (default {})", p.name, p.new_value, p.default_value))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    if summary.synthetic {
        n.push("Synthetic data: simulated participants (grove synth), not people.".into());
    }
    via_temp(&out.join("sweep.png"), |tmp| chart::sweep_chart(tmp, &sweep, &n, 1000, 620))?;
    via_temp(&out.join("ablation.png"), |tmp| {
        chart::ablation_chart(
            tmp,
            &summary.per_participant,
            None,
            "Baseline task time per participant: ray-casting vs manual",
            &notes(None, &summary),
            1100,
            640,
        )
    })?;
    let charts = if to.html {
        let title = "Baseline task time per participant: ray-casting vs manual".to_string();
        vec![
            (
                title.clone(),
                chart::ablation_svg(&summary.per_participant, None, &title, &notes(None, &summary), 1100, 640)?,
            ),
            (format!("Mean task time against {name}"), chart::sweep_svg(&sweep, &n, 1000, 620)?),
        ]
    } else {
        Vec::new()
    };

    let mut text =
        format!("sweep of {name} ({}: {}); default {}\n", sweep.kind, sweep.kind_meaning, sweep.default_value);
    let _ = writeln!(
        text,
        "{:>10} {:>8} {:>14} {:>10} {:>10} {:>14} {:>10} {:>10}",
        "value", "default", "ray_casting_s", "done", "diff_s", "manual_s", "done", "diff_s"
    );
    for r in &sweep.rows {
        let m = |mode: &str| r.modes.get(mode);
        let _ = writeln!(
            text,
            "{:>10} {:>8} {:>14} {:>10} {:>10} {:>14} {:>10} {:>10}",
            r.value,
            if r.is_default { "yes" } else { "" },
            opt(m("ray-casting").and_then(|c| c.what_if_mean_s)),
            r.completed.get("ray-casting").copied().unwrap_or(0),
            opt(m("ray-casting").and_then(|c| c.difference_s)),
            opt(m("manual").and_then(|c| c.what_if_mean_s)),
            r.completed.get("manual").copied().unwrap_or(0),
            opt(m("manual").and_then(|c| c.difference_s)),
        );
    }
    text.push_str("baseline (every parameter at its default):\n");
    text.push_str(&table::summary_lines(&summary));
    let _ = writeln!(text, "reports in {} (sweep.csv, sweep.png)", out.display());
    Ok(Reports {
        json,
        text,
        ok,
        resimulated: None,
        trials: baseline,
        summary,
        what_if: None,
        sweep: Some(sweep),
        charts,
        overrides: Vec::new(),
        questionnaires: None,
    })
}
