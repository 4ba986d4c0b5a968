//! Runs scenario files as `grove test` does and writes each run as a recording (its steps
//! turned into input events, with checkpoints and footer), so that another build of the
//! simulation (the WebAssembly module under Node, `web/sim/tests/`) can drive the same events
//! and compare the world hash a scenario pins.
//!
//! ```text
//! cargo run -p grove-systems --example scenario_recording -- OUT_DIR [SCENARIO.ron…]
//! ```
//!
//! The scenarios default to every `.ron` file in `tests/scenarios/`. It prints one JSON object
//! a line: `{"scenario": FILE, "recording": OUT_DIR/NAME.jsonl, "hashes": [the world hashes its
//! Hash expectations met]}`. A scenario that fails, or bad arguments, give one line on stderr
//! and exit code 1 or 2.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use grove_systems::scenario::Loaded;
use grove_systems::scenario::run::{RunOptions, run};

fn scenarios(args: &[String]) -> Result<Vec<PathBuf>, String> {
    if !args.is_empty() {
        return Ok(args.iter().map(PathBuf::from).collect());
    }
    let dir = Path::new("tests/scenarios");
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    files.sort();
    Ok(files)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((out, rest)) = args.split_first() else {
        eprintln!("usage: scenario_recording OUT_DIR [SCENARIO.ron…]");
        return ExitCode::from(2);
    };
    let files = match scenarios(rest) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("scenario_recording: {e}");
            return ExitCode::from(2);
        }
    };
    if let Err(e) = std::fs::create_dir_all(out) {
        eprintln!("scenario_recording: {out}: {e}");
        return ExitCode::from(2);
    }
    for file in files {
        let loaded = match Loaded::load(&file) {
            Ok(l) => l,
            Err(e) => {
                eprintln!("scenario_recording: {e}");
                return ExitCode::from(2);
            }
        };
        let outcome = match run(&loaded, &RunOptions::default()) {
            Ok(o) => o,
            Err(e) => {
                eprintln!("scenario_recording: {}: {e}", file.display());
                return ExitCode::from(2);
            }
        };
        if let Some(f) = &outcome.failure {
            eprintln!("scenario_recording: {}: {f}", file.display());
            return ExitCode::from(1);
        }
        let path = Path::new(out).join(format!("{}.jsonl", loaded.name));
        let written = outcome
            .recording()
            .map_err(|e| e.to_string())
            .and_then(|bytes| std::fs::write(&path, bytes).map_err(|e| e.to_string()));
        if let Err(e) = written {
            eprintln!("scenario_recording: {}: {e}", path.display());
            return ExitCode::from(2);
        }
        println!(
            "{}",
            serde_json::json!({ "scenario": file.display().to_string(), "recording": path.display().to_string(), "hashes": outcome.hashes })
        );
    }
    ExitCode::SUCCESS
}
