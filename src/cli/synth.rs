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
    /// The folder to write the recordings to.
    #[arg(long, default_value = "replays/study")]
    pub out: PathBuf,
    /// Overwrite recordings that already exist.
    #[arg(long)]
    pub force: bool,
}

/// Runs `grove synth`.
pub fn run(args: SynthArgs) -> anyhow::Result<ExitCode> {
    if args.participants == 0 || args.participants > 999 {
        bail!("--participants {} must be between 1 and 999", args.participants);
    }
    let written = write_study(&args.out, args.participants, args.seed, args.force, &|what| eprintln!("synth: {what}"))?;
    println!("wrote {} recordings to {}", written.len(), args.out.display());
    Ok(ExitCode::SUCCESS)
}
