//! `grove bench`: measure grove and print one JSON object.
//!
//! `grove bench` runs every benchmark but `render-reference` (a part of `render`),
//! `render-gpu` (which needs a real GPU), `grass` and `video` (long on a software rasteriser);
//! `grove bench sim raycast` runs only those named. Each benchmark is a function that returns a
//! JSON value; every figure is the median of several timed runs on one thread, in whatever
//! build (debug or release) the binary is.

use std::process::ExitCode;

use anyhow::anyhow;
use grove_systems::Sim;
use serde::Serialize;
use serde_json::{Value, json};

pub use super::bench_args::{median, time_ms, BenchArgs, Which};

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
                super::bench_suites::bench_reference(render)?,
            ),
            Which::RenderGpu => ("render_gpu", super::bench_suites::bench_gpu(render)?),
            Which::Water => ("water", super::bench_water::bench_water(render)?),
            Which::Grass => ("grass", super::bench_grass::bench_grass()?),
            Which::GrassGoals => ("grass_goals", super::bench_grass::bench_grass_goals()?),
            Which::RenderForest => ("render_forest", super::bench_impostor::bench_forest(render)?),
            Which::Park => ("park", super::bench_park::bench_park(render)?),
            Which::Video => ("video", super::bench_video::bench_video()?),
        };
        report.insert(name.into(), value);
    }
    super::print_json(&Value::Object(report))?;
    Ok(ExitCode::SUCCESS)
}
