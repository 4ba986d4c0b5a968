//! The dashboard's live view of a session (`/dashboard`, `docs/protocol.md`): its file so far
//! re-simulated (the acknowledged lines, a copy cut at the last whole line), giving the task
//! clock, trees planted, errors, the trees and targets from above and the ray's hit cells as
//! the HTML report's map counts them. Computed again only when the file has grown.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use grove_systems::bank::Banks;
use grove_systems::events::Happening;
use grove_systems::replay::player::Player;
use serde_json::{json, Value};

/// The side of a hit cell, metres (as the HTML report's map).
pub const CELL_M: f32 = crate::html::trace::CELL_M;

/// Why a live view could not be made (the dashboard shows it in the view's place).
#[derive(Debug, thiserror::Error)]
pub enum LiveError {
    /// The file could not be read.
    #[error("{0}")]
    Read(String),
    /// The scratch copy could not be written.
    #[error("{path}: {message}")]
    Io {
        /// The path.
        path: String,
        /// What went wrong, one line.
        message: String,
    },
    /// The model banks could not be opened, or the replay refused the copy.
    #[error("{0}")]
    Replay(String),
}

/// Live views by session file, with the line count each was made at.
#[derive(Default)]
pub struct LiveCache {
    views: Mutex<HashMap<String, (u64, Value)>>,
    /// Held while a view is made: one re-simulation at a time, however many pages poll.
    pub making: tokio::sync::Mutex<()>,
}

impl LiveCache {
    /// The view of `file` at `lines` lines, if one was made.
    pub fn get(&self, file: &str, lines: u64) -> Option<Value> {
        self.views.lock().unwrap_or_else(|p| p.into_inner()).get(file).filter(|(n, _)| *n == lines).map(|(_, v)| v.clone())
    }

    /// Keeps a view.
    pub fn put(&self, file: &str, lines: u64, v: Value) {
        self.views.lock().unwrap_or_else(|p| p.into_inner()).insert(file.to_string(), (lines, v));
    }

    /// The last view of `file`, whatever its line count.
    pub fn last(&self, file: &str) -> Option<Value> {
        self.views.lock().unwrap_or_else(|p| p.into_inner()).get(file).map(|(_, v)| v.clone())
    }
}

/// Re-simulates the whole lines of `path` (a copy in `scratch`) and describes the world.
pub fn view(path: &Path, scratch: &Path, bank_dirs: &[PathBuf]) -> Result<Value, LiveError> {
    let io = |p: &Path, e: std::io::Error| LiveError::Io { path: p.display().to_string(), message: e.to_string() };
    let text = grove_systems::files::read(path, grove_systems::files::Kind::Recording).map_err(|e| LiveError::Read(e.reason()))?;
    let whole = text.iter().rposition(|b| *b == b'\n').map_or(0, |i| i + 1);
    std::fs::create_dir_all(scratch).map_err(|e| io(scratch, e))?;
    let copy = scratch.join(path.file_name().unwrap_or_default());
    std::fs::write(&copy, &text[..whole]).map_err(|e| io(&copy, e))?;
    let banks = Banks::open(bank_dirs).map_err(|e| LiveError::Replay(e.to_string()))?;
    let result = run(&copy, &banks);
    let _ = std::fs::remove_file(&copy);
    result
}

fn run(copy: &Path, banks: &Banks) -> Result<Value, LiveError> {
    let mut player = Player::open(copy, &[], banks).map_err(|e| LiveError::Replay(e.to_string()))?;
    let end = player.final_tick();
    let mut hits: BTreeMap<(i32, i32), u32> = BTreeMap::new();
    while player.sim().tick() < end {
        player.step();
        let sim = player.sim();
        let h = sim.hit_marker();
        if h.visible && sim.task().is_none_or(|t| !t.is_over()) {
            *hits.entry(((h.position.x / CELL_M).floor() as i32, (h.position.z / CELL_M).floor() as i32)).or_insert(0) += 1;
        }
    }
    let sim = player.sim();
    let dt = sim.dt();
    let mut trees = Vec::new();
    sim.for_each_tree(|t| trees.push(json!([t.transform.translation.x, t.transform.translation.z])));
    let planted = sim.log().entries.iter().filter(|e| matches!(e.what, Happening::Planted { .. })).count();
    let (clock, errors, targets, satisfied) = match sim.task() {
        Some(t) => {
            let stop = t.end_tick().unwrap_or(sim.tick());
            let clock = grove_systems::task::ticks_to_seconds(stop.saturating_sub(t.started_tick), dt);
            let targets: Vec<Value> = t.def.targets.iter().map(|g| json!([g.position.x, g.position.z])).collect();
            (Some(clock), t.errors.total(), targets, t.satisfied.iter().filter(|s| s.is_some()).count())
        }
        None => (None, 0, Vec::new(), 0),
    };
    Ok(json!({
        "tick": sim.tick(),
        "task_clock_s": clock,
        "trees_planted": planted,
        "targets_satisfied": satisfied,
        "errors": errors,
        "trees": trees,
        "targets": targets,
        "cell_m": CELL_M,
        "hits": hits.iter().map(|((x, z), n)| json!([x, z, n])).collect::<Vec<_>>(),
    }))
}
