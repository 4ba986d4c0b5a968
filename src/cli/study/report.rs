//! The reports of `grove study` from the trials of its runs: the same for a run without shards
//! and for `grove study merge`, so both write the same files.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{anyhow, bail};
use grove::atomic_write::{write_atomic, write_via_temp};
use grove_systems::resources::{Override, Overrides};
use grove_systems::set_arg::{SetArgs, Sweep as SweptParam};

use grove::html;
use grove::study::report::{self, Summary};
use grove::study::shard::RunPart;
use grove::study::whatif::{self, Sweep, WhatIf};
use grove::study::{chart, csv_out, table, Trial, TrialStatus};

/// Where and how the reports are written.
pub struct ReportTo {
    /// The folder of the reports.
    pub out: PathBuf,
    /// Print the summary as JSON instead of the table.
    pub json: bool,
    /// The `--replays` folder, for messages.
    pub replays: String,
    /// Whether the what-if compares with `--baseline` recordings (re-simulated participants).
    pub baseline: bool,
    /// `--html`: also write report.html, with these trials' sections.
    pub html: Option<grove::html::Selection>,
}

/// The files `grove study` writes into `--out`.
pub const REPORT_FILES: &[&str] = &["trial_results.csv", "trees.csv", "summary.json", "ablation.png", "sweep.csv", "sweep.png", "report.html"];

/// Refuses an output folder that is a file, or that holds reports, unless `force`; makes it.
pub fn prepare_out(out: &std::path::Path, force: bool) -> anyhow::Result<()> {
    if out.exists() && !out.is_dir() {
        bail!("{}: exists and is not a folder", out.display());
    }
    if !force
        && let Some(old) = REPORT_FILES.iter().map(|f| out.join(f)).find(|p| p.exists())
    {
        bail!("{}: holds the reports of an earlier run ({}); use --force to replace them, or another --out", out.display(), old.display());
    }
    std::fs::create_dir_all(out).map_err(|e| anyhow!("{}: {e}", out.display()))
}

fn write_json(path: &Path, value: &serde_json::Value) -> anyhow::Result<()> {
    write_atomic(path, serde_json::to_string_pretty(value)?.as_bytes()).map_err(|e| anyhow!("{}: {e}", path.display()))
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
        n.push(format!("No comparison for {} (a red cross marks each missing bar).", summary.missing_comparisons.join(", ")));
    }
    if summary.synthetic {
        n.push("Synthetic data: simulated participants (grove synth), not people.".into());
    }
    n
}

/// Writes report.html and says so on stderr, with the time it took.
fn write_html(out: &Path, page: &html::StudyPage<'_>, trials: &[Trial], selection: &html::Selection) -> anyhow::Result<()> {
    let start = std::time::Instant::now();
    let file = html::write_study(out, page, trials, selection)?;
    let bytes = std::fs::metadata(&file).map(|m| m.len()).unwrap_or(0);
    eprintln!("study: {} ({:.1} MB) written in {:.1} s", file.display(), bytes as f64 / 1e6, start.elapsed().as_secs_f64());
    Ok(())
}

fn opt(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.2}"))
}

/// Writes the reports of a study from its runs (see `cli::study::compute` for their order) and
/// prints the table or the JSON. The exit code is 1 when a recording failed or diverged.
pub fn write_reports(to: &ReportTo, set: &SetArgs, runs: Vec<RunPart>) -> anyhow::Result<ExitCode> {
    if let Some(sweep) = &set.sweep {
        return write_sweep(to, &set.fixed, sweep, runs);
    }
    let mut runs = runs.into_iter();
    let main = runs.next().ok_or_else(|| anyhow!("a study without a run"))?;
    let (trials, wall) = (main.trials, main.wall_seconds);
    let what_if = match runs.next() {
        Some(base) if to.baseline => {
            // The recordings' headers were checked when read; together they must still agree.
            let params: Overrides = trials.iter().flat_map(|t| t.config.as_slice().iter().cloned()).collect();
            if params.is_empty() {
                bail!("{}: the recordings carry no changed setting (`config` in their headers); write them with `grove synth --set NAME=VALUE`", to.replays);
            }
            params.config().map_err(|e| anyhow!("{}: {e}", to.replays))?;
            let params = params.as_slice();
            Some(WhatIf::compare(whatif::RESIMULATED_PARTICIPANTS, whatif::param_changes(&params), &base.trials, &trials, base.wall_seconds))
        }
        Some(base) => Some(WhatIf::compare(whatif::REPLAYED_HANDS, whatif::param_changes(&set.fixed), &base.trials, &trials, base.wall_seconds)),
        None => None,
    };

    // Each report goes through a temporary file and a rename, so none is ever left half written.
    let out = &to.out;
    let summary = report::summarize(&trials, &set.fixed, wall);
    write_via_temp(&out.join("trial_results.csv"), |tmp| csv_out::write_trial_results(tmp, &trials, what_if.as_ref()))?;
    write_via_temp(&out.join("trees.csv"), |tmp| csv_out::write_trees(tmp, &trials))?;
    let json = serde_json::json!({"note": &summary.note, "summary": &summary, "what_if": &what_if, "sweep": null, "trials": &trials});
    write_json(&out.join("summary.json"), &json)?;
    let title = match &what_if {
        None => "Task time per participant: ray-casting vs manual".to_string(),
        // The chart font has no arrow.
        Some(w) => format!("What-if ({}): {}", w.kind, w.parameters_text().replace('→', "->")),
    };
    let baseline_rows = what_if.as_ref().map(|w| w.baseline.per_participant.as_slice());
    write_via_temp(&out.join("ablation.png"), |tmp| chart::ablation_chart(tmp, &summary.per_participant, baseline_rows, &title, &notes(what_if.as_ref(), &summary), 1100, 640))?;
    if let Some(selection) = &to.html {
        let charts = vec![(title.clone(), chart::ablation_svg(&summary.per_participant, baseline_rows, &title, &notes(what_if.as_ref(), &summary), 1100, 640)?)];
        // The what-if trials of replayed hands ran under --set; re-simulated participants carry
        // their setting in their headers.
        let overrides: &[Override] = if to.baseline { &[] } else { &set.fixed };
        let page = html::StudyPage { summary: &summary, what_if: what_if.as_ref(), sweep: None, charts, replays: to.replays.clone(), overrides };
        write_html(out, &page, &trials, selection)?;
    }

    if to.json {
        crate::cli::print_json(&json)?;
    } else {
        print!("{}", table::table(&trials, what_if.as_ref()));
        if let Some(w) = &what_if {
            println!("what-if kind: {} ({})", w.kind, w.kind_meaning);
            for (mode, m) in &w.modes {
                println!(
                    "{mode:<12} baseline {} s, what-if {} s, difference {} s over {} trials completed in both ({} without a difference)",
                    opt(m.baseline_mean_s),
                    opt(m.what_if_mean_s),
                    opt(m.difference_s),
                    m.pairs,
                    m.unpaired
                );
                if let Some(p) = &m.paired {
                    print!("  {}", table::paired_line(p));
                }
            }
            println!("under the what-if:");
        }
        print!("{}", table::summary_lines(&summary));
        println!("reports in {}", out.display());
    }
    eprintln!("study: {} recordings re-simulated in {:.3} s", trials.len(), wall);
    let ok = all_ok(&trials) && what_if.as_ref().is_none_or(|w| w.baseline.status.get("failed").is_none() && w.baseline.status.get("diverged").is_none());
    Ok(if ok { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// A sweep's reports: the baseline (first run) and one replayed-hands run per value.
fn write_sweep(to: &ReportTo, fixed: &[Override], swept: &SweptParam, runs: Vec<RunPart>) -> anyhow::Result<ExitCode> {
    let (name, values) = (swept.param.name, &swept.values);
    if runs.len() != values.len() + 1 {
        bail!("a sweep of {} values with {} runs", values.len(), runs.len());
    }
    let mut runs = runs.into_iter();
    let base = runs.next().ok_or_else(|| anyhow!("a sweep without its baseline"))?;
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
    write_via_temp(&out.join("trial_results.csv"), |tmp| csv_out::write_trial_results(tmp, &baseline, None))?;
    write_via_temp(&out.join("trees.csv"), |tmp| csv_out::write_trees(tmp, &baseline))?;
    write_via_temp(&out.join("sweep.csv"), |tmp| csv_out::write_sweep(tmp, &sweep))?;
    let json = serde_json::json!({"note": &summary.note, "summary": &summary, "what_if": null, "sweep": &sweep, "trials": &baseline});
    write_json(&out.join("summary.json"), &json)?;
    let mut n = vec![format!("Sweep, {}: {}.", sweep.kind, sweep.kind_meaning), format!("Default {} = {}; means are over the completed trials.", name, sweep.default_value)];
    if !sweep.fixed.is_empty() {
        n.push(format!("Held for every value: {}.", sweep.fixed.iter().map(|p| format!("{} = {} (default {})", p.name, p.new_value, p.default_value)).collect::<Vec<_>>().join(", ")));
    }
    if summary.synthetic {
        n.push("Synthetic data: simulated participants (grove synth), not people.".into());
    }
    write_via_temp(&out.join("sweep.png"), |tmp| chart::sweep_chart(tmp, &sweep, &n, 1000, 620))?;
    write_via_temp(&out.join("ablation.png"), |tmp| {
        chart::ablation_chart(tmp, &summary.per_participant, None, "Baseline task time per participant: ray-casting vs manual", &notes(None, &summary), 1100, 640)
    })?;
    if let Some(selection) = &to.html {
        let title = "Baseline task time per participant: ray-casting vs manual".to_string();
        let charts = vec![
            (title.clone(), chart::ablation_svg(&summary.per_participant, None, &title, &notes(None, &summary), 1100, 640)?),
            (format!("Mean task time against {name}"), chart::sweep_svg(&sweep, &n, 1000, 620)?),
        ];
        let page = html::StudyPage { summary: &summary, what_if: None, sweep: Some(&sweep), charts, replays: to.replays.clone(), overrides: &[] };
        write_html(out, &page, &baseline, selection)?;
    }

    if to.json {
        crate::cli::print_json(&json)?;
    } else {
        println!("sweep of {name} ({}: {}); default {}", sweep.kind, sweep.kind_meaning, sweep.default_value);
        println!("{:>10} {:>8} {:>14} {:>10} {:>10} {:>14} {:>10} {:>10}", "value", "default", "ray_casting_s", "done", "diff_s", "manual_s", "done", "diff_s");
        for r in &sweep.rows {
            let m = |mode: &str| r.modes.get(mode);
            println!(
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
        println!("baseline (every parameter at its default):");
        print!("{}", table::summary_lines(&summary));
        println!("reports in {} (sweep.csv, sweep.png)", out.display());
    }
    Ok(if ok { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
