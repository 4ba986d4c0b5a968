//! `grove bench`: measure grove and print one JSON object.
//!
//! `grove bench` runs every benchmark but `render-reference` (a part of `render`),
//! `render-gpu` (which needs a real GPU) and `grass` (long on a software rasteriser);
//! `grove bench sim raycast` runs only those named. Each benchmark is a function that returns a
//! JSON value; every figure is the median of several timed runs on one thread, in whatever
//! build (debug or release) the binary is.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::anyhow;
use clap::{Args, ValueEnum};
use grove_systems::Sim;
use serde::Serialize;
use serde_json::{Value, json};

/// The benchmarks `grove bench` knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Which {
    /// The simulation tick with 1k to 1M trees, animation systems on.
    Sim,
    /// Replay speed of a 5-minute session.
    Replay,
    /// The whole study: 24 recordings re-simulated, verified and reported.
    Study,
    /// The wind and sun systems' tick for 100k trees.
    Wind,
    /// One controller ray against the study planes and 10k trees.
    Raycast,
    /// Offscreen frame times at 1280x720: the 100-tree reference scene and cost per model.
    Render,
    /// Only the 100-tree reference scene of the render benchmark, shadows on and off.
    RenderReference,
    /// Grass: Fukuda et al.'s 1 km² shell field with and without grass, and 10k to 1M blades at
    /// 640x360 and 1280x720.
    Grass,
    /// Only the grass goals: 65,536 blades all in view at 640x360 (at most 33 ms) and Fukuda et
    /// al.'s 1 km² shell field at 1280x720, each with and without grass.
    GrassGoals,
    /// The reference scene, a 10k-tree forest, the water test and grass on a real GPU, and the
    /// forest scene and a million trees at 1920x1080, timed with timestamp queries (fails on a
    /// software adapter such as lavapipe).
    RenderGpu,
    /// Fukuda et al.'s water test: 500 m of water 50 m deep under the sky, with and without
    /// water, at 1280x720.
    Water,
    /// The 10,000-tree forest of assets/scenes/forest.ron at 1280x720, shadows on and off.
    RenderForest,
    /// Fukuda et al.'s park table on assets/scenes/park.ron at 1280x720: nothing, grass, grass
    /// and water, grass, water and shadows.
    Park,
}

/// Arguments of `grove bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// Which benchmarks to run (default: all).
    #[arg(value_enum)]
    pub which: Vec<Which>,
    /// The scene used by the benchmarks.
    #[arg(long, default_value = "assets/scenes/study.ron")]
    pub scene: PathBuf,
    /// Tree counts for the sim tick benchmark (comma-separated).
    #[arg(long, value_delimiter = ',', default_values_t = vec![1_000usize, 10_000, 100_000, 1_000_000])]
    pub trees: Vec<usize>,
    /// Ticks timed per tree count.
    #[arg(long, default_value_t = 120)]
    pub ticks: u64,
    /// Shadow-map edge in texels for the render benchmarks.
    #[arg(long, default_value_t = grove::render::RenderOptions::default().shadow_size)]
    pub shadow_size: u32,
    /// Leaf pixel budget of the foliage level of detail for the render benchmarks (0: every
    /// leaf at every distance).
    #[arg(long, default_value_t = grove::render::RenderOptions::default().leaf_pixels)]
    pub leaf_pixels: f32,
    /// On-screen size in pixels below which trees are drawn as impostors in the render
    /// benchmarks (0: every tree a mesh).
    #[arg(long, default_value_t = grove::render::DEFAULT_IMPOSTOR_PIXELS, value_parser = non_negative)]
    pub impostor_pixels: f32,
}

/// Parses a finite number of at least 0 (a clap value parser).
pub fn non_negative(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("expected a number of at least 0, got {s:?}")),
    }
}

/// The median of a slice of timings (sorted in place); 0 for an empty slice.
pub fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Times `f` `n` times and returns the per-call durations in milliseconds.
pub fn time_ms(n: usize, mut f: impl FnMut()) -> Vec<f64> {
    (0..n)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect()
}

#[derive(Serialize)]
struct TickFigure {
    trees: usize,
    ms_per_tick_median: f64,
    ms_per_tick_min: f64,
    ms_per_tick_max: f64,
}

fn bench_sim(args: &BenchArgs) -> anyhow::Result<Value> {
    let scene = super::load_scene(&args.scene)?;
    let mut figures = Vec::new();
    for &n in &args.trees {
        eprintln!("bench: sim tick with {n} trees");
        let mut sim = Sim::from_scene(&scene, scene.seed).map_err(|e| anyhow!("{e}"))?;
        sim.scatter_trees(n);
        sim.run(5);
        let mut times = time_ms(args.ticks.max(1) as usize, || sim.step());
        let min = times.iter().copied().fold(f64::MAX, f64::min);
        let max = times.iter().copied().fold(0.0, f64::max);
        figures.push(TickFigure {
            trees: n,
            ms_per_tick_median: median(&mut times),
            ms_per_tick_min: min,
            ms_per_tick_max: max,
        });
    }
    Ok(serde_json::to_value(figures)?)
}

/// Runs `grove bench`.
pub fn run(args: BenchArgs) -> anyhow::Result<ExitCode> {
    let all = [
        Which::Sim,
        Which::Raycast,
        Which::Wind,
        Which::Replay,
        Which::Study,
        Which::Render,
        Which::Water,
    ];
    let which: Vec<Which> = if args.which.is_empty() {
        all.to_vec()
    } else {
        args.which.clone()
    };
    let mut report = serde_json::Map::new();
    report.insert(
        "build".into(),
        json!(if cfg!(debug_assertions) {
            "debug"
        } else {
            "release"
        }),
    );
    report.insert("threads".into(), json!(1));
    let render = super::bench_render::RenderBenchOptions {
        shadow_size: args.shadow_size,
        leaf_pixels: args.leaf_pixels,
        impostor_pixels: args.impostor_pixels,
    };
    for w in which {
        let (name, value) = match w {
            Which::Sim => ("sim_tick", bench_sim(&args)?),
            Which::Replay => ("replay", super::bench_replay::bench_replay()?),
            Which::Study => ("study", super::bench_replay::bench_study()?),
            Which::Wind => ("wind_sun_tick", super::bench_wind::bench_wind(&args)?),
            Which::Raycast => ("raycast", super::bench_raycast::bench_raycast(&args)?),
            Which::Render => ("render", super::bench_render::bench_render(render)?),
            Which::RenderReference => (
                "render_reference",
                super::bench_render::bench_reference(render)?,
            ),
            Which::RenderGpu => ("render_gpu", super::bench_render::bench_gpu(render)?),
            Which::Water => ("water", super::bench_water::bench_water(render)?),
            Which::Grass => ("grass", super::bench_grass::bench_grass()?),
            Which::GrassGoals => ("grass_goals", super::bench_grass::bench_grass_goals()?),
            Which::RenderForest => ("render_forest", super::bench_impostor::bench_forest(render)?),
            Which::Park => ("park", super::bench_park::bench_park(render)?),
        };
        report.insert(name.into(), value);
    }
    super::print_json(&Value::Object(report))?;
    Ok(ExitCode::SUCCESS)
}
