//! One session's recording replayed as it grows: the acknowledged bytes of its file read from
//! where the last turn stopped, each line checked again by the format's rules and handed to the
//! replay's [`Verifier`], which steps the world to the line's tick and compares each checkpoint
//! as it comes. What it holds is bounded whatever the session's length: the world, the rules'
//! state, one line at most of unfinished text, a read buffer and at most [`MAX_CELLS`] counted
//! cells of the ray's hits.
//!
//! [`LiveView`] is what it shows: the verification so far (the same fields as a session's
//! verification once it ended) and the world now (the task's clock, trees planted, targets met,
//! errors, the current model, the trees and targets from above and the ray's hit cells as the HTML
//! report's map counts them).

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use grove_systems::bank::Banks;
use grove_systems::events::Happening;
use grove_systems::limits::MAX_LINE_BYTES;
use grove_systems::replay::{header_line, sim_for_header_in, Line, LineRules, ReplayError, Verifier};
use grove_systems::sim::Sim;
use serde::Serialize;

use crate::serve::line_split::LineSplitter;
use crate::serve::sessions::states::VerifyStatus;
use crate::serve::sessions::verify::Verification;

/// The side of a hit cell, metres (as the HTML report's map).
pub const CELL_M: f32 = crate::html::trace::CELL_M;
/// The most cells of the ray's hits a view counts; hits in further cells are left out.
pub const MAX_CELLS: usize = 4096;
/// The most bytes one turn reads, so that one long file does not hold up the other sessions.
pub const TURN_BYTES: u64 = 256 * 1024;
const CHUNK: usize = 16 * 1024;

/// What a session's live replay shows.
#[derive(Clone, Debug, Serialize)]
pub struct LiveView {
    /// Lines replayed (the header is line 1).
    pub lines: u64,
    /// The verification of those lines: `incomplete` (verified to the last checkpoint) while the
    /// footer has not come, `diverged` from the first checkpoint that differs, `invalid` when a
    /// line could not be replayed, `verified` or `unverified` with the footer.
    pub verification: Verification,
    /// The world's tick.
    pub tick: u64,
    /// The task's clock, seconds (none without a task).
    pub task_clock_s: Option<f64>,
    /// Trees planted so far.
    pub trees_planted: usize,
    /// The task's targets met.
    pub targets_satisfied: usize,
    /// The task's errors.
    pub errors: u32,
    /// The model the next tree will be (the menu's choice).
    pub model: Option<String>,
    /// The trees from above, `[x, z]` metres.
    pub trees: Vec<[f32; 2]>,
    /// The task's targets from above, `[x, z]` metres.
    pub targets: Vec<[f32; 2]>,
    /// The side of a hit cell, metres.
    pub cell_m: f32,
    /// The ray's hits on the ground while the task ran, `[x, z, count]` by cell.
    pub hits: Vec<(i32, i32, u32)>,
}

enum Stage {
    /// The header has not been read yet.
    Header,
    /// Lines are replayed.
    Going { rules: LineRules, verifier: Box<Verifier>, last_checkpoint: u64 },
}

/// One session's file replayed as it grows.
pub struct LiveReplay {
    path: PathBuf,
    file: Option<File>,
    /// Bytes of the file taken so far.
    offset: u64,
    splitter: LineSplitter,
    stage: Stage,
    hits: BTreeMap<(i32, i32), u32>,
    /// Why the replay stopped: a line it could not replay. Nothing more is read.
    error: Option<String>,
    buf: Vec<u8>,
}

impl LiveReplay {
    /// A replay of the file at `path`, which nothing has been read of yet.
    pub fn new(path: &Path) -> LiveReplay {
        LiveReplay { path: path.to_path_buf(), file: None, offset: 0, splitter: LineSplitter::new(MAX_LINE_BYTES), stage: Stage::Header, hits: BTreeMap::new(), error: None, buf: Vec::new() }
    }

    /// Bytes of the file taken so far.
    pub fn offset(&self) -> u64 {
        self.offset
    }

    /// Whether the replay stopped (a line it could not replay): nothing more is read.
    pub fn stopped(&self) -> bool {
        self.error.is_some()
    }

    /// Reads and replays the file's bytes up to `upto` (acknowledged, so ending in a newline), at
    /// most [`TURN_BYTES`] of them; `banks` are the model banks a header may name.
    pub fn read(&mut self, upto: u64, banks: &Banks) {
        let end = upto.min(self.offset + TURN_BYTES);
        while self.offset < end && !self.stopped() {
            if let Err(why) = self.read_chunk(end, banks) {
                self.stop(why);
            }
        }
    }

    fn read_chunk(&mut self, end: u64, banks: &Banks) -> Result<(), String> {
        if self.file.is_none() {
            let (f, _) = grove_systems::files::open(&self.path, grove_systems::files::Kind::Recording).map_err(|e| e.reason())?;
            self.file = Some(f);
        }
        let Some(file) = self.file.as_mut() else { return Ok(()) };
        let want = ((end - self.offset) as usize).min(CHUNK);
        self.buf.resize(want, 0);
        file.seek(SeekFrom::Start(self.offset)).map_err(|e| e.to_string())?;
        let n = file.read(&mut self.buf[..want]).map_err(|e| e.to_string())?;
        if n == 0 {
            return Err(format!("the file ends at byte {}, before what was acknowledged", self.offset));
        }
        self.offset += n as u64;
        let chunk = std::mem::take(&mut self.buf);
        let mut failed = None;
        let split = {
            let (stage, hits, path) = (&mut self.stage, &mut self.hits, &self.path);
            let dir = path.parent().unwrap_or(Path::new("."));
            let mut number = self.splitter.lines();
            self.splitter.push(&chunk[..n], &mut |text| {
                number += 1;
                match take(stage, hits, dir, banks, text) {
                    Ok(()) => true,
                    Err(message) => {
                        failed = Some(ReplayError { file: path.display().to_string(), line: Some(number), message }.to_string());
                        false
                    }
                }
            })
        };
        self.buf = chunk;
        if let Some(why) = failed {
            return Err(why);
        }
        split.map(|_| ()).map_err(|e| e.to_string())
    }

    fn stop(&mut self, why: String) {
        self.error = Some(why);
        self.file = None;
        self.buf = Vec::new();
    }

    /// The verification of the lines replayed so far (before the header: verified to tick 0).
    pub fn verification(&self) -> Verification {
        let (last_tick, found) = match &self.stage {
            Stage::Going { rules, verifier, last_checkpoint } => {
                (rules.last_tick(), Verification::found(verifier.complete(), verifier.checkpoints_checked(), verifier.first_divergence(), rules.last_tick(), *last_checkpoint))
            }
            Stage::Header => (0, Verification::found(false, 0, None, 0, 0)),
        };
        match &self.error {
            Some(why) => Verification::invalid(why.clone(), last_tick),
            None => found,
        }
    }

    /// What the replay shows now.
    pub fn view(&self) -> LiveView {
        let mut view = LiveView {
            lines: self.splitter.lines(),
            verification: self.verification(),
            tick: 0,
            task_clock_s: None,
            trees_planted: 0,
            targets_satisfied: 0,
            errors: 0,
            model: None,
            trees: Vec::new(),
            targets: Vec::new(),
            cell_m: CELL_M,
            hits: Vec::new(),
        };
        if let Stage::Going { verifier, .. } = &self.stage {
            world(&mut view, verifier.sim());
            view.hits = self.hits.iter().map(|(&(x, z), &n)| (x, z, n)).collect();
        }
        view
    }
}

/// Replays one line (its text without the newline): the header builds the world, every later
/// line is checked by the rules and handed to the verifier; each step's hit is counted.
fn take(stage: &mut Stage, hits: &mut BTreeMap<(i32, i32), u32>, dir: &Path, banks: &Banks, text: String) -> Result<(), String> {
    match stage {
        Stage::Header => {
            let header = header_line(&text).map_err(|e| e.to_string())?;
            let sim = sim_for_header_in(&header, Some(dir), &[], banks).map_err(|e| e.to_string())?;
            *stage = Stage::Going { rules: LineRules::after(&header), verifier: Box::new(Verifier::new(sim, true)), last_checkpoint: 0 };
            Ok(())
        }
        Stage::Going { rules, verifier, last_checkpoint } => {
            let ruled = rules.check(text).map_err(|e| e.to_string())?;
            if let Line::Checkpoint(c) = &ruled.line {
                *last_checkpoint = c.tick;
            }
            verifier.take(ruled.line, ruled.tick, || None, |sim| count_hit(hits, sim)).map_err(|e| e.to_string())
        }
    }
}

/// Counts the cell the ray hits after a step, while the task runs (as the HTML report's map).
fn count_hit(hits: &mut BTreeMap<(i32, i32), u32>, sim: &Sim) {
    let h = sim.hit_marker();
    if !h.visible || sim.task().is_some_and(|t| t.is_over()) {
        return;
    }
    let cell = ((h.position.x / CELL_M).floor() as i32, (h.position.z / CELL_M).floor() as i32);
    if let Some(n) = hits.get_mut(&cell) {
        *n += 1;
    } else if hits.len() < MAX_CELLS {
        hits.insert(cell, 1);
    }
}

/// The world's figures for a view.
fn world(view: &mut LiveView, sim: &Sim) {
    view.tick = sim.tick();
    sim.for_each_tree(|t| view.trees.push([t.transform.translation.x, t.transform.translation.z]));
    view.trees_planted = sim.log().entries.iter().filter(|e| matches!(e.what, Happening::Planted { .. })).count();
    let current = sim.menu().current_model;
    view.model = sim.catalogue().get(current).map(|m| m.name.clone());
    if let Some(t) = sim.task() {
        let stop = t.end_tick().unwrap_or(sim.tick());
        view.task_clock_s = Some(grove_systems::task::ticks_to_seconds(stop.saturating_sub(t.started_tick), sim.dt()));
        view.targets = t.def.targets.iter().map(|g| [g.position.x, g.position.z]).collect();
        view.targets_satisfied = t.satisfied.iter().filter(|s| s.is_some()).count();
        view.errors = t.errors.total();
    }
}

impl VerifyStatus {
    /// Whether a live verification found something wrong (a divergence, or a line it could not
    /// replay).
    pub fn is_wrong(self) -> bool {
        matches!(self, VerifyStatus::Diverged | VerifyStatus::Invalid)
    }
}
