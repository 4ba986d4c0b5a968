//! Replays a recording several times in one process, headless, and prints the median speed as
//! JSON: the native side of the WebAssembly module's replay figure (`web/bench.mjs` runs it and
//! the module in turn on the same file; `docs/wasm.md`).
//!
//! ```text
//! cargo run --release -p grove-systems --example replay_speed -- FILE [RUNS]
//! ```
//!
//! RUNS defaults to 7. It prints `{"sim_seconds", "wall_ms_median", "speedup_median",
//! "verified", "runs"}`. Bad arguments or a bad recording give one line on stderr and exit 2.

use std::process::ExitCode;
use std::time::Instant;

use grove_systems::replay::{ReplayOptions, replay_reader};
use grove_systems::task::ticks_to_seconds;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(file), runs) = (args.first(), args.get(1).map(|r| r.parse::<usize>())) else {
        eprintln!("usage: replay_speed FILE [RUNS]");
        return ExitCode::from(2);
    };
    let runs = match runs {
        None => 7,
        Some(Ok(n)) if (1..=1000).contains(&n) => n,
        Some(_) => {
            eprintln!("replay_speed: RUNS must be a whole number from 1 to 1000");
            return ExitCode::from(2);
        }
    };
    let bytes = match grove_systems::files::read(std::path::Path::new(file), grove_systems::files::Kind::Recording) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("replay_speed: {file}: {}", e.reason());
            return ExitCode::from(2);
        }
    };
    let (mut walls, mut verified, mut sim_seconds) = (Vec::new(), true, 0.0);
    for _ in 0..runs {
        let t = Instant::now();
        let outcome = match replay_reader(&bytes[..], file, None, &ReplayOptions::default()) {
            Ok(o) => o,
            Err(e) => {
                eprintln!("replay_speed: {e}");
                return ExitCode::from(2);
            }
        };
        walls.push(t.elapsed().as_secs_f64());
        let s = outcome.sim.snapshot();
        sim_seconds = ticks_to_seconds(s.tick, s.dt);
        verified &= outcome.complete && outcome.first_divergence.is_none() && outcome.checkpoints_checked > 0;
    }
    walls.sort_by(f64::total_cmp);
    let wall = walls[walls.len() / 2];
    println!(
        "{}",
        serde_json::json!({ "sim_seconds": sim_seconds, "wall_ms_median": (wall * 1e5).round() / 100.0, "speedup_median": (sim_seconds / wall).round(), "verified": verified, "runs": runs })
    );
    ExitCode::SUCCESS
}
