//! `grove synth`: generate synthetic study recordings (one per participant per task).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{anyhow, bail};
use clap::Args;

use grove::study::shard::Shard;
use grove::study::synth::{conditions, write_conditions, write_study};
use grove_systems::set_arg::{SetArg, SetArgs};

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
    pub set: Vec<SetArg>,
    /// The conditions, comma-separated registered techniques (e.g.
    /// ray-casting,manual,gaze-dwell; docs/techniques.md), in a balanced Latin square order per
    /// participant. Default: ray-casting,manual. Needs --out.
    #[arg(long, value_delimiter = ',', value_name = "NAMES")]
    pub techniques: Vec<String>,
    /// Write only shard K of N (1 ≤ K ≤ N): the participants whose id (P07) hashes (XXH3) to K,
    /// both of their recordings, exactly as a run without shards writes them; the recordings
    /// `grove study --shard K/N` re-simulates (docs/scale.md).
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
}

/// Runs `grove synth`.
pub fn run(args: SynthArgs) -> anyhow::Result<ExitCode> {
    if args.participants == 0 || args.participants > 999 {
        bail!("--participants {} must be between 1 and 999", args.participants);
    }
    let overrides = SetArgs::single_values(&args.set).map_err(|e| anyhow!("--set {e}"))?;
    if !args.techniques.is_empty() && args.out.is_none() {
        bail!("--techniques writes a study of its own: give it a folder with --out DIR");
    }
    let shard: Option<Shard> = args.shard.as_deref().map(str::parse).transpose().map_err(|e| anyhow!("--shard {e}"))?;
    let out = match (&args.out, overrides.is_empty()) {
        (Some(o), _) => o.clone(),
        (None, true) => PathBuf::from("replays/study"),
        (None, false) => bail!("--set writes what-if recordings: give them their own folder with --out DIR"),
    };
    let progress = |what: &str| eprintln!("synth: {what}");
    let written = if args.techniques.is_empty() {
        write_study(&out, args.participants, args.seed, args.force, &overrides, shard, &progress)?
    } else {
        let names: Vec<&str> = args.techniques.iter().map(|s| s.as_str()).collect();
        write_conditions(
            &out,
            &conditions(&names)?,
            args.participants,
            args.seed,
            args.force,
            &overrides,
            shard,
            &progress,
        )?
    };
    match shard {
        Some(s) => println!("wrote {} recordings (shard {s}) to {}", written.len(), out.display()),
        None => println!("wrote {} recordings to {}", written.len(), out.display()),
    }
    if !overrides.is_empty() {
        println!(
            "re-simulated participants under {}; compare with: grove study --replays {} --baseline replays/study",
            args.set.iter().map(SetArg::to_string).collect::<Vec<_>>().join(", "),
            out.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}
