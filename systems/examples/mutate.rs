//! The mutation run: thousands of damaged recordings and scenes fed to the readers, counting
//! panics, hangs, aborts and damage that went unnoticed. It needs no `grove` binary and no GPU.
//!
//! ```text
//! cargo run --release -p grove-systems --example mutate -- [--replay-mutants N] [--scene-mutants M] [--seed S]
//! ```
//!
//! Replay mutants start from the version-2 recordings in `tests/fixtures/replay-v2.jsonl` and
//! `replays/scenarios/`:
//! - **structural** (the checksums are left as they are, as a lost, repeated or reordered line
//!   would leave them): every deletion and every duplication of a line after the header, every
//!   swap of two neighbouring lines, and random swaps of two lines. Each must be refused (exit 2)
//!   or, for a deleted footer, read as incomplete; anything else counts as **undetected**.
//! - **forged** (the whole checksum chain signed again, as an attacker would): a number replaced
//!   by a hostile value (0, -1, 10^9, 10^12, u64::MAX, 1e39, NaN, ...), a field removed or an
//!   unknown field added, an event kind changed, a line cut short. These must not panic or hang;
//!   whether they are refused, diverge or verify is counted (a changed `ms` or `frame` verifies,
//!   correctly).
//! - **truncations** at random bytes.
//!
//! Scene mutants start from `assets/scenes/study.ron`: numbers replaced by hostile values
//! (5e19, 1e39, NaN, inf, 0, -1, 2000, 1e-30, ...), lines deleted or repeated, a huge grid, many
//! holes, cuts. Each is parsed, built and stepped ten times; it must be refused or run, without
//! a panic or a hang.
//!
//! A mutant that takes longer than 2 s counts as a hang; one that takes longer than 60 s stops
//! the run (a watchdog aborts the process and names the mutant). The run prints one summary and
//! exits 1 if anything failed.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use grove_systems::Sim;
use grove_systems::replay::{ReplayOptions, rechain, replay_reader};
use grove_systems::scene::Scene;

/// A small deterministic generator (SplitMix64), so the run needs no RNG crate.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// What happened to one mutant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Outcome {
    Refused,
    Diverged,
    /// Read without an error, but no checkpoint was reached to verify (`grove replay` exit 1).
    Unverified,
    Incomplete,
    Verified,
    Panicked,
}

#[derive(Default)]
struct Tally {
    counts: std::collections::BTreeMap<String, u64>,
    failures: Vec<String>,
}

impl Tally {
    fn add(&mut self, key: &str) {
        *self.counts.entry(key.to_string()).or_default() += 1;
    }
}

const HANG: Duration = Duration::from_secs(2);
const ABORT_AFTER: Duration = Duration::from_secs(60);

/// Runs `f` under the watchdog and `catch_unwind`; returns its outcome and the time it took.
fn guarded(
    name: &str,
    current: &Mutex<String>,
    started: &AtomicU64,
    epoch: Instant,
    f: impl FnOnce() -> Outcome,
) -> (Outcome, Duration) {
    *current.lock().unwrap() = name.to_string();
    started.store(epoch.elapsed().as_millis() as u64 + 1, Ordering::SeqCst);
    let t = Instant::now();
    let outcome = catch_unwind(AssertUnwindSafe(f)).unwrap_or(Outcome::Panicked);
    started.store(0, Ordering::SeqCst);
    (outcome, t.elapsed())
}

fn replay_outcome(text: &str, base: &Path) -> Outcome {
    match replay_reader(text.as_bytes(), "mutant.jsonl", Some(base), &ReplayOptions::default()) {
        Err(_) => Outcome::Refused,
        Ok(o) if o.first_divergence.is_some() => Outcome::Diverged,
        Ok(o) if o.checkpoints_checked == 0 => Outcome::Unverified,
        Ok(o) if !o.complete => Outcome::Incomplete,
        Ok(_) => Outcome::Verified,
    }
}

fn scene_outcome(text: &str) -> Outcome {
    match Scene::parse(text, "mutant.ron") {
        Err(_) => Outcome::Refused,
        Ok(scene) => match Sim::from_scene(&scene, scene.seed) {
            Err(_) => Outcome::Refused,
            Ok(mut sim) => {
                sim.run(10);
                let _ = sim.hash();
                Outcome::Verified
            }
        },
    }
}

const HOSTILE_NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1000000000",
    "1000000000000",
    "18446744073709551615",
    "1e39",
    "-1e39",
    "NaN",
    "1e999",
    "0.5",
    "4294967296",
    "-0",
];
const HOSTILE_SCENE_NUMBERS: &[&str] = &[
    "5e19",
    "-5e19",
    "1e39",
    "NaN",
    "inf",
    "-inf",
    "0",
    "-1",
    "0.0",
    "-0.0",
    "2000.0",
    "1e-30",
    "1e6",
    "1000001.0",
    "4294967296",
    "18446744073709551615",
    "1e-3",
];

/// The byte ranges of the numbers in a text.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) {
            let start = if i > 0 && b[i - 1] == b'-' { i - 1 } else { i };
            let mut j = i;
            while j < b.len() && (b[j].is_ascii_digit() || matches!(b[j], b'.' | b'e' | b'E' | b'-' | b'+')) {
                j += 1;
            }
            out.push((start, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// A forged mutant of one line's body (without its sum), or `None` when it has nothing to mutate.
fn forge_body(body: &str, rng: &mut Rng) -> Option<String> {
    match rng.below(5) {
        0 | 1 => {
            let nums = numbers(body);
            let (a, b) = *nums.get(rng.below(nums.len()))?;
            let v = HOSTILE_NUMBERS[rng.below(HOSTILE_NUMBERS.len())];
            Some(format!("{}{}{}", &body[..a], v, &body[b..]))
        }
        2 => {
            // An unknown field, in the line or in its event.
            let at = if body.contains("\"event\":{") && rng.below(2) == 0 {
                body.find("\"event\":{").map(|i| i + 9)
            } else {
                Some(1)
            };
            let at = at?;
            Some(format!("{}\"bogus\":1,{}", &body[..at], &body[at..]))
        }
        3 => {
            // A field removed.
            let starts: Vec<usize> = body.match_indices(",\"").map(|(i, _)| i).collect();
            let s = *starts.get(rng.below(starts.len()))?;
            let end = body[s + 1..].find(",\"").map(|e| s + 1 + e).unwrap_or(body.len() - 1);
            Some(format!("{}{}", &body[..s], &body[end..]))
        }
        _ => {
            let kinds =
                ["open_menu", "close_menu", "end_task", "button_down", "start_task", "choose_model", "teleport"];
            let i = body.find("\"kind\":\"")? + 8;
            let j = i + body[i..].find('"')?;
            Some(format!("{}{}{}", &body[..i], kinds[rng.below(kinds.len())], &body[j..]))
        }
    }
}

fn scene_mutant(base: &str, rng: &mut Rng) -> String {
    let lines: Vec<&str> = base.lines().collect();
    match rng.below(8) {
        0..=2 => {
            let nums = numbers(base);
            let (a, b) = nums[rng.below(nums.len())];
            let v = HOSTILE_SCENE_NUMBERS[rng.below(HOSTILE_SCENE_NUMBERS.len())];
            format!("{}{}{}", &base[..a], v, &base[b..])
        }
        3 => {
            let i = rng.below(lines.len());
            lines.iter().enumerate().filter(|(k, _)| *k != i).map(|(_, l)| *l).collect::<Vec<_>>().join("\n")
        }
        4 => {
            let i = rng.below(lines.len());
            let mut v = lines.clone();
            let n = 1 + rng.below(50);
            for _ in 0..n {
                v.insert(i, lines[i]);
            }
            v.join("\n")
        }
        5 => {
            let side = ["2000.0", "600.0", "500.0", "1e6"][rng.below(4)];
            base.replacen("size: (30.0, 30.0)", &format!("size: ({side}, {side})"), 1)
        }
        6 => {
            let n = [100, 5_000, 10_001, 20_000][rng.below(4)];
            let holes: String = (0..n)
                .map(|k| format!("(center: ({}.0, {}.0), radius: {}.0),", k % 30 - 15, (k / 30) % 30 - 15, 1 + k % 7))
                .collect();
            base.replacen("holes: [", &format!("holes: [{holes}"), 1)
        }
        _ => {
            let mut cut = rng.below(base.len());
            while !base.is_char_boundary(cut) {
                cut -= 1;
            }
            base[..cut].to_string()
        }
    }
}

fn arg(args: &[String], name: &str, default: u64) -> u64 {
    args.iter().position(|a| a == name).and_then(|i| args.get(i + 1)).and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn peak_rss_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let replay_target = arg(&args, "--replay-mutants", 5_000) as usize;
    let scene_target = arg(&args, "--scene-mutants", 2_000) as usize;
    let mut rng = Rng(arg(&args, "--seed", 14));
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    // The mutants never name a scene file, so any folder will do as their own.
    let base = root.clone();

    let mut files = vec![root.join("tests/fixtures/replay-v2.jsonl")];
    let mut scen: Vec<PathBuf> = std::fs::read_dir(root.join("replays/scenarios"))
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    scen.sort();
    files.extend(scen);
    let recordings: Vec<(String, Vec<String>)> = files
        .iter()
        .filter_map(|p| {
            let text = std::fs::read_to_string(p).ok()?;
            text.lines().next()?.contains("\"format_version\":2").then(|| {
                (p.file_name().unwrap().to_string_lossy().into_owned(), text.lines().map(str::to_string).collect())
            })
        })
        .collect();
    if recordings.is_empty() {
        eprintln!("error: no version-2 recordings found (tests/fixtures/replay-v2.jsonl, replays/scenarios/*.jsonl)");
        std::process::exit(2);
    }

    // The watchdog: aborts the whole run, naming the mutant, if one runs for more than a minute.
    let current = Arc::new(Mutex::new(String::new()));
    let started = Arc::new(AtomicU64::new(0));
    let epoch = Instant::now();
    {
        let (current, started) = (current.clone(), started.clone());
        std::thread::spawn(move || {
            loop {
                std::thread::sleep(Duration::from_millis(500));
                let s = started.load(Ordering::SeqCst);
                if s > 0 && epoch.elapsed().as_millis() as u64 > s + ABORT_AFTER.as_millis() as u64 {
                    eprintln!(
                        "error: mutant {} has run for more than {} s: a hang",
                        current.lock().unwrap(),
                        ABORT_AFTER.as_secs()
                    );
                    std::process::abort();
                }
            }
        });
    }
    // A panic is counted, not printed.
    std::panic::set_hook(Box::new(|_| {}));

    let mut tally = Tally::default();
    let mut slowest = (Duration::ZERO, String::new());
    let mut record =
        |tally: &mut Tally, family: &str, name: String, outcome: Outcome, took: Duration, must_detect: bool| {
            tally.add(&format!("replay {family} total"));
            tally.add(&format!("replay {family} {outcome:?}"));
            if took > slowest.0 {
                slowest = (took, name.clone());
            }
            if outcome == Outcome::Panicked {
                tally.failures.push(format!("{name}: panicked"));
            }
            if took > HANG {
                tally.failures.push(format!("{name}: took {:.1} s", took.as_secs_f64()));
            }
            if must_detect && !matches!(outcome, Outcome::Refused | Outcome::Incomplete) {
                tally.add(&format!("replay {family} UNDETECTED"));
                tally.failures.push(format!("{name}: undetected ({outcome:?})"));
            }
        };
    let join = |lines: &[String]| lines.join("\n") + "\n";
    let mut replays = 0usize;

    // Structural mutants: every deletion, duplication and neighbour swap, then random swaps.
    for (file, lines) in &recordings {
        for i in 1..lines.len() {
            let mut v = lines.clone();
            v.remove(i);
            let name = format!("{file} delete line {}", i + 1);
            let (o, t) = guarded(&name, &current, &started, epoch, || replay_outcome(&join(&v), &base));
            record(&mut tally, "deletion", name, o, t, true);
            let mut v = lines.clone();
            v.insert(i, lines[i].clone());
            let name = format!("{file} duplicate line {}", i + 1);
            let (o, t) = guarded(&name, &current, &started, epoch, || replay_outcome(&join(&v), &base));
            record(&mut tally, "duplication", name, o, t, true);
            replays += 2;
            if i + 1 < lines.len() && lines[i] != lines[i + 1] {
                let mut v = lines.clone();
                v.swap(i, i + 1);
                let name = format!("{file} swap lines {} and {}", i + 1, i + 2);
                let (o, t) = guarded(&name, &current, &started, epoch, || replay_outcome(&join(&v), &base));
                record(&mut tally, "swap", name, o, t, true);
                replays += 1;
            }
        }
    }
    // For comparison only (not counted as failures): the same damage to the version-1 fixture,
    // whose checksums cover each line alone.
    if let Ok(text) = std::fs::read_to_string(root.join("tests/fixtures/replay-v1.jsonl")) {
        let lines: Vec<String> = text.lines().map(str::to_string).collect();
        for i in 1..lines.len() {
            let mut mutants = Vec::new();
            let mut v = lines.clone();
            v.remove(i);
            mutants.push(("deletion", v));
            let mut v = lines.clone();
            v.insert(i, lines[i].clone());
            mutants.push(("duplication", v));
            if i + 1 < lines.len() && lines[i] != lines[i + 1] {
                let mut v = lines.clone();
                v.swap(i, i + 1);
                mutants.push(("swap", v));
            }
            for (family, v) in mutants {
                let name = format!("replay-v1.jsonl {family} at line {}", i + 1);
                let (o, _) = guarded(&name, &current, &started, epoch, || replay_outcome(&join(&v), &base));
                tally.add(&format!("v1 comparison {family} total"));
                if !matches!(o, Outcome::Refused | Outcome::Incomplete) {
                    tally.add(&format!("v1 comparison {family} not refused"));
                }
                if o == Outcome::Panicked {
                    tally.failures.push(format!("{name}: panicked"));
                }
            }
        }
    }
    let structural_target = replay_target / 2;
    while replays < structural_target {
        let (file, lines) = &recordings[rng.below(recordings.len())];
        let (i, j) = (1 + rng.below(lines.len() - 1), 1 + rng.below(lines.len() - 1));
        if i == j || lines[i] == lines[j] {
            continue;
        }
        let mut v = lines.clone();
        v.swap(i, j);
        let name = format!("{file} swap lines {} and {}", i + 1, j + 1);
        let (o, t) = guarded(&name, &current, &started, epoch, || replay_outcome(&join(&v), &base));
        record(&mut tally, "swap", name, o, t, true);
        replays += 1;
    }
    // Forged mutants (a valid chain signed over the damage) and truncations.
    while replays < replay_target {
        let (file, lines) = &recordings[rng.below(recordings.len())];
        if rng.below(8) == 0 {
            let text = join(lines);
            let mut cut = rng.below(text.len());
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            let name = format!("{file} cut at byte {cut}");
            let (o, t) = guarded(&name, &current, &started, epoch, || replay_outcome(&text[..cut], &base));
            record(&mut tally, "truncation", name, o, t, false);
            replays += 1;
            continue;
        }
        let i = rng.below(lines.len());
        let Ok((body, _)) = grove_systems::replay::split_sum(&lines[i]) else { continue };
        let Some(new_body) = forge_body(&body, &mut rng) else { continue };
        let mut v = lines.clone();
        v[i] = grove_systems::replay::sign_body(&new_body, 0).0;
        let Ok(v) = rechain(&v) else { continue };
        let name = format!("{file} forged line {}: {}", i + 1, new_body.chars().take(120).collect::<String>());
        let (o, t) = guarded(&name, &current, &started, epoch, || replay_outcome(&join(&v), &base));
        record(&mut tally, "forged", name, o, t, false);
        replays += 1;
    }

    // Scene mutants.
    let study = std::fs::read_to_string(root.join("assets/scenes/study.ron")).expect("assets/scenes/study.ron");
    for k in 0..scene_target {
        let text = scene_mutant(&study, &mut rng);
        let name = format!("scene mutant {k} ({} bytes)", text.len());
        let (o, t) = guarded(&name, &current, &started, epoch, || scene_outcome(&text));
        tally.add("scene total");
        tally.add(&format!("scene {}", if o == Outcome::Verified { "Accepted".to_string() } else { format!("{o:?}") }));
        if o == Outcome::Panicked {
            tally.failures.push(format!("{name}: panicked"));
        }
        if t > HANG {
            tally.failures.push(format!("{name}: took {:.1} s", t.as_secs_f64()));
        }
        if t > slowest.0 {
            slowest = (t, name);
        }
    }

    println!(
        "mutation run: {} replay mutants of {} version-2 recordings, {} scene mutants, {:.1} s",
        replays,
        recordings.len(),
        scene_target,
        epoch.elapsed().as_secs_f64()
    );
    for (k, v) in &tally.counts {
        println!("  {k:<32} {v}");
    }
    println!("  slowest mutant: {:.3} s ({})", slowest.0.as_secs_f64(), slowest.1);
    println!("  peak memory (resident): {:.0} MB", peak_rss_mb());
    println!("  panics, hangs (> 2 s) and undetected structural damage: {}", tally.failures.len());
    for f in tally.failures.iter().take(20) {
        println!("    {f}");
    }
    if !tally.failures.is_empty() {
        std::process::exit(1);
    }
}
