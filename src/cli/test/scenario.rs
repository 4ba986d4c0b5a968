//! `grove scenario from-recording FILE --out SCENARIO`: draft a scenario file
//! (docs/scenarios.md) from a recorded session, for a person to edit.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{anyhow, bail};
use clap::Subcommand;
use grove::atomic_write::write_atomic;
use grove_systems::hash::hex;
use grove_systems::replay::{ReplayOptions, read_events, replay_file};
use grove_systems::scenario::draft::draft;

/// Subcommands of `grove scenario`.
#[derive(Subcommand)]
pub enum ScenarioCommand {
    /// Turn a recording into a scenario file: steps from its events, expectations drafted from
    /// the state they reach.
    FromRecording {
        /// The recording (JSON Lines, docs/replay-format.md).
        file: PathBuf,
        /// The scenario file to write (RON); never overwritten without --force.
        #[arg(long, value_name = "SCENARIO")]
        out: PathBuf,
        /// Replace an existing --out file.
        #[arg(long)]
        force: bool,
    },
}

/// Runs `grove scenario ...`.
pub fn run(cmd: ScenarioCommand) -> anyhow::Result<ExitCode> {
    match cmd {
        ScenarioCommand::FromRecording { file, out, force } => {
            if out.exists() && !force {
                bail!("{}: already exists (use --force to replace it)", out.display());
            }
            let (header, events) = read_events(&file).map_err(|e| anyhow!("{e}"))?;
            let replayed = replay_file(&file, &ReplayOptions::default()).map_err(|e| anyhow!("{e}"))?;
            let end = replayed.sim.tick();
            let final_hash = hex(replayed.sim.hash().total);
            let d = draft(&header, &events, file.parent(), &final_hash, end, &out)
                .map_err(|e| anyhow!("{}: {e}", file.display()))?;
            write_atomic(&out, d.text.as_bytes())?;
            println!(
                "{}: {} steps and {} expectations from {} events of {}",
                out.display(),
                d.steps,
                d.expectations,
                events.len(),
                file.display()
            );
            if !d.same_as_recording {
                println!(
                    "  note: the steps re-enact the session approximately (each step takes its own ticks); the expectations come from the draft's own run"
                );
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}
