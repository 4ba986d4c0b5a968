//! Benchmarks of replays and of the whole study.

use std::time::Instant;

use crate::atomic_write::{via_temp, write_bytes};
use glam::Vec3;
use grove_systems::Sim;
use grove_systems::catalogue::ModelId;
use grove_systems::input::Button;
use grove_systems::replay::{Header, ReplayOptions, record_events, replay_reader};
use grove_systems::scene::Scene;
use grove_systems::script::Script;
use serde_json::{Value, json};

use super::{BenchError, median};

/// Builds a 5-minute recording in memory: the controller sweeps over the ground at 30 Hz and
/// plants, selects and removes trees every few seconds.
pub fn five_minute_session() -> Result<Vec<u8>, BenchError> {
    let scene = Scene::builtin("study").ok_or(BenchError::MissingScene("study"))?;
    let mut script = Script::new(Sim::from_scene(&scene, 7).map_err(grove_systems::Error::from)?);
    let ticks = (300.0 / scene.dt as f64).round() as u64;
    let mut k = 0u64;
    while script.sim().tick() + 4 < ticks {
        let a = k as f32 * 0.02;
        let target = Vec3::new(6.0 * a.sin(), 0.0, -5.0 + 3.0 * (0.7 * a).cos());
        script.point_at(target).wait(1);
        match k % 240 {
            0 => {
                script.choose_model(ModelId((k / 240 % 8) as u8)).press(Button::Trigger);
            }
            120 => {
                script.point_at(target + Vec3::Y * 2.0).press(Button::Bumper);
            }
            _ => {}
        }
        k += 1;
    }
    let (sim, events) = script.into_parts();
    let header = Header::new("study", 7, scene.dt);
    Ok(record_events(Vec::new(), &header, &events, ticks.max(sim.tick()), json!({}))
        .map_err(grove_systems::Error::from)?)
}

/// Replay speed of a 5-minute session, in simulated seconds per wall second (median of runs).
pub fn bench_replay() -> Result<Value, BenchError> {
    eprintln!("bench: replay of a 5-minute session");
    let bytes = five_minute_session()?;
    let mut speedups = Vec::new();
    let mut walls = Vec::new();
    let mut sim_seconds = 0.0;
    let mut verified = true;
    for _ in 0..7 {
        let t = Instant::now();
        let o = replay_reader(&bytes[..], "<5-minute session>", None, &ReplayOptions::default())
            .map_err(grove_systems::Error::from)?;
        let wall = t.elapsed().as_secs_f64();
        verified &= o.first_divergence.is_none() && o.complete;
        sim_seconds = o.sim.tick() as f64 * o.sim.dt() as f64;
        speedups.push(sim_seconds / wall);
        walls.push(wall * 1e3);
    }
    Ok(json!({
        "sim_seconds": sim_seconds,
        "file_bytes": bytes.len(),
        "wall_ms_median": median(&mut walls),
        "speedup_median": median(&mut speedups),
        "verified": verified,
    }))
}

/// The whole study: every recording in `replays/study` re-simulated, verified and reported
/// (CSV, JSON and chart written to a temporary folder), wall seconds.
pub fn bench_study() -> Result<Value, BenchError> {
    eprintln!("bench: the whole study");
    let files = crate::study::recordings_in(std::path::Path::new("replays/study"))?;
    let out = std::env::temp_dir().join(format!("grove-bench-study-{}", std::process::id()));
    std::fs::create_dir_all(&out).map_err(|source| BenchError::Folder { path: out.clone(), source })?;
    let mut walls = Vec::new();
    let mut verified = 0;
    for _ in 0..5 {
        let t = Instant::now();
        let (trials, wall_sim) = crate::study::run_all(&files, &[], &|| {});
        let summary = crate::study::report::summarize(&trials, &[], wall_sim);
        // Written as `grove study` writes them: through a temporary file and a rename.
        via_temp(&out.join("trial_results.csv"), |tmp| crate::study::csv_out::write_trial_results(tmp, &trials, None))?;
        via_temp(&out.join("trees.csv"), |tmp| crate::study::csv_out::write_trees(tmp, &trials))?;
        write_bytes(&out.join("summary.json"), serde_json::to_string_pretty(&summary)?.as_bytes())?;
        via_temp(&out.join("ablation.png"), |tmp| {
            crate::study::chart::ablation_chart(tmp, &summary.per_participant, None, "bench", &[], 1100, 600)
        })?;
        walls.push(t.elapsed().as_secs_f64());
        verified = trials.iter().filter(|t| t.status == crate::study::TrialStatus::Verified).count();
    }
    let _ = std::fs::remove_dir_all(&out);
    Ok(json!({
        "recordings": files.len(),
        "verified": verified,
        "threads": rayon::current_num_threads(),
        "wall_seconds_median": median(&mut walls),
    }))
}
