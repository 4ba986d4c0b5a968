//! The benchmarks behind `grove bench` (the command is `cli/bench/`, which parses its
//! arguments, calls these and prints their JSON): each is a function that returns a JSON value;
//! every figure is the median of several timed runs, in whatever build (debug or release) the
//! binary is. The timing and process-measuring helpers they share are here.

pub mod aerial;
pub mod error;
pub mod grass;
pub mod impostor;
pub mod pairs;
pub mod park;
pub mod raycast;
pub mod render;
pub mod replay;
pub mod serve_idle;
pub mod suites;
pub mod video;
pub mod water;
pub mod wind;

pub use error::BenchError;

use std::path::{Path, PathBuf};
use std::time::Instant;

use grove_systems::scene::Scene;
use grove_systems::Sim;
use serde::Serialize;
use serde_json::Value;

/// What the simulation benchmarks run on.
#[derive(Clone, Debug)]
pub struct SimOptions {
    /// The scene file.
    pub scene: PathBuf,
    /// The tree counts of the tick benchmark.
    pub trees: Vec<usize>,
    /// Timed ticks per figure.
    pub ticks: u64,
}

/// A scene file, read and checked.
pub fn load_scene(path: &Path) -> Result<Scene, BenchError> {
    Ok(Scene::load(path).map_err(grove_systems::Error::from)?)
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

/// A memory figure of this process from `/proc/self/status` (`VmHWM` the peak, `VmRSS` now),
/// MiB; 0 where there is none (not Linux).
pub fn status_mib(key: &str) -> f64 {
    let status = grove_systems::files::read_text(Path::new("/proc/self/status"), grove_systems::files::Kind::Status).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix(key).and_then(|r| r.strip_prefix(':')))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(0.0, |kb| kb / 1024.0)
}

/// The CPU time this process has used so far, all threads, user and system, seconds. On a
/// machine shared with other work it says what a frame costs better than the wall clock does.
pub fn process_cpu_seconds() -> f64 {
    // SAFETY: getrusage only writes the struct it is given, which is plain data.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut usage) } != 0 {
        return 0.0;
    }
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    secs(usage.ru_utime) + secs(usage.ru_stime)
}

#[derive(Serialize)]
struct TickFigure {
    trees: usize,
    ms_per_tick_median: f64,
    ms_per_tick_min: f64,
    ms_per_tick_max: f64,
}

/// The simulation tick with each of `options.trees` trees scattered in the scene, animation
/// systems on.
pub fn bench_sim(options: &SimOptions) -> Result<Value, BenchError> {
    let scene = load_scene(&options.scene)?;
    let mut figures = Vec::new();
    for &n in &options.trees {
        eprintln!("bench: sim tick with {n} trees");
        let mut sim = Sim::from_scene(&scene, scene.seed).map_err(grove_systems::Error::from)?;
        sim.scatter_trees(n);
        sim.run(5);
        let mut times = time_ms(options.ticks.max(1) as usize, || sim.step());
        let min = times.iter().copied().fold(f64::MAX, f64::min);
        let max = times.iter().copied().fold(0.0, f64::max);
        figures.push(TickFigure { trees: n, ms_per_tick_median: median(&mut times), ms_per_tick_min: min, ms_per_tick_max: max });
    }
    Ok(serde_json::to_value(figures)?)
}
