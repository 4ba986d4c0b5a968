//! `grove sim`: run a scene headless with no input and print its world hash.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::anyhow;
use clap::Args;
use grove_systems::Sim;
use grove_systems::hash::hex;
use grove_systems::sim::EntityCounts;
use serde::Serialize;

/// Arguments of `grove sim`.
#[derive(Args)]
pub struct SimArgs {
    /// The scene file (RON), e.g. assets/scenes/study.ron.
    #[arg(long)]
    pub scene: PathBuf,
    /// Number of fixed steps to run.
    #[arg(long, default_value_t = 600)]
    pub ticks: u64,
    /// Scatter this many extra trees over the planes, for scale tests.
    #[arg(long, default_value_t = 0)]
    pub trees: usize,
    /// The RNG seed (default: the scene's seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// A model-bank folder (repeatable) whose models the scene may name; GROVE_BANK's folders
    /// come after these.
    #[arg(long = "bank", value_name = "DIR")]
    pub banks: Vec<PathBuf>,
}

#[derive(Serialize)]
struct SimReport {
    scene: String,
    ticks: u64,
    hash: String,
    entities: EntityCounts,
    wall_seconds: f64,
}

/// Runs `grove sim`.
pub fn run(args: SimArgs) -> anyhow::Result<ExitCode> {
    let scene = crate::cli::load_scene(&args.scene)?;
    if args.ticks > grove_systems::limits::MAX_TICKS {
        return Err(anyhow!(
            "--ticks {} is past the limit of {} ticks ({})",
            args.ticks,
            grove_systems::limits::MAX_TICKS,
            grove_systems::limits::RAISE
        ));
    }
    if args.trees > 5_000_000 {
        return Err(anyhow!("--trees {} is more than 5,000,000", args.trees));
    }
    let seed = args.seed.unwrap_or(scene.seed);
    let banks =
        grove::bank::open_for_scene(&scene, &args.banks).map_err(|e| anyhow!("{}: {e}", args.scene.display()))?;
    let (catalogue, _) = banks.session_catalogue().map_err(|e| anyhow!(e))?;
    let mut sim =
        Sim::from_scene_with(&scene, seed, catalogue).map_err(|e| anyhow!("{}: {e}", args.scene.display()))?;
    sim.scatter_trees(args.trees);
    let start = Instant::now();
    sim.run(args.ticks);
    let wall_seconds = start.elapsed().as_secs_f64();
    let report = SimReport {
        scene: args.scene.display().to_string(),
        ticks: sim.tick(),
        hash: hex(sim.hash().total),
        entities: sim.counts(),
        wall_seconds,
    };
    if args.json {
        crate::cli::print_json(&report)?;
    } else {
        println!(
            "{}: {} ticks, {} trees, {} planes, hash {} ({:.3} s)",
            report.scene, report.ticks, report.entities.trees, report.entities.planes, report.hash, report.wall_seconds
        );
    }
    Ok(ExitCode::SUCCESS)
}
