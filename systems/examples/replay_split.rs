//! Where the time of re-simulating a recording goes: reading the file, checking the lines'
//! chained checksums, parsing the JSON lines, stepping the simulation and hashing the world at
//! the checkpoints. One thread, every recording of a folder in turn, each phase timed on its own
//! (docs/scale.md has the figures).
//!
//! ```text
//! cargo run --release -p grove-systems --example replay_split -- [FOLDER] [ROUNDS]
//! ```
//!
//! FOLDER defaults to `replays/study`, ROUNDS (how often the whole folder is timed; the fastest
//! round counts) to 3. Prints one JSON object. Bad arguments or an unreadable recording give one
//! line on stderr and exit code 2.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use grove_systems::files::{self, Kind};
use grove_systems::replay::codec::{chained_sum, decode_line_parts, split_sum};
use grove_systems::replay::{Line, ReplayOptions, replay_reader};

#[derive(Default, Clone, Copy)]
struct Split {
    read: f64,
    sums: f64,
    decode: f64,
    replay: f64,
    hashes: f64,
    checkpoints: u64,
    ticks: u64,
    bytes: u64,
    lines: u64,
}

fn time<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let t = Instant::now();
    let v = f();
    (v, t.elapsed().as_secs_f64())
}

fn one(path: &Path) -> Result<Split, String> {
    let (bytes, read) = time(|| files::read(path, Kind::Recording));
    let bytes = bytes.map_err(|e| e.to_string())?;
    let text = std::str::from_utf8(&bytes).map_err(|_| format!("{}: not UTF-8", path.display()))?;
    let lines: Vec<&str> = text.lines().collect();
    // The checksums alone: split off each line's sum and hash its body, chained (version 2:
    // the header and the line after it have seed 0).
    let (sums_ok, sums) = time(|| {
        let mut prev = 0;
        for (i, l) in lines.iter().enumerate() {
            let (body, sum) = split_sum(l).map_err(|e| e.to_string())?;
            if chained_sum(&body, prev) != sum {
                return Err(format!("line {}: checksum mismatch", i + 1));
            }
            prev = if i == 0 { 0 } else { sum };
        }
        Ok::<(), String>(())
    });
    sums_ok.map_err(|e| format!("{}: {e}", path.display()))?;
    // Checksums and parsing, as the reader does them, without the simulation.
    let (decoded, decode) = time(|| {
        let mut prev = 0;
        let mut checkpoints = 0;
        for (i, l) in lines.iter().enumerate() {
            let (line, _, sum) = decode_line_parts(l, prev).map_err(|e| e.to_string())?;
            checkpoints += matches!(line, Line::Checkpoint(_) | Line::Footer(_)) as u64;
            prev = if i == 0 { 0 } else { sum };
        }
        Ok::<u64, String>(checkpoints)
    });
    let checkpoints = decoded.map_err(|e| format!("{}: {e}", path.display()))?;
    // The whole replay from memory: parsing, stepping and checkpoint hashes.
    let base = path.parent();
    let (outcome, replay) =
        time(|| replay_reader(&bytes[..], &path.display().to_string(), base, &ReplayOptions::default()));
    let outcome = outcome.map_err(|e| e.to_string())?;
    if outcome.first_divergence.is_some() {
        return Err(format!("{}: diverged", path.display()));
    }
    // The cost of one world hash, on the final world, times the checkpoints the replay checked.
    let reps = 20;
    let (_, h) = time(|| {
        for _ in 0..reps {
            std::hint::black_box(outcome.sim.hash());
        }
    });
    Ok(Split {
        read,
        sums,
        decode,
        replay,
        hashes: h / reps as f64 * outcome.checkpoints_checked as f64,
        checkpoints,
        ticks: outcome.sim.tick(),
        bytes: bytes.len() as u64,
        lines: lines.len() as u64,
    })
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let dir = PathBuf::from(args.next().unwrap_or_else(|| "replays/study".into()));
    let rounds = match args.next().map(|r| r.parse::<u32>()) {
        None => 3,
        Some(Ok(r)) if (1..=100).contains(&r) => r,
        Some(_) => {
            eprintln!("replay_split: ROUNDS must be a whole number from 1 to 100");
            return ExitCode::from(2);
        }
    };
    let mut paths: Vec<PathBuf> = match std::fs::read_dir(&dir) {
        Ok(d) => {
            d.filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.extension().is_some_and(|x| x == "jsonl")).collect()
        }
        Err(e) => {
            eprintln!("replay_split: {}: {e}", dir.display());
            return ExitCode::from(2);
        }
    };
    paths.sort();
    if paths.is_empty() {
        eprintln!("replay_split: {}: no recordings (*.jsonl)", dir.display());
        return ExitCode::from(2);
    }
    let mut best: Option<Split> = None;
    for _ in 0..rounds {
        let mut total = Split::default();
        for p in &paths {
            match one(p) {
                Ok(s) => {
                    total.read += s.read;
                    total.sums += s.sums;
                    total.decode += s.decode;
                    total.replay += s.replay;
                    total.hashes += s.hashes;
                    total.checkpoints += s.checkpoints;
                    total.ticks += s.ticks;
                    total.bytes += s.bytes;
                    total.lines += s.lines;
                }
                Err(e) => {
                    eprintln!("replay_split: {}", e.replace('\n', " "));
                    return ExitCode::from(2);
                }
            }
        }
        if best.is_none_or(|b| total.replay + total.read < b.replay + b.read) {
            best = Some(total);
        }
    }
    let Some(t) = best else { return ExitCode::from(2) };
    let n = paths.len() as f64;
    let whole = t.read + t.replay;
    let stepping = t.replay - t.decode - t.hashes;
    let ms = |x: f64| (x / n * 1e6).round() / 1e3;
    let share = |x: f64| (x / whole * 1000.0).round() / 10.0;
    let sim_seconds = t.ticks as f64 / 60.0;
    println!(
        "{}",
        serde_json::json!({
            "recordings": paths.len(),
            "mean_bytes": (t.bytes as f64 / n).round(),
            "mean_lines": (t.lines as f64 / n).round(),
            "mean_ticks": (t.ticks as f64 / n).round(),
            "ms_per_recording": {
                "whole": ms(whole),
                "read_file": ms(t.read),
                "checksums": ms(t.sums),
                "json_parse": ms(t.decode - t.sums),
                "checkpoint_hashes": ms(t.hashes),
                "stepping": ms(stepping),
            },
            "percent": {
                "read_file": share(t.read),
                "checksums": share(t.sums),
                "json_parse": share(t.decode - t.sums),
                "checkpoint_hashes": share(t.hashes),
                "stepping": share(stepping),
            },
            "recordings_per_second_one_thread": (n / whole * 10.0).round() / 10.0,
            "speedup_real_time": (sim_seconds / t.replay).round(),
            "rounds": rounds,
        })
    );
    ExitCode::SUCCESS
}
