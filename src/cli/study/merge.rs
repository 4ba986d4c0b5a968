//! `grove study merge PART… --out DIR`: the partial results of every shard of a study
//! (`grove study --shard K/N --out PART`) put together into the reports a run without shards
//! writes: the same CSV and JSON, apart from the timing fields (`wall_seconds`, here the sum of
//! the shards' seconds).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use grove::study::assign_order;
use grove::study::shard::{Partial, combine};
use grove::study::write::{ReportTo, prepare_out, write_reports};
use grove_systems::set_arg::SetArgs;

/// Arguments of `grove study merge`.
#[derive(Args)]
pub struct MergeArgs {
    /// The partial results, one per shard (any order; every shard of 1..N exactly once).
    #[arg(required = true, value_name = "PART")]
    pub parts: Vec<PathBuf>,
    /// Where the reports go (as for `grove study --out`).
    #[arg(long, default_value = "target/study")]
    pub out: PathBuf,
    /// Print the summary as JSON on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Replace the reports of an earlier run in --out.
    #[arg(long)]
    pub force: bool,
}

/// Runs `grove study merge`.
pub fn run(args: MergeArgs) -> anyhow::Result<ExitCode> {
    let names: Vec<String> = args.parts.iter().map(|p| p.display().to_string()).collect();
    let parts = args.parts.iter().map(|p| Partial::read(p)).collect::<Result<Vec<_>, _>>()?;
    let (study, replays, mut runs) = combine(parts, &names)?;
    if runs.first().is_none_or(|r| r.trials.is_empty()) {
        anyhow::bail!("{}: no recordings in any of the shards (as grove study refuses a folder without any)", replays);
    }
    let set = SetArgs::new(&study.set).map_err(|e| anyhow::anyhow!("--set {e}"))?;
    prepare_out(&args.out, args.force)?;
    for r in &mut runs {
        assign_order(&mut r.trials);
    }
    let to = ReportTo { out: args.out, replays, baseline: study.baseline, html: false, questionnaires: None };
    let reports = write_reports(&to, &set, runs)?;
    super::show(&to, None, args.json, &reports)
}
