//! `grove bench`: measure the simulation and print JSON.
//!
//! Every figure is the median of several timed runs on one thread.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::anyhow;
use clap::Args;
use grove_systems::Sim;
use serde::Serialize;

/// Arguments of `grove bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// The scene the trees are scattered over.
    #[arg(long, default_value = "assets/scenes/study.ron")]
    pub scene: PathBuf,
    /// Tree counts to measure the tick at (comma-separated).
    #[arg(long, value_delimiter = ',', default_values_t = vec![1_000usize, 10_000, 100_000, 1_000_000])]
    pub trees: Vec<usize>,
    /// Ticks timed per tree count.
    #[arg(long, default_value_t = 120)]
    pub ticks: u64,
}

#[derive(Serialize)]
struct TickFigure {
    trees: usize,
    ms_per_tick_median: f64,
    ms_per_tick_min: f64,
    ms_per_tick_max: f64,
}

#[derive(Serialize)]
struct BenchReport {
    build: &'static str,
    threads: usize,
    sim_tick: Vec<TickFigure>,
}

/// The median of a slice of timings (sorted in place).
pub fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Runs `grove bench`.
pub fn run(args: BenchArgs) -> anyhow::Result<ExitCode> {
    let scene = super::load_scene(&args.scene)?;
    let mut sim_tick = Vec::new();
    for &n in &args.trees {
        eprintln!("bench: sim tick with {n} trees");
        let mut sim = Sim::from_scene(&scene, scene.seed).map_err(|e| anyhow!("{e}"))?;
        sim.scatter_trees(n);
        sim.run(5);
        let mut times: Vec<f64> = (0..args.ticks.max(1))
            .map(|_| {
                let t = Instant::now();
                sim.step();
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        let min = times.iter().copied().fold(f64::MAX, f64::min);
        let max = times.iter().copied().fold(0.0, f64::max);
        sim_tick.push(TickFigure { trees: n, ms_per_tick_median: median(&mut times), ms_per_tick_min: min, ms_per_tick_max: max });
    }
    let report = BenchReport {
        build: if cfg!(debug_assertions) { "debug" } else { "release" },
        threads: 1,
        sim_tick,
    };
    super::print_json(&report)?;
    Ok(ExitCode::SUCCESS)
}
