//! `grove bench raycast`: the cost of one controller ray against the study planes and 10k trees.
//!
//! The trees are scattered over the study scene's planes (grounded where there is a plane), and
//! the rays start at head height (1.7 m) above random points of the planes' bounding rectangle,
//! aimed at other random ground points of it. The points come from a fixed splitmix64 sequence,
//! so every run casts the same rays. Each ray is one `SpatialIndex::cast` (planes and trees, the
//! query the raycast system makes every tick); the figure is the median, over several batches,
//! of the mean time per ray in a batch.

use glam::Vec3;
use grove_systems::Sim;
use serde::Serialize;
use serde_json::Value;

use super::{BenchError, SimOptions, median, time_ms};

/// Trees in the raycast benchmark.
pub const RAYCAST_TREES: usize = 10_000;
/// Rays per batch.
pub const RAYS: usize = 4_096;
/// Timed batches.
pub const BATCHES: usize = 15;

#[derive(Serialize)]
struct RaycastFigure {
    trees: usize,
    planes: usize,
    plane_triangles: usize,
    rays_per_batch: usize,
    batches: usize,
    hits: usize,
    tree_hits: usize,
    ns_per_ray_median: f64,
    ns_per_ray_min: f64,
    ns_per_ray_max: f64,
    goal_ns_per_ray: f64,
    planes_only_ns_per_ray_median: f64,
    trees_only_ns_per_ray_median: f64,
}

/// A splitmix64 step: a fixed, well-mixed sequence of 64-bit numbers.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A number in [0, 1) from the sequence.
fn unit(state: &mut u64) -> f32 {
    (splitmix(state) >> 40) as f32 / (1u64 << 24) as f32
}

/// Runs the raycast benchmark.
pub fn bench_raycast(args: &SimOptions) -> Result<Value, BenchError> {
    let scene = super::load_scene(&args.scene)?;
    eprintln!("bench: raycast with {RAYCAST_TREES} trees");
    let mut sim = Sim::from_scene(&scene, scene.seed).map_err(grove_systems::Error::from)?;
    sim.scatter_trees(RAYCAST_TREES);
    let (mut min, mut max) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    let (mut planes, mut plane_triangles) = (0, 0);
    sim.for_each_plane(|_, p| {
        planes += 1;
        plane_triangles += p.triangles.len();
        for v in &p.vertices {
            min = min.min(*v);
            max = max.max(*v);
        }
    });
    let mut state = 0x6772_6f76_6521_u64;
    let mut point =
        |y: f32| Vec3::new(min.x + (max.x - min.x) * unit(&mut state), y, min.z + (max.z - min.z) * unit(&mut state));
    let rays: Vec<(Vec3, Vec3)> = (0..RAYS)
        .map(|_| {
            let from = point(1.7);
            let to = point(0.0);
            (from, (to - from).normalize_or(Vec3::NEG_Y))
        })
        .collect();
    let spatial = sim.spatial();
    let max_len = sim.config().max_ray_length;
    let (mut hits, mut tree_hits) = (0, 0);
    for (o, d) in &rays {
        if let Some(h) = spatial.cast(*o, *d, max_len, None) {
            hits += 1;
            if sim.tree(h.entity.to_bits().get()).is_some() {
                tree_hits += 1;
            }
        }
    }
    let mut sink = 0.0f32;
    let mut times = time_ms(BATCHES, || {
        for (o, d) in &rays {
            if let Some(h) = spatial.cast(*o, *d, max_len, None) {
                sink += h.distance;
            }
        }
    });
    let per_ray = |mut t: Vec<f64>| {
        for x in t.iter_mut() {
            *x *= 1e6 / RAYS as f64;
        }
        median(&mut t)
    };
    let planes_only = per_ray(time_ms(BATCHES, || {
        for (o, d) in &rays {
            if let Some(h) = spatial.cast_planes(*o, *d, max_len) {
                sink += h.distance;
            }
        }
    }));
    let trees_only = per_ray(time_ms(BATCHES, || {
        for (o, d) in &rays {
            if let Some(h) = spatial.cast_trees(*o, *d, max_len, None) {
                sink += h.distance;
            }
        }
    }));
    std::hint::black_box(sink);
    for t in times.iter_mut() {
        *t *= 1e6 / RAYS as f64;
    }
    let lo = times.iter().copied().fold(f64::MAX, f64::min);
    let hi = times.iter().copied().fold(0.0, f64::max);
    Ok(serde_json::to_value(RaycastFigure {
        trees: spatial.tree_count(),
        planes,
        plane_triangles,
        rays_per_batch: RAYS,
        batches: BATCHES,
        hits,
        tree_hits,
        ns_per_ray_median: median(&mut times),
        ns_per_ray_min: lo,
        ns_per_ray_max: hi,
        goal_ns_per_ray: 2000.0,
        planes_only_ns_per_ray_median: planes_only,
        trees_only_ns_per_ray_median: trees_only,
    })?)
}
