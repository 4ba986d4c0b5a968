//! `grove synth`: generate synthetic study recordings (one per participant per task).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::bail;
use clap::Args;

use crate::study::synth::write_study;

/// Arguments of `grove synth`.
#[derive(Args)]
pub struct SynthArgs {
    /// Number of participants (each does both tasks).
    #[arg(long, default_value_t = 12)]
    pub participants: usize,
    /// The seed of the participants' skills, errors and simulations.
    #[arg(long, default_value_t = 2019)]
    pub seed: u64,
    /// The folder to write the recordings to (default replays/study; required with --set).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Overwrite recordings that already exist.
    #[arg(long)]
    pub force: bool,
    /// Re-simulated participants: the synthetic participants act again, closed-loop, under a
    /// changed parameter, e.g. --set snap_threshold=0.2. Compare with
    /// `grove study --replays OUT --baseline replays/study`.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
}

/// Runs `grove synth`.
pub fn run(args: SynthArgs) -> anyhow::Result<ExitCode> {
    if args.participants == 0 || args.participants > 999 {
        bail!("--participants {} must be between 1 and 999", args.participants);
    }
    let overrides = super::study::parse_overrides(&args.set)?;
    let out = match (&args.out, overrides.is_empty()) {
        (Some(o), _) => o.clone(),
        (None, true) => PathBuf::from("replays/study"),
        (None, false) => bail!("--set writes what-if recordings: give them their own folder with --out DIR"),
    };
    let written = write_study(&out, args.participants, args.seed, args.force, &overrides, &|what| eprintln!("synth: {what}"))?;
    println!("wrote {} recordings to {}", written.len(), out.display());
    if !overrides.is_empty() {
        println!("re-simulated participants under {}; compare with: grove study --replays {} --baseline replays/study", args.set.join(", "), out.display());
    }
    Ok(ExitCode::SUCCESS)
}
