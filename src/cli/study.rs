//! `grove study`: re-simulate every recording of the study, verify each, evaluate its task and
//! write the researchers' reports.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{anyhow, bail};
use clap::Args;
use grove_systems::resources::Override;
use indicatif::{ProgressBar, ProgressStyle};

use crate::study::{chart, recordings_in, report, run_all, TrialStatus};

/// Arguments of `grove study`.
#[derive(Args)]
pub struct StudyArgs {
    /// The folder of recordings (*.jsonl).
    #[arg(long, default_value = "replays/study")]
    pub replays: PathBuf,
    /// Where the reports go: trial_results.csv, trees.csv, summary.json, ablation.png.
    #[arg(long, default_value = "target/study")]
    pub out: PathBuf,
    /// Print the summary as JSON on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Re-run the same input with a changed parameter, e.g. --set snap_threshold=0.1 (what-if).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
}

/// Parses and checks `--set NAME=VALUE` arguments, once, into typed overrides.
pub fn parse_overrides(set: &[String]) -> anyhow::Result<Vec<Override>> {
    Override::parse_all(set).map_err(|e| anyhow!("--set {e}"))
}

/// Runs `grove study`.
pub fn run(args: StudyArgs) -> anyhow::Result<ExitCode> {
    let overrides = parse_overrides(&args.set)?;
    let files = recordings_in(&args.replays)?;
    if args.out.exists() && !args.out.is_dir() {
        bail!("{}: exists and is not a folder", args.out.display());
    }
    std::fs::create_dir_all(&args.out).map_err(|e| anyhow!("{}: {e}", args.out.display()))?;

    let bar = ProgressBar::new(files.len() as u64);
    bar.set_style(ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} recordings {elapsed}").unwrap_or_else(|_| ProgressStyle::default_bar()));
    bar.set_prefix("study");
    let (trials, wall) = run_all(&files, &overrides, &|| bar.inc(1));
    bar.finish_and_clear();

    let summary = report::summarize(&trials, &overrides, wall);
    report::write_trial_results(&args.out.join("trial_results.csv"), &trials)?;
    report::write_trees(&args.out.join("trees.csv"), &trials)?;
    std::fs::write(args.out.join("summary.json"), serde_json::to_string_pretty(&serde_json::json!({"summary": &summary, "trials": &trials}))?)
        .map_err(|e| anyhow!("{}: {e}", args.out.display()))?;
    let title = if overrides.is_empty() {
        "Task time per participant: ray-casting vs manual".to_string()
    } else {
        format!("What-if ({}): task time per participant", overrides.iter().map(|o| format!("{}={}", o.name, o.text)).collect::<Vec<_>>().join(", "))
    };
    chart::ablation_chart(&args.out.join("ablation.png"), &summary.per_participant, &title, 1100, 600)?;

    if args.json {
        super::print_json(&serde_json::json!({"summary": &summary, "trials": &trials}))?;
    } else {
        print!("{}", report::table(&trials));
        for (mode, s) in &summary.modes {
            println!("{mode:<12} mean {:.2} s (sd {:.2}) over {} completed of {} trials, {:.2} errors per trial", s.mean_time_s, s.sd_time_s, s.completed, s.trials, s.mean_errors);
        }
        println!("ray-casting faster for every participant: {}", if summary.ray_casting_faster_for_all { "yes" } else { "no" });
        println!("reports in {}", args.out.display());
    }
    eprintln!("study: {} recordings re-simulated in {:.3} s", trials.len(), wall);
    let ok = trials.iter().all(|t| matches!(t.status, TrialStatus::Verified | TrialStatus::WhatIf));
    Ok(if ok { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
