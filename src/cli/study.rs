//! `grove study`: re-simulate every recording of the study, verify each, evaluate its task and
//! write the researchers' reports (`docs/reports.md` defines every column and field).
//!
//! Four kinds of run:
//! - plain: the recordings as they are;
//! - what-if, replayed hands (`--set NAME=VALUE`): the baseline and the same input under the
//!   new setting, compared trial by trial;
//! - what-if, re-simulated participants (`--baseline DIR`): recordings made by
//!   `grove synth --set …` compared with the baseline recordings in DIR;
//! - sweep (`--set NAME=V1,V2,…`): the baseline and one replayed-hands run per value.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{anyhow, bail};
use clap::Args;
use grove::atomic_write::{write_atomic, write_via_temp};
use grove_systems::resources::{Config, Override};
use indicatif::{ProgressBar, ProgressStyle};

use crate::study::report::{self, Summary};
use crate::study::whatif::{self, Sweep, WhatIf};
use crate::study::{chart, csv_out, recordings_in, run_all, Trial, TrialStatus};

/// Arguments of `grove study`.
#[derive(Args)]
pub struct StudyArgs {
    /// The folder of recordings (*.jsonl).
    #[arg(long, default_value = "replays/study")]
    pub replays: PathBuf,
    /// Where the reports go: trial_results.csv, trees.csv, summary.json, ablation.png (and
    /// sweep.csv, sweep.png for a sweep).
    #[arg(long, default_value = "target/study")]
    pub out: PathBuf,
    /// Print the summary as JSON on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    /// What-if on the replayed hands: re-run the same input with a changed parameter and compare
    /// with the baseline, e.g. --set snap_threshold=0.2. Several comma-separated values sweep the
    /// parameter: --set snap_threshold=0.05,0.1,0.2,0.3,0.5.
    #[arg(long = "set", value_name = "NAME=VALUE[,VALUE…]")]
    pub set: Vec<String>,
    /// What-if on re-simulated participants: compare the recordings in --replays (written by
    /// `grove synth --set …`) with the baseline recordings in this folder.
    #[arg(long, value_name = "DIR", conflicts_with = "set")]
    pub baseline: Option<PathBuf>,
    /// Replace the reports of an earlier run in --out (without it, a folder holding any of them
    /// is refused).
    #[arg(long)]
    pub force: bool,
}

/// The files `grove study` writes into `--out`.
pub const REPORT_FILES: &[&str] = &["trial_results.csv", "trees.csv", "summary.json", "ablation.png", "sweep.csv", "sweep.png"];

/// Parses and checks `--set NAME=VALUE` arguments, once, into typed overrides.
pub fn parse_overrides(set: &[String]) -> anyhow::Result<Vec<Override>> {
    Override::parse_all(set).map_err(|e| anyhow!("--set {e}"))
}

/// The parsed `--set` arguments: single values, and at most one swept parameter.
pub struct SetArgs {
    /// Parameters with one value.
    pub fixed: Vec<Override>,
    /// The swept parameter and its values, each already checked.
    pub sweep: Option<(String, Vec<Override>)>,
}

/// Splits `--set` arguments into fixed values and one sweep, checking every value once.
pub fn parse_set(set: &[String]) -> anyhow::Result<SetArgs> {
    let mut fixed = Vec::new();
    let mut sweep: Option<(String, Vec<Override>)> = None;
    for s in set {
        let (k, v) = s.split_once('=').ok_or_else(|| anyhow!("--set {s}: expected NAME=VALUE"))?;
        let values: Vec<&str> = v.split(',').map(str::trim).collect();
        if values.iter().any(|x| x.is_empty()) {
            bail!("--set {s}: an empty value in the list");
        }
        let parsed = values.iter().map(|value| Override::parse(&format!("{}={value}", k.trim()))).collect::<Result<Vec<_>, _>>().map_err(|e| anyhow!("--set {e}"))?;
        if parsed.len() > 1 {
            if sweep.is_some() {
                bail!("--set {s}: only one parameter can be swept at a time");
            }
            sweep = Some((k.trim().to_string(), parsed));
        } else {
            fixed.extend(parsed);
        }
    }
    // The values must also hold together (e.g. min_scale ≤ max_scale).
    Config::default().apply(&fixed).map_err(|e| anyhow!("--set {e}"))?;
    Ok(SetArgs { fixed, sweep })
}

fn progress(total: u64) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} re-simulations {elapsed}").unwrap_or_else(|_| ProgressStyle::default_bar()));
    bar.set_prefix("study");
    bar
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

/// Runs `grove study`.
pub fn run(args: StudyArgs) -> anyhow::Result<ExitCode> {
    let set = parse_set(&args.set)?;
    let files = recordings_in(&args.replays)?;
    let base_files = args.baseline.as_deref().map(recordings_in).transpose()?;
    if args.out.exists() && !args.out.is_dir() {
        bail!("{}: exists and is not a folder", args.out.display());
    }
    if !args.force
        && let Some(old) = REPORT_FILES.iter().map(|f| args.out.join(f)).find(|p| p.exists())
    {
        bail!("{}: holds the reports of an earlier run ({}); use --force to replace them, or another --out", args.out.display(), old.display());
    }
    std::fs::create_dir_all(&args.out).map_err(|e| anyhow!("{}: {e}", args.out.display()))?;
    if let Some((name, values)) = &set.sweep {
        return run_sweep(&args, &files, &set.fixed, name, values);
    }

    let runs = if set.fixed.is_empty() && base_files.is_none() { 1 } else { 2 };
    let total = files.len() + base_files.as_ref().map_or(if runs == 2 { files.len() } else { 0 }, Vec::len);
    let bar = progress(total as u64);
    let tick = || bar.inc(1);
    let (trials, wall) = run_all(&files, &set.fixed, &tick);
    let what_if = if let Some(base_files) = &base_files {
        let (baseline, bwall) = run_all(base_files, &[], &tick);
        let mut params: std::collections::BTreeMap<String, String> = Default::default();
        for t in &trials {
            params.extend(t.config.clone());
        }
        if params.is_empty() {
            bar.finish_and_clear();
            bail!("{}: the recordings carry no changed setting (`config` in their headers); write them with `grove synth --set NAME=VALUE`", args.replays.display());
        }
        let params: Vec<(String, String)> = params.into_iter().collect();
        let params = Override::parse_all(&params.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>()).map_err(|e| anyhow!("{}: {e}", args.replays.display()))?;
        Some(WhatIf::compare(whatif::RESIMULATED_PARTICIPANTS, whatif::param_changes(&params), &baseline, &trials, bwall))
    } else if !set.fixed.is_empty() {
        let (baseline, bwall) = run_all(&files, &[], &tick);
        Some(WhatIf::compare(whatif::REPLAYED_HANDS, whatif::param_changes(&set.fixed), &baseline, &trials, bwall))
    } else {
        None
    };
    bar.finish_and_clear();

    // Each report goes through a temporary file and a rename, so none is ever left half written.
    let summary = report::summarize(&trials, &set.fixed, wall);
    write_via_temp(&args.out.join("trial_results.csv"), |tmp| csv_out::write_trial_results(tmp, &trials, what_if.as_ref()))?;
    write_via_temp(&args.out.join("trees.csv"), |tmp| csv_out::write_trees(tmp, &trials))?;
    let json = serde_json::json!({"note": &summary.note, "summary": &summary, "what_if": &what_if, "sweep": null, "trials": &trials});
    write_json(&args.out.join("summary.json"), &json)?;
    let title = match &what_if {
        None => "Task time per participant: ray-casting vs manual".to_string(),
        // The chart font has no arrow.
        Some(w) => format!("What-if ({}): {}", w.kind, w.parameters_text().replace('→', "->")),
    };
    let baseline_rows = what_if.as_ref().map(|w| w.baseline.per_participant.as_slice());
    write_via_temp(&args.out.join("ablation.png"), |tmp| chart::ablation_chart(tmp, &summary.per_participant, baseline_rows, &title, &notes(what_if.as_ref(), &summary), 1100, 640))?;

    if args.json {
        super::print_json(&json)?;
    } else {
        print!("{}", report::table(&trials, what_if.as_ref()));
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
                    print!("  {}", report::paired_line(p));
                }
            }
            println!("under the what-if:");
        }
        print!("{}", report::summary_lines(&summary));
        println!("reports in {}", args.out.display());
    }
    eprintln!("study: {} recordings re-simulated in {:.3} s", trials.len(), wall);
    let ok = all_ok(&trials) && what_if.as_ref().is_none_or(|w| w.baseline.status.get("failed").is_none() && w.baseline.status.get("diverged").is_none());
    Ok(if ok { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

fn opt(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.2}"))
}

/// A sweep: the baseline and one replayed-hands run per value.
fn run_sweep(args: &StudyArgs, files: &[PathBuf], fixed: &[Override], name: &str, values: &[Override]) -> anyhow::Result<ExitCode> {
    let bar = progress((files.len() * (values.len() + 1)) as u64);
    let tick = || bar.inc(1);
    let (baseline, bwall) = run_all(files, &[], &tick);
    let mut rows = Vec::new();
    let mut ok = all_ok(&baseline);
    for v in values {
        let mut overrides = fixed.to_vec();
        overrides.push(v.clone());
        let (trials, _) = run_all(files, &overrides, &tick);
        ok &= all_ok(&trials);
        rows.push(Sweep::row(name, &v.text, &baseline, &trials));
    }
    bar.finish_and_clear();
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
    csv_out::write_trial_results(&args.out.join("trial_results.csv"), &baseline, None)?;
    csv_out::write_trees(&args.out.join("trees.csv"), &baseline)?;
    write_via_temp(&args.out.join("sweep.csv"), |tmp| csv_out::write_sweep(tmp, &sweep))?;
    let json = serde_json::json!({"note": &summary.note, "summary": &summary, "what_if": null, "sweep": &sweep, "trials": &baseline});
    write_json(&args.out.join("summary.json"), &json)?;
    let mut n = vec![format!("Sweep, {}: {}.", sweep.kind, sweep.kind_meaning), format!("Default {} = {}; means are over the completed trials.", name, sweep.default_value)];
    if !sweep.fixed.is_empty() {
        n.push(format!("Held for every value: {}.", sweep.fixed.iter().map(|p| format!("{} = {} (default {})", p.name, p.new_value, p.default_value)).collect::<Vec<_>>().join(", ")));
    }
    if summary.synthetic {
        n.push("Synthetic data: simulated participants (grove synth), not people.".into());
    }
    write_via_temp(&args.out.join("sweep.png"), |tmp| chart::sweep_chart(tmp, &sweep, &n, 1000, 620))?;
    chart::ablation_chart(&args.out.join("ablation.png"), &summary.per_participant, None, "Baseline task time per participant: ray-casting vs manual", &notes(None, &summary), 1100, 640)?;

    if args.json {
        super::print_json(&json)?;
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
        print!("{}", report::summary_lines(&summary));
        println!("reports in {} (sweep.csv, sweep.png)", args.out.display());
    }
    Ok(if ok { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
