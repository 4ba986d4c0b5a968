//! `grove bench`: measure grove and print one JSON object.
//!
//! `grove bench` runs every benchmark but `render-reference` (a part of `render`),
//! `render-gpu` (which needs a real GPU), `grass` and `video` (long on a software rasteriser);
//! `grove bench sim raycast` runs only those named. The benchmarks are `grove::bench`'s: each
//! is a function that returns a JSON value, every figure the median of several timed runs on
//! one thread, in whatever build (debug or release) the binary is.

pub mod args;

use std::process::ExitCode;

use grove::bench::{self, SimOptions};
use serde_json::{json, Value};

pub use args::{BenchArgs, Which};

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
    if args.scene.is_some() && !which.iter().any(|w| w.takes_scene()) {
        anyhow::bail!("--scene is used only by the sim, wind, raycast, park and render-forest benchmarks");
    }
    let scene = args.scene.as_deref();
    let study = grove::render::default_assets_dir().join("scenes/study.ron");
    let sim = SimOptions { scene: scene.map_or(study, std::path::Path::to_path_buf), trees: args.trees.clone(), ticks: args.ticks };
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
    let render = bench::render::RenderBenchOptions {
        shadow_size: args.shadow_size,
        leaf_pixels: args.leaf_pixels,
        impostor_pixels: args.impostor_pixels,
    };
    for w in which {
        let (name, value) = match w {
            Which::Sim => ("sim_tick", bench::bench_sim(&sim)?),
            Which::Replay => ("replay", bench::replay::bench_replay()?),
            Which::Study => ("study", bench::replay::bench_study()?),
            Which::Wind => ("wind_sun_tick", bench::wind::bench_wind(&sim)?),
            Which::Raycast => ("raycast", bench::raycast::bench_raycast(&sim)?),
            Which::Render => ("render", bench::render::bench_render(render)?),
            Which::RenderReference => (
                "render_reference",
                bench::suites::bench_reference(render)?,
            ),
            Which::RenderGpu => ("render_gpu", bench::suites::bench_gpu(render)?),
            Which::Water => ("water", bench::water::bench_water(render)?),
            Which::Grass => ("grass", bench::grass::bench_grass()?),
            Which::GrassGoals => ("grass_goals", bench::grass::bench_grass_goals()?),
            Which::RenderForest => ("render_forest", bench::impostor::bench_forest(render, scene)?),
            Which::Park => ("park", bench::park::bench_park(render, scene)?),
            Which::Video => ("video", bench::video::bench_video()?),
            Which::ServeIdle => {
                let grove = std::env::current_exe()?;
                ("serve_idle", bench::serve_idle::bench_serve_idle(&grove)?)
            }
        };
        report.insert(name.into(), value);
    }
    crate::cli::print_json(&Value::Object(report))?;
    Ok(ExitCode::SUCCESS)
}
