//! `grove test [PATHS…] [--junit OUT.xml] [--update]`: run scenario files (docs/scenarios.md)
//! headless, in parallel, and print one line per scenario.
//!
//! Exit codes: 0 every scenario passed, 1 one or more failed, 2 a file could not be read or is
//! not a valid scenario (one line on stderr, before anything runs). A failed scenario's run is
//! kept as a recording in `--keep` (default `target/grove-test/NAME.jsonl`, replaced by the
//! next failed run of that scenario), so `grove view` or `grove replay` shows what happened;
//! with `--keep DIR` given, or `--trace DIR`, a scenario's trace is written as an HTML page
//! (`grove::html::scenario_trace`).

pub mod junit;
pub mod scenario;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{anyhow, bail};
use clap::Args;
use grove::atomic_write::write_atomic;
use grove_systems::scenario::run::{Outcome, RunOptions, run as run_scenario};
use grove_systems::scenario::update::pin_hashes;
use grove_systems::scenario::{Loaded, Step};
use grove_systems::set_arg::{SetArg, SetArgs};
use rayon::prelude::*;

/// Arguments of `grove test`.
#[derive(Args)]
pub struct TestArgs {
    /// Scenario files, or folders whose `.ron` files are scenarios (default: tests/scenarios).
    pub paths: Vec<PathBuf>,
    /// Also write the results as JUnit XML to this file, for CI systems.
    #[arg(long, value_name = "OUT.xml")]
    pub junit: Option<PathBuf>,
    /// Let --junit replace an existing file.
    #[arg(long, requires = "junit")]
    pub force: bool,
    /// Pin every Hash("…") expectation to the world hash this run reaches, rewriting the
    /// scenario files in place (the rest of each file is kept as written).
    #[arg(long, conflicts_with = "set")]
    pub update: bool,
    /// Override a parameter in every scenario, after the file's own config (repeatable), e.g.
    /// --set snap_threshold=0.01.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<SetArg>,
    /// The folder where a failed scenario's recording is kept (default target/grove-test);
    /// given, each failed scenario's trace (NAME.html) is written there too.
    #[arg(long, value_name = "DIR")]
    pub keep: Option<PathBuf>,
    /// Write every scenario's trace to DIR: NAME.html (its steps, what each did, frames before
    /// and after each from the head and from above, the failing step highlighted) and the
    /// recording it opens with `grove view`, NAME.jsonl.
    #[arg(long, value_name = "DIR")]
    pub trace: Option<PathBuf>,
    /// How many scenarios run at once (default: one per CPU).
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
}

/// The scenario files PATHS name: files as given, folders' `.ron` files in name order.
fn scenario_files(paths: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let default = [PathBuf::from("tests/scenarios")];
    let paths = if paths.is_empty() { &default[..] } else { paths };
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut found: Vec<PathBuf> = p
                .read_dir()
                .map_err(|e| anyhow!("{}: cannot list ({e})", p.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| f.extension().is_some_and(|x| x == "ron") && !f.is_dir())
                .collect();
            if found.is_empty() {
                bail!("{}: no scenario files (*.ron) in this folder", p.display());
            }
            found.sort();
            out.extend(found);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

/// One scenario's result.
struct Ran {
    outcome: Result<Outcome, grove_systems::scenario::RunError>,
    seconds: f64,
}

/// Runs `grove test`.
pub fn run(args: TestArgs) -> anyhow::Result<ExitCode> {
    let overrides = SetArgs::single_values(&args.set).map_err(|e| anyhow!("--set {e}"))?;
    if let Some(out) = &args.junit {
        if out.exists() && !args.force {
            bail!("{}: already exists (use --force to replace it)", out.display());
        }
        let folder = out.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        if !folder.is_dir() {
            bail!("{}: the folder {} does not exist", out.display(), folder.display());
        }
    }
    let files = scenario_files(&args.paths)?;
    let loaded = files.iter().map(|f| Loaded::load(f)).collect::<Result<Vec<_>, _>>()?;
    for (i, a) in loaded.iter().enumerate() {
        if let Some(b) = loaded[..i].iter().find(|b| b.name == a.name) {
            bail!("{} and {} are both named \"{}\"; give one a `name:`", b.path.display(), a.path.display(), a.name);
        }
    }
    let options = RunOptions { overrides, update: args.update };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.jobs.unwrap_or(0))
        .build()
        .map_err(|e| anyhow!("--jobs: {e}"))?;
    let started = Instant::now();
    let results: Vec<Ran> = pool.install(|| {
        loaded
            .par_iter()
            .map(|l| {
                let t = Instant::now();
                let outcome = run_scenario(l, &options);
                Ran { outcome, seconds: t.elapsed().as_secs_f64() }
            })
            .collect()
    });
    let wall = started.elapsed().as_secs_f64();

    let keep_dir = args.keep.clone().unwrap_or_else(|| PathBuf::from("target/grove-test"));
    if let Some(dir) = &args.trace {
        std::fs::create_dir_all(dir).map_err(|e| anyhow!("{}: cannot create ({e})", dir.display()))?;
    }
    let mut cases = Vec::new();
    let mut failed = 0;
    for (l, r) in loaded.iter().zip(&results) {
        let mut failure = match &r.outcome {
            Err(e) => Some(format!("did not run: {e}")),
            Ok(o) => match &o.failure {
                None => None,
                Some(f) => Some(format!("{f}; {}", keep(&keep_dir, &l.name, o))),
            },
        };
        // The trace: of every scenario with --trace; of a failed one into an explicit --keep.
        let trace_dir = args.trace.as_deref().or(args.keep.as_deref().filter(|_| failure.is_some()));
        let mut traced = String::new();
        if let (Some(dir), Ok(o)) = (trace_dir, &r.outcome) {
            traced = trace(dir, l, o, &options, failure.is_some() && args.trace.is_none());
        }
        if let Some(f) = failure.as_mut() {
            f.push_str(&traced);
        }
        let time = junit::seconds(r.seconds);
        match &failure {
            None if !traced.is_empty() => println!("pass  {}  {time} s  {}", l.name, traced.trim_start_matches("; ")),
            None => println!("pass  {}  {time} s", l.name),
            Some(f) => {
                failed += 1;
                println!("FAIL  {}  {time} s  {f}", l.name);
            }
        }
        if args.update {
            if let Ok(o) = &r.outcome {
                update(l, o)?;
            }
        }
        let details = failure.as_ref().map(|f| format!("{}: {f}", l.path.display()));
        cases.push(junit::Case {
            name: l.name.clone(),
            file: l.path.display().to_string(),
            seconds: r.seconds,
            failure: failure.map(|f| (f, details.unwrap_or_default())),
        });
    }
    let n = loaded.len();
    println!("{n} scenario{}: {} passed, {failed} failed ({wall:.2} s)", if n == 1 { "" } else { "s" }, n - failed);
    if let Some(out) = &args.junit {
        write_atomic(out, junit::document("grove test", &cases).as_bytes())?;
    }
    Ok(if failed > 0 { ExitCode::from(1) } else { ExitCode::SUCCESS })
}

/// Writes a failed run's recording into the keep folder and says where, or why not.
fn keep(dir: &Path, name: &str, outcome: &Outcome) -> String {
    let path = dir.join(format!("{}.jsonl", file_stem(name)));
    let written = outcome.recording().map_err(|e| anyhow!("{e}")).and_then(|bytes| {
        std::fs::create_dir_all(dir).map_err(|e| anyhow!("{}: cannot create ({e})", dir.display()))?;
        write_atomic(&path, &bytes)
    });
    match written {
        Ok(()) => format!("recording: {}", path.display()),
        Err(e) => format!("recording not kept: {}", crate::cli::one_line(&e)),
    }
}

/// A scenario's file name in the keep and trace folders: its name, other characters as `_`.
fn file_stem(name: &str) -> String {
    name.chars().map(|c| if c.is_alphanumeric() || c == '-' || c == '_' || c == '.' { c } else { '_' }).collect()
}

/// Writes a scenario's trace (and, unless it is kept there already, its recording) into `dir`,
/// and says where, or why not: `; trace: DIR/NAME.html`.
fn trace(dir: &Path, l: &Loaded, o: &Outcome, options: &RunOptions, recording_kept: bool) -> String {
    let stem = file_stem(&l.name);
    let recording = dir.join(format!("{stem}.jsonl"));
    let html = dir.join(format!("{stem}.html"));
    let written = (|| -> anyhow::Result<Option<String>> {
        std::fs::create_dir_all(dir).map_err(|e| anyhow!("{}: cannot create ({e})", dir.display()))?;
        if !recording_kept {
            write_atomic(&recording, &o.recording().map_err(|e| anyhow!("{e}"))?)?;
        }
        let traced = grove::html::scenario_trace::write(l, options, &recording, &html)?;
        Ok(traced.no_pictures)
    })();
    match written {
        Ok(None) => format!("; trace: {}", html.display()),
        Ok(Some(why)) => format!("; trace (no pictures: {why}): {}", html.display()),
        Err(e) => format!("; trace not written: {}", super::one_line(&e)),
    }
}

/// Pins the hashes a run met into its file, when the run reached every one.
fn update(l: &Loaded, o: &Outcome) -> anyhow::Result<()> {
    if o.hashes.is_empty() {
        return Ok(());
    }
    if o.failure.is_some() {
        println!("      {}: hashes not updated: the run failed before reaching all of them", l.path.display());
        return Ok(());
    }
    let step_hashes =
        l.scenario.steps.iter().filter(|s| matches!(s, Step::Expect(grove_systems::expect::Expect::Hash(_)))).count();
    let text = pin_hashes(&l.text, &o.hashes, step_hashes).map_err(|e| anyhow!("{}: {e}", l.path.display()))?;
    if text != l.text {
        write_atomic(&l.path, text.as_bytes())?;
        println!(
            "      {}: pinned {} world hash{}",
            l.path.display(),
            o.hashes.len(),
            if o.hashes.len() == 1 { "" } else { "es" }
        );
    }
    Ok(())
}
