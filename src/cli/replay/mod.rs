//! `grove replay`: re-simulate a recording headless and verify every checkpoint.
//!
//! Exit codes: 0 verified or unverified (no checkpoints to compare), 1 diverged, 2 unreadable or
//! invalid input. `--seal` re-simulates an event-only file and writes it with checkpoints
//! (`seal.rs`).

pub mod html;
pub mod seal;
pub mod upgrade;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use grove_systems::hash::hex;
use grove_systems::replay::{replay_file, Divergence, ReplayOptions, ReplayOutcome};
use grove_systems::task::TaskReport;
use serde::Serialize;

/// Arguments of `grove replay`.
#[derive(Args)]
pub struct ReplayArgs {
    /// The recording (JSON Lines, see docs/replay-format.md).
    pub file: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Stop at this tick.
    #[arg(long)]
    pub until: Option<u64>,
    /// Seal FILE: re-simulate its events and write them with checkpoints and a footer to --out.
    #[arg(long, requires = "out", conflicts_with_all = ["upgrade"])]
    pub seal: bool,
    /// Rewrite FILE (format version 1) as version 2 into --out instead of replaying it.
    #[arg(long, requires = "out", conflicts_with_all = ["json", "until"])]
    pub upgrade: bool,
    /// The file --seal or --upgrade writes (never overwritten, except by --upgrade --force).
    #[arg(long, value_name = "OUT")]
    pub out: Option<PathBuf>,
    /// A model-bank folder (repeatable) in which the models the header lists are found;
    /// GROVE_BANK's folders are searched after these.
    #[arg(long = "bank", value_name = "DIR")]
    pub banks: Vec<PathBuf>,
    /// Let --upgrade overwrite an existing --out file, or --html an existing page.
    #[arg(long)]
    pub force: bool,
    /// Also write the recording's page to this file: its numbers, its events on a time axis,
    /// the time each tree took, a head-camera filmstrip and, when it diverges, the first
    /// diverging tick with the entities and components that differ and frames just before and
    /// at it (one self-contained HTML file).
    #[arg(long, value_name = "OUT.html", conflicts_with_all = ["seal", "upgrade", "until"])]
    pub html: Option<PathBuf>,
}

/// What `grove replay --json` prints.
#[derive(Serialize)]
pub struct ReplayReport {
    /// The file replayed.
    pub file: String,
    /// Its format version.
    pub format_version: u32,
    /// Ticks simulated.
    pub ticks: u64,
    /// Simulated seconds.
    pub sim_seconds: f64,
    /// Wall-clock seconds the replay took.
    pub wall_seconds: f64,
    /// Simulated seconds per wall second.
    pub speedup: f64,
    /// Every checkpoint compared matched (and at least one was compared).
    pub verified: bool,
    /// "verified", "unverified" (no checkpoint to compare) or "diverged".
    pub status: &'static str,
    /// The file has its footer.
    pub complete: bool,
    /// Checkpoints compared, the footer's final hash included.
    pub checkpoints_checked: u64,
    /// The first divergence, if any.
    pub first_divergence: Option<Divergence>,
    /// Input events by kind.
    pub events: std::collections::BTreeMap<String, u64>,
    /// The world hash at the end of the replay.
    pub final_hash: String,
    /// The participant id from the header.
    pub participant: Option<String>,
    /// Whether the header marks the session as synthetic.
    pub synthetic: bool,
    /// The input device the header names (`profile`, `target_ray_mode`, `mapping`); a
    /// controller of unknown profile for a recording without one.
    pub device: grove_systems::replay::HeaderDevice,
    /// The task outcome, recomputed by the simulation, if the session ran a task.
    pub task: Option<TaskReport>,
}

impl ReplayReport {
    /// Builds the report from a replay's outcome.
    pub fn new(file: String, outcome: &ReplayOutcome, wall_seconds: f64) -> ReplayReport {
        let sim = &outcome.sim;
        let ticks = sim.tick();
        let sim_seconds = grove_systems::task::ticks_to_seconds(ticks, sim.dt());
        let verified = outcome.verifying && outcome.first_divergence.is_none() && outcome.checkpoints_checked > 0;
        ReplayReport {
            file,
            format_version: outcome.header.format_version,
            ticks,
            sim_seconds,
            wall_seconds,
            speedup: if wall_seconds > 0.0 { sim_seconds / wall_seconds } else { f64::INFINITY },
            verified,
            status: if outcome.first_divergence.is_some() {
                "diverged"
            } else if verified {
                "verified"
            } else {
                "unverified"
            },
            complete: outcome.complete,
            checkpoints_checked: outcome.checkpoints_checked,
            first_divergence: outcome.first_divergence.clone(),
            events: outcome.events.clone(),
            final_hash: hex(sim.hash().total),
            participant: outcome.header.participant.clone(),
            synthetic: outcome.header.synthetic,
            device: outcome.header.device_or_unknown(),
            task: sim.task().map(|t| grove::study::technique_report(TaskReport::new(t, sim.dt(), ticks, sim.catalogue()), &sim)),
        }
    }
}

/// Runs `grove replay`.
pub fn run(args: ReplayArgs) -> anyhow::Result<ExitCode> {
    if args.seal {
        return seal::run(&args.file, args.out.as_deref());
    }
    if args.upgrade {
        return upgrade::run(&args.file, args.out.as_deref(), args.force);
    }
    if args.out.is_some() {
        anyhow::bail!("--out is only for --seal or --upgrade");
    }
    if args.force && args.html.is_none() {
        anyhow::bail!("--force is only for --upgrade or --html");
    }
    if let Some(page) = &args.html {
        html::check_out(page, args.force)?;
    }
    let start = Instant::now();
    let options = ReplayOptions { until: args.until, banks: grove::bank::session_dirs(&args.banks), ..Default::default() };
    let outcome = match replay_file(&args.file, &options) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("error: {e}");
            return Ok(ExitCode::from(2));
        }
    };
    let wall = start.elapsed().as_secs_f64();
    let report = ReplayReport::new(args.file.display().to_string(), &outcome, wall);
    if let Some(page) = &args.html {
        html::write(&args.file, &outcome, page)?;
    }
    if args.json {
        crate::cli::print_json(&report)?;
    } else {
        let state = if report.first_divergence.is_some() {
            "DIVERGED"
        } else if report.verified {
            "verified"
        } else {
            "unverified (no checkpoint to compare; `grove replay --seal` adds them)"
        };
        println!(
            "{}: {state}, {} ({} ticks, {:.1} s simulated in {:.3} s, {:.0}x), {} checkpoints, final hash {}",
            report.file,
            if report.complete { "complete" } else { "incomplete" },
            report.ticks,
            report.sim_seconds,
            report.wall_seconds,
            report.speedup,
            report.checkpoints_checked,
            report.final_hash
        );
        if let Some(d) = &report.first_divergence {
            let what: Vec<String> = d.differing.iter().map(|x| format!("entity {} {}", x.entity, x.component)).collect();
            println!("  first divergence at tick {}: expected {}, got {}; differs: {}", d.tick, d.expected_hash, d.actual_hash, what.join(", "));
        }
        if report.synthetic {
            println!("  note: a synthetic recording (generated by grove synth), not a person's session");
        }
        let d = &report.device;
        println!("  device: {} ({}, {})", d.mapping, d.target_ray_mode, d.profile);
        if let Some(t) = &report.task {
            println!("  {}", t.result_line());
            if let Some(p) = &t.layout {
                println!("  layout: room, the task file's spacing x{:.4} in a floor of {:.2} x {:.2} m ({:.1} m²), every target at least {:.2} m from its edges", p.scale, p.floor_size[0], p.floor_size[1], p.floor_m2, p.edge_m);
            }
        }
    }
    Ok(if report.first_divergence.is_some() { ExitCode::from(1) } else { ExitCode::SUCCESS })
}
