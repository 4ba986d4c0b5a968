//! `grove bench wind`: the wind and sun systems' tick for 100k trees.
//!
//! Builds the benchmark scene, scatters 100,000 trees, gives the sun a time rate of 60 (if the
//! scene's is 0) so that SPA runs every tick, then times `systems::wind::run` and
//! `systems::sun::run` together, and each alone, on one thread. The goal is 1.5 ms per tick in
//! a release build.

use grove_systems::Sim;
use serde_json::{Value, json};

use super::{BenchError, SimOptions, median, time_ms};

/// Trees in the wind benchmark.
pub const WIND_BENCH_TREES: usize = 100_000;

/// Runs the wind and sun benchmark and returns its figures.
pub fn bench_wind(args: &SimOptions) -> Result<Value, BenchError> {
    let mut scene = super::load_scene(&args.scene)?;
    if scene.sun.time_rate == 0.0 {
        scene.sun.time_rate = 60.0;
    }
    eprintln!("bench: wind and sun tick with {WIND_BENCH_TREES} trees");
    let mut sim = Sim::from_scene(&scene, scene.seed).map_err(grove_systems::Error::from)?;
    sim.scatter_trees(WIND_BENCH_TREES);
    let ticks = args.ticks.max(1) as usize;
    let mut set_up = sim.set_up();
    // Warm the caches, then time both systems together and each alone, advancing the tick
    // counter as the schedule would.
    for _ in 0..5 {
        set_up.run_wind_and_sun(true, true);
    }
    let mut both = time_ms(ticks, || {
        set_up.run_wind_and_sun(true, true);
    });
    let mut wind_only = time_ms(ticks, || {
        set_up.run_wind_and_sun(true, false);
    });
    let mut sun_only = time_ms(ticks, || {
        set_up.run_wind_and_sun(false, true);
    });
    Ok(json!({
        "trees": WIND_BENCH_TREES,
        "ticks": ticks,
        "wind_sun_ms_per_tick_median": median(&mut both),
        "wind_ms_per_tick_median": median(&mut wind_only),
        "sun_ms_per_tick_median": median(&mut sun_only),
        "goal_ms": 1.5,
    }))
}
