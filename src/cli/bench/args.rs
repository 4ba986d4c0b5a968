//! The arguments of `grove bench` (the benchmarks themselves are `grove::bench`).

use std::path::PathBuf;

use clap::{Args, ValueEnum};

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
    /// A 5-minute session written as a 1280x720, 30 fps H.264 video (9,000 frames), with the
    /// memory every 1,000 frames.
    Video,
    /// Six study recordings pushed to two grove serve processes of its own, one holding 600
    /// idle connections: the median push of each and their ratio (goal: at most 2).
    ServeIdle,
}

/// Arguments of `grove bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// Which benchmarks to run (default: all).
    #[arg(value_enum)]
    pub which: Vec<Which>,
    /// The scene of the benchmarks that take one: sim, wind and raycast (default
    /// assets/scenes/study.ron), park (default assets/scenes/park.ron) and render-forest
    /// (default assets/scenes/forest.ron). The others draw scenes of their own.
    #[arg(long)]
    pub scene: Option<PathBuf>,
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

impl Which {
    /// Whether the benchmark runs on `--scene`.
    pub fn takes_scene(self) -> bool {
        matches!(self, Which::Sim | Which::Wind | Which::Raycast | Which::Park | Which::RenderForest)
    }
}

/// A value that is not a finite number of at least 0: the text as given.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("expected a number of at least 0, got {0:?}")]
pub struct NotNonNegative(pub String);

/// Parses a finite number of at least 0 (a clap value parser).
pub fn non_negative(s: &str) -> Result<f32, NotNonNegative> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(NotNonNegative(s.to_string())),
    }
}
