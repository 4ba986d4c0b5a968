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

pub mod merge;
pub mod synth;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{anyhow, bail};
use clap::{Args, Subcommand};
use grove::atomic_write::write_atomic;
use grove_systems::resources::Override;
use grove_systems::set_arg::{SetArg, SetArgs};
use indicatif::{ProgressBar, ProgressStyle};

use grove::study::shard::{Partial, RunPart, Shard, StudyKey};
use grove::study::write::{ReportTo, Reports, prepare_out, write_reports};
use grove::study::{list_recordings, recordings_in, run_all};

/// Arguments of `grove study`.
#[derive(Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct StudyArgs {
    /// `grove study merge`: put the partial results of `--shard` runs together.
    #[command(subcommand)]
    pub command: Option<StudyCommand>,
    /// The folder of recordings (*.jsonl).
    #[arg(long, default_value = "replays/study")]
    pub replays: PathBuf,
    /// Where the reports go: trial_results.csv, trees.csv, summary.json, ablation.png (and
    /// sweep.csv, sweep.png for a sweep); default target/study. With --shard, the partial
    /// result's file.
    #[arg(long, value_name = "DIR|PART")]
    pub out: Option<PathBuf>,
    /// Print the summary as JSON on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    #[arg(long = "set", value_name = "NAME=VALUE[,VALUE…]", help = SET_HELP, long_help = set_long_help())]
    pub set: Vec<SetArg>,
    /// What-if on re-simulated participants: compare the recordings in --replays (written by
    /// `grove synth --set …`) with the baseline recordings in this folder.
    #[arg(long, value_name = "DIR", conflicts_with = "set")]
    pub baseline: Option<PathBuf>,
    /// Replace the reports of an earlier run in --out (without it, a folder holding any of them
    /// is refused); with --shard, replace the partial result.
    #[arg(long)]
    pub force: bool,
    /// Re-simulate only shard K of N (1 ≤ K ≤ N): the recordings whose file name, up to its
    /// first '-' (the participant, P07), hashes (XXH3) to K, in --replays and --baseline alike. Writes a partial result to --out PART;
    /// `grove study merge` puts the N of them together into the reports (docs/scale.md).
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Also write report.html: one self-contained page (no network) with the overview, the task
    /// area from above (ray heatmaps, tree paths, planting errors) and each trial's timeline,
    /// tree durations and head-camera filmstrip (docs/reports.md, "The HTML report").
    #[arg(long, conflicts_with = "shard")]
    pub html: bool,
    /// With --html: the participants whose trials get a section of their own, e.g. P03,P07, or
    /// `all`. Default: every trial up to 50 recordings; beyond, the three slowest completed
    /// trials per condition and every incomplete, failed or diverged one.
    #[arg(long, value_name = "P03,P07|all", requires = "html")]
    pub html_trials: Option<String>,
}

/// Subcommands of `grove study`.
#[derive(Subcommand)]
pub enum StudyCommand {
    /// Merge the partial results of every shard (`grove study --shard K/N --out PART`) into the
    /// reports a run without shards writes.
    Merge(merge::MergeArgs),
}

fn progress(total: u64) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} re-simulations {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_prefix("study");
    bar
}

/// Re-simulates the recordings of every run a study makes, in this order:
/// - plain: the recordings;
/// - what-if: the what-if trials, then the baseline's (`base_files`, or the same files at the
///   defaults);
/// - sweep: the baseline, then one run per value.
fn compute(set: &SetArgs, files: &[PathBuf], base_files: Option<&[PathBuf]>) -> Vec<RunPart> {
    let run = |files: &[PathBuf], overrides: &[Override], bar: &ProgressBar| {
        let (trials, wall_seconds) = run_all(files, overrides, &|| bar.inc(1));
        RunPart { trials, wall_seconds }
    };
    let mut runs = Vec::new();
    if let Some(sweep) = &set.sweep {
        let bar = progress((files.len() * (sweep.values.len() + 1)) as u64);
        runs.push(run(files, &[], &bar));
        for v in &sweep.values {
            let mut overrides = set.fixed.clone();
            overrides.push(v.clone());
            runs.push(run(files, &overrides, &bar));
        }
        bar.finish_and_clear();
        return runs;
    }
    let what_if = !set.fixed.is_empty() || base_files.is_some();
    let bar =
        progress((files.len() + base_files.map_or(if what_if { files.len() } else { 0 }, <[PathBuf]>::len)) as u64);
    runs.push(run(files, &set.fixed, &bar));
    if let Some(base) = base_files {
        runs.push(run(base, &[], &bar));
    } else if what_if {
        runs.push(run(files, &[], &bar));
    }
    bar.finish_and_clear();
    runs
}

/// Runs `grove study` (or `grove study merge`).
pub fn run(args: StudyArgs) -> anyhow::Result<ExitCode> {
    if let Some(StudyCommand::Merge(m)) = args.command {
        return merge::run(m);
    }
    let set = SetArgs::new(&args.set).map_err(|e| anyhow!("--set {e}"))?;
    let html = match (args.html, &args.html_trials) {
        (false, _) => None,
        (true, None) => Some(grove::html::Selection::Auto),
        (true, Some(s)) => Some(s.parse::<grove::html::Selection>()?),
    };
    // A shard's folder may hold none of the study's recordings (grove synth --shard wrote no
    // participant there); a study without shards needs some.
    let list = if args.shard.is_some() { list_recordings } else { recordings_in };
    let files = list(&args.replays)?;
    let base_files = args.baseline.as_deref().map(list).transpose()?;
    if let Some(shard) = &args.shard {
        let shard: Shard = shard.parse().map_err(|e| anyhow!("--shard {e}"))?;
        return run_shard(&args, shard, &set, &files, base_files.as_deref());
    }
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from("target/study"));
    prepare_out(&out, args.force)?;
    let runs = compute(&set, &files, base_files.as_deref());
    let to = ReportTo {
        out,
        replays: args.replays.display().to_string(),
        baseline: args.baseline.is_some(),
        html: html.is_some(),
        questionnaires: Some(args.replays.clone()),
    };
    let reports = write_reports(&to, &set, runs)?;
    show(&to, html.as_ref(), args.json, &reports)
}

/// Writes report.html if asked (saying so on stderr, with the time it took), prints the table
/// or the summary as JSON, and gives the exit code: 1 when a recording failed or diverged.
pub(super) fn show(
    to: &ReportTo,
    html: Option<&grove::html::Selection>,
    json: bool,
    r: &Reports,
) -> anyhow::Result<ExitCode> {
    if let Some(selection) = html {
        let start = std::time::Instant::now();
        let page = grove::html::StudyPage {
            summary: &r.summary,
            what_if: r.what_if.as_ref(),
            sweep: r.sweep.as_ref(),
            charts: r.charts.clone(),
            replays: to.replays.clone(),
            overrides: &r.overrides,
            questionnaires: r.questionnaires.as_ref(),
        };
        let file = grove::html::write_study(&to.out, &page, &r.trials, selection)?;
        let bytes = std::fs::metadata(&file).map(|m| m.len()).unwrap_or(0);
        eprintln!(
            "study: {} ({:.1} MB) written in {:.1} s",
            file.display(),
            bytes as f64 / 1e6,
            start.elapsed().as_secs_f64()
        );
    }
    if json {
        crate::cli::print_json(&r.json)?;
    } else {
        print!("{}", r.text);
    }
    if let Some((n, wall)) = r.resimulated {
        eprintln!("study: {n} recordings re-simulated in {wall:.3} s");
    }
    Ok(if r.ok { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// `grove study --shard K/N --out PART`: the runs of this shard's recordings, as a partial result.
fn run_shard(
    args: &StudyArgs,
    shard: Shard,
    set: &SetArgs,
    files: &[PathBuf],
    base_files: Option<&[PathBuf]>,
) -> anyhow::Result<ExitCode> {
    let Some(out) = &args.out else { bail!("--shard {shard} writes a partial result: name its file with --out PART") };
    if out.is_dir() {
        bail!(
            "{}: is a folder; --shard writes a partial result file (merge them into a folder with grove study merge)",
            out.display()
        );
    }
    if out.exists() && !args.force {
        bail!("{}: already exists; use --force to replace it, or another --out", out.display());
    }
    let study = StudyKey { set: args.set.clone(), baseline: base_files.is_some() };
    let mine = shard.files(files);
    let base_mine = base_files.map(|b| shard.files(b));
    let runs = compute(set, &mine, base_mine.as_deref());
    let failed = runs
        .iter()
        .flat_map(|r| &r.trials)
        .filter(|t| matches!(t.status, grove::study::TrialStatus::Failed | grove::study::TrialStatus::Diverged))
        .count();
    let part = Partial { shard, study, replays: args.replays.display().to_string(), runs };
    write_atomic(out, &part.encode()?)?;
    let wall: f64 = part.runs.iter().map(|r| r.wall_seconds).sum();
    let runs = if part.runs.len() == 1 { "1 run".to_string() } else { format!("{} runs", part.runs.len()) };
    println!(
        "shard {shard}: {} of {} recordings ({runs}) in {wall:.3} s; partial result in {}",
        mine.len(),
        files.len(),
        out.display()
    );
    // A failed or diverged recording is a result like any other: the partial is written, and the
    // exit code says so, as a run without shards does.
    Ok(if failed == 0 { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// `--set`'s help.
const SET_HELP: &str = "What-if on the replayed hands: re-run the same input with a changed parameter and compare with the baseline, e.g. --set snap_threshold=0.2. Several comma-separated values sweep the parameter: --set snap_threshold=0.05,0.1,0.2,0.3,0.5.";

/// `--set`'s long help: the help, then every parameter with its default, range and unit (from
/// `Config::PARAMS`, the one list the parameters are declared in).
fn set_long_help() -> String {
    let mut help = format!("{SET_HELP}\n\nParameters (default, accepted range):");
    for p in grove_systems::resources::Config::PARAMS {
        let unit = p.unit_suffix();
        help.push_str(&format!(
            "\n  {:<24} {}{unit}, {} to {}{unit}: {}",
            p.name,
            p.default,
            p.min,
            p.max,
            p.doc.trim()
        ));
    }
    help
}
