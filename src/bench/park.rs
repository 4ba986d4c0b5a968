//! `grove bench park`: Fukuda et al. (2007)'s park table (their Table 5) on `assets/scenes/park.ron`
//! (lawns of shells and blades, a pond, trees) from the scene's own camera at 1280×720: the park
//! with nothing but ground, sky and trees; with grass; with grass and water; and with grass,
//! water and the sun's shadows. One row each, frame time and fps; on a real GPU the same rows
//! run inside `grove bench render-gpu`, with the passes' GPU times.
//!
//! The shares of the frame that grass and water take (issue #39's goals: at most 25 % and 10 %)
//! are timed apart from the rows, in interleaved pairs of frames (one without, one with, in
//! turn), so that a machine whose speed drifts while the rows run one after another, as a
//! shared one does, weighs on both halves of each pair alike: rows timed seconds apart gave the
//! water's share anywhere from -25 to +14 % on one build.

use std::path::Path;

use anyhow::anyhow;
use crate::render::offscreen::{self, Gpu};
use crate::render::Renderer;
use grove_systems::scene::Scene;
use grove_systems::Sim;
use serde_json::{json, Value};

use super::render::{setup, time_frames, RenderBenchOptions, HEIGHT, WIDTH};

/// A configuration of the table: grass, water, shadows.
type Config = (bool, bool, bool);

/// The park scene's file, relative to the repository root (where the benchmarks run).
pub const PARK: &str = "assets/scenes/park.ron";

/// The table's rows: name, grass, water, shadows.
const ROWS: [(&str, bool, bool, bool); 4] = [
    ("nothing", false, false, false),
    ("grass", true, false, false),
    ("grass_water", true, true, false),
    ("grass_water_shadows", true, true, true),
];

/// The park table with `gpu` and `renderer`: one row per configuration, `frames` frames each.
pub fn park_figures(gpu: &Gpu, renderer: &mut Renderer, frames: usize) -> anyhow::Result<Value> {
    let scene = Scene::load(Path::new(PARK)).map_err(|e| anyhow!("{PARK}: {e}"))?;
    let sim = Sim::from_scene(&scene, scene.seed).map_err(|e| anyhow!(e))?;
    crate::bank::load_for_scene(renderer, &scene, &[], &sim.res().catalogue).map_err(|e| anyhow!(e))?;
    let saved = renderer.options;
    let mut rows = serde_json::Map::new();
    for (name, grass, water, shadows) in ROWS {
        eprintln!("bench: park, {name}");
        renderer.options.grass = grass;
        renderer.options.water = water;
        renderer.options.shadows = shadows;
        let t = time_frames(gpu, renderer, &sim, frames)?;
        rows.insert(name.into(), t.json(renderer));
    }
    eprintln!("bench: park, the shares of grass and water in {frames} interleaved pairs of frames each");
    let grass_share = paired_share(gpu, renderer, &sim, frames, (false, false, false), (true, false, false));
    let water_share = paired_share(gpu, renderer, &sim, frames, (true, false, false), (true, true, false));
    renderer.options = saved;
    Ok(json!({
        "scene": PARK,
        "rows": rows,
        "grass_share_of_frame_percent": grass_share?,
        "water_share_of_frame_percent": water_share?,
        "shares": format!("the median over {frames} interleaved pairs of frames (nothing, grass; grass, grass and water) of (with - without) / with"),
    }))
}

/// Sets `renderer`'s grass, water and shadows to `config` and times one frame of `sim` into
/// `target`: wall time of the render and the wait for the device, milliseconds.
fn one_frame(gpu: &Gpu, renderer: &mut Renderer, sim: &Sim, target: &offscreen::Target, config: Config) -> anyhow::Result<f64> {
    (renderer.options.grass, renderer.options.water, renderer.options.shadows) = config;
    let t = std::time::Instant::now();
    renderer.render(sim, target.view())?;
    gpu.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| anyhow!("GPU poll failed ({e})"))?;
    Ok(t.elapsed().as_secs_f64() * 1e3)
}

/// The share of the frame, per cent, that `with` adds to `without`: `pairs` pairs of frames,
/// one of each in turn, after one of each to warm up ([`share_of_pairs`]).
fn paired_share(gpu: &Gpu, renderer: &mut Renderer, sim: &Sim, pairs: usize, without: Config, with: Config) -> anyhow::Result<f64> {
    let target = offscreen::Target::new(&gpu.device, WIDTH, HEIGHT);
    one_frame(gpu, renderer, sim, &target, without)?;
    one_frame(gpu, renderer, sim, &target, with)?;
    let mut times = Vec::with_capacity(pairs);
    for _ in 0..pairs.max(1) {
        let a = one_frame(gpu, renderer, sim, &target, without)?;
        let b = one_frame(gpu, renderer, sim, &target, with)?;
        times.push((a, b));
    }
    Ok(share_of_pairs(&times))
}

/// The median over `(without, with)` frame times of `(with - without) / with`, per cent; 0
/// without pairs. Each pair's frames ran one after the other, so a drift of the machine's speed
/// over the run moves both alike and the median of the pairs' shares stays.
pub fn share_of_pairs(pairs: &[(f64, f64)]) -> f64 {
    let mut shares: Vec<f64> = pairs.iter().filter(|(_, b)| *b > 0.0).map(|(a, b)| (b - a) / b * 100.0).collect();
    if shares.is_empty() {
        return 0.0;
    }
    super::median(&mut shares)
}

#[cfg(test)]
mod tests {
    use super::share_of_pairs;

    #[test]
    fn a_share_is_the_median_of_the_pairs_and_survives_a_drift() {
        // Water adds 10 ms to a 90 ms frame (10 % of 100), while the machine slows down over the
        // run: each pair's frames slow alike, the pairs' shares stay near 10 %.
        let pairs: Vec<(f64, f64)> = (0..9).map(|k| (90.0 * (1.0 + 0.1 * k as f64), 100.0 * (1.0 + 0.1 * k as f64))).collect();
        assert!((share_of_pairs(&pairs) - 10.0).abs() < 1e-9);
        // Timing the rows apart, the first half of the run without and the second with, would
        // have given far more: the drift counted as water.
        let apart = (pairs[6].1 - pairs[2].0) / pairs[6].1 * 100.0;
        assert!(apart > 30.0, "{apart}");
        // One pair disturbed by another process does not move the median.
        let mut noisy = pairs.clone();
        noisy[4] = (300.0, 100.0);
        assert!((share_of_pairs(&noisy) - 10.0).abs() < 1e-9);
        // A share is negative where the extra costs nothing and noise falls the other way; no
        // pairs give 0.
        assert!(share_of_pairs(&[(100.0, 95.0)]) < 0.0);
        assert_eq!(share_of_pairs(&[]), 0.0);
    }
}

/// Runs `grove bench park` on whatever adapter wgpu picks (lavapipe here).
pub fn bench_park(options: RenderBenchOptions) -> anyhow::Result<Value> {
    let (gpu, mut renderer, adapter) = setup(options, false)?;
    let figures = park_figures(&gpu, &mut renderer, 10)?;
    Ok(json!({"adapter": adapter, "resolution": [WIDTH, HEIGHT], "timing": super::render::WALL_TIMING, "park": figures}))
}
