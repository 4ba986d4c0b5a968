//! Prints the world hash of a scene after a number of ticks with no input, as `grove sim --json`
//! reports it, from the headless crate alone. `scripts/test` runs it in a release build and
//! compares the hash with the debug `grove sim`: the same simulation code optimised and not,
//! without a release build of the whole app.
//!
//! ```text
//! cargo run --release -p grove-systems --example world_hash -- [SCENE] [TICKS]
//! ```
//!
//! SCENE defaults to `assets/scenes/study.ron`, TICKS to 600. Bad arguments or an unreadable
//! scene give one line on stderr and exit code 2.

use std::path::PathBuf;
use std::process::ExitCode;

use grove_systems::Sim;
use grove_systems::hash::hex;
use grove_systems::scene::Scene;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let scene = PathBuf::from(args.next().unwrap_or_else(|| "assets/scenes/study.ron".into()));
    let ticks = match args.next().map(|t| t.parse::<u64>()) {
        None => 600,
        Some(Ok(t)) if t <= grove_systems::limits::MAX_TICKS => t,
        Some(_) => {
            eprintln!("world_hash: TICKS must be a whole number up to {}", grove_systems::limits::MAX_TICKS);
            return ExitCode::from(2);
        }
    };
    let built = Scene::load(&scene)
        .map_err(|e| e.to_string())
        .and_then(|s| Sim::from_scene(&s, s.seed).map_err(|e| e.to_string()));
    let mut sim = match built {
        Ok(sim) => sim,
        Err(e) => {
            eprintln!("world_hash: {}: {e}", scene.display());
            return ExitCode::from(2);
        }
    };
    // As `grove sim` does (no extra trees; it also builds the spatial index first).
    sim.scatter_trees(0);
    sim.run(ticks);
    println!(
        "{{\"scene\": \"{}\", \"ticks\": {}, \"hash\": \"{}\"}}",
        scene.display(),
        sim.tick(),
        hex(sim.hash().total)
    );
    ExitCode::SUCCESS
}
