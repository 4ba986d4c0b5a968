//! Recordings and replays: the versioned JSON Lines format, a writer and a verifying reader.
//!
//! `docs/replay-format.md` documents the format. In short, a recording is one JSON object per
//! line: a header, then input events ordered by tick, checkpoints every [`CHECKPOINT_EVERY`]
//! ticks, and a footer. Every line ends with a `"sum"` field, a checksum of the rest of the line,
//! so that a flipped byte anywhere is caught as a corrupt line rather than silently replayed.
//!
//! Tick semantics: an event stamped `tick: t` applies at the start of tick `t`, that is, it is
//! pushed when `sim.res.tick == t`, before the step. A checkpoint stamped `tick: T` is the world
//! hash when `sim.res.tick == T` (after `T` steps, before the events of tick `T`).
//!
//! The reader streams the file line by line with a bounded line length, so a huge file of
//! garbage is rejected at its first line without being read into memory.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::hash::{hex, WorldHash, COMPONENTS};
use crate::input::{InputEvent, StampedEvent};
use crate::resources::{Config, Override};
use crate::scene::Scene;
use crate::sim::Sim;

/// The format version this build writes.
pub const FORMAT_VERSION: u32 = 1;
/// The versions this build reads.
pub const READABLE_VERSIONS: &[u32] = &[1];
/// The value of the header's `format` field.
pub const FORMAT_NAME: &str = "grove-replay";
/// Ticks between checkpoints.
pub const CHECKPOINT_EVERY: u64 = 60;
/// The longest line the reader accepts, bytes.
pub const MAX_LINE: usize = 1 << 20;

/// The first line of a recording.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Header {
    /// Always [`FORMAT_NAME`].
    pub format: String,
    /// The format version, see [`FORMAT_VERSION`].
    pub format_version: u32,
    /// The grove version that wrote the file.
    pub grove_version: String,
    /// A built-in scene name (e.g. "study") or a path to a scene file.
    pub scene: String,
    /// The study task id, if the session ran one.
    #[serde(default)]
    pub task: Option<String>,
    /// The participant id, e.g. "P01".
    #[serde(default)]
    pub participant: Option<String>,
    /// The RNG seed.
    pub seed: u64,
    /// The fixed step, seconds; must equal the scene's.
    pub dt: f32,
    /// Whether the session was generated rather than recorded from a person.
    pub synthetic: bool,
    /// Configuration overrides in effect during the session (names as in [`Config::set`]).
    #[serde(default)]
    pub config: BTreeMap<String, String>,
}

impl Header {
    /// A header for a new recording with this build's format and version.
    pub fn new(scene: &str, seed: u64, dt: f32) -> Header {
        Header {
            format: FORMAT_NAME.into(),
            format_version: FORMAT_VERSION,
            grove_version: env!("CARGO_PKG_VERSION").into(),
            scene: scene.into(),
            task: None,
            participant: None,
            seed,
            dt,
            synthetic: false,
            config: BTreeMap::new(),
        }
    }
}

/// An input event line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventLine {
    /// The tick at whose start the event applies.
    pub tick: u64,
    /// Wall-clock milliseconds since the recording started.
    pub ms: u64,
    /// The display frame number at which the event was captured.
    pub frame: u64,
    /// The event.
    pub event: InputEvent,
}

/// A checkpoint line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckpointLine {
    /// The tick (number of completed steps) the hash was taken at.
    pub tick: u64,
    /// The total world hash, 16 hex digits.
    pub hash: String,
    /// Hash per component type, 16 hex digits each.
    pub components: BTreeMap<String, String>,
    /// Hash per entity (entity id bits in decimal → 16 hex digits).
    pub entities: BTreeMap<String, String>,
}

/// The last line of a complete recording.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FooterLine {
    /// The tick the recording ended at.
    pub final_tick: u64,
    /// The world hash at `final_tick`.
    pub final_hash: String,
    /// Free-form summary: counts and, for tasks, the recorder's own view of the outcome.
    /// Readers never trust it; replays recompute everything.
    pub summary: serde_json::Value,
}

/// One line of a recording.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Line {
    /// The header.
    Header(Header),
    /// An input event.
    Event(EventLine),
    /// A checkpoint.
    Checkpoint(CheckpointLine),
    /// The footer.
    Footer(FooterLine),
}

/// An event line read directly (see [`decode_line`]).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TaggedEvent {
    #[serde(rename = "type")]
    kind: String,
    tick: u64,
    ms: u64,
    frame: u64,
    event: InputEvent,
}

/// A controller-pose event line read directly (see [`decode_line`]).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TaggedPose {
    #[serde(rename = "type")]
    kind: String,
    tick: u64,
    ms: u64,
    frame: u64,
    event: PoseBody,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PoseBody {
    kind: String,
    pose: crate::components::Pose,
}

/// The checksum of a line's text (without its `sum` field): 8 hex digits.
pub fn line_sum(text: &str) -> String {
    format!("{:08x}", xxhash_rust::xxh3::xxh3_64(text.as_bytes()) as u32)
}

const SUM_KEY: &str = ",\"sum\":\"";

/// Serializes a line with its checksum, without the trailing newline.
pub fn encode_line(line: &Line) -> String {
    // Serializing these plain types to JSON cannot fail.
    let body = serde_json::to_string(line).unwrap_or_default();
    let sum = line_sum(&body);
    let mut out = String::with_capacity(body.len() + 20);
    out.push_str(&body[..body.len() - 1]);
    out.push_str(SUM_KEY);
    out.push_str(&sum);
    out.push_str("\"}");
    out
}

/// Checks a line's checksum and parses it.
pub fn decode_line(text: &str) -> Result<Line, String> {
    let text = text.trim_end_matches(['\r', '\n']);
    // The sum is always the last field: `,"sum":"` + 8 hex digits + `"}` = 18 bytes.
    let idx = text.len().checked_sub(SUM_KEY.len() + 10).filter(|&i| text.is_char_boundary(i) && text[i..].starts_with(SUM_KEY));
    let idx = idx.ok_or("no checksum (\"sum\" field) at the end; the line is truncated or not a grove recording")?;
    let tail = &text[idx + SUM_KEY.len()..];
    if !tail.ends_with("\"}") {
        return Err("malformed checksum field; the line is truncated or corrupt".into());
    }
    let sum = &tail[..8];
    let body = format!("{}}}", &text[..idx]);
    if line_sum(&body) != sum {
        return Err("checksum mismatch: the line was changed or corrupted".into());
    }
    // Event lines are by far the most common: read them straight into their struct, without
    // the buffering that the tagged `Line` enum needs.
    if body.starts_with("{\"type\":\"event\",") {
        // Controller poses are most of a recording: read them without the buffering that the
        // tagged `InputEvent` enum needs.
        if let Ok(e) = serde_json::from_str::<TaggedPose>(&body)
            && e.kind == "event"
            && e.event.kind == "controller_pose"
        {
            let event = InputEvent::ControllerPose { pose: e.event.pose };
            event.validate()?;
            return Ok(Line::Event(EventLine { tick: e.tick, ms: e.ms, frame: e.frame, event }));
        }
        let e: TaggedEvent = serde_json::from_str(&body).map_err(|e| {
            let msg = e.to_string();
            msg.split(" at line ").next().unwrap_or(&msg).to_string()
        })?;
        if e.kind != "event" {
            return Err(format!("unexpected line type '{}'", e.kind));
        }
        e.event.validate()?;
        return Ok(Line::Event(EventLine { tick: e.tick, ms: e.ms, frame: e.frame, event: e.event }));
    }
    let line: Line = serde_json::from_str(&body).map_err(|e| {
        let msg = e.to_string();
        // serde_json reports positions within the line; the caller adds the line number.
        msg.split(" at line ").next().unwrap_or(&msg).to_string()
    })?;
    if let Line::Event(ev) = &line {
        ev.event.validate()?;
    }
    Ok(line)
}

/// Builds a checkpoint line from a world hash.
pub fn checkpoint_line(tick: u64, h: &WorldHash) -> CheckpointLine {
    CheckpointLine {
        tick,
        hash: hex(h.total),
        components: h.components.iter().map(|(n, v)| (n.to_string(), hex(*v))).collect(),
        entities: h.entities.iter().map(|(e, v)| (e.to_string(), hex(*v))).collect(),
    }
}

/// Writes a recording while a session runs. Lines are appended and flushed at every checkpoint
/// (once a simulated second) and on [`Recorder::flush`], so a killed writer loses at most the
/// last second.
pub struct Recorder<W: Write> {
    out: W,
    events: u64,
    checkpoints: u64,
    last_tick: u64,
}

impl<W: Write> Recorder<W> {
    /// Starts a recording by writing its header.
    pub fn new(mut out: W, header: &Header) -> std::io::Result<Recorder<W>> {
        writeln!(out, "{}", encode_line(&Line::Header(header.clone())))?;
        out.flush()?;
        Ok(Recorder { out, events: 0, checkpoints: 0, last_tick: 0 })
    }

    /// Records an event that applies at `tick`.
    pub fn event(&mut self, tick: u64, ms: u64, frame: u64, event: &InputEvent) -> std::io::Result<()> {
        self.events += 1;
        self.last_tick = self.last_tick.max(tick);
        let line = Line::Event(EventLine { tick, ms, frame, event: event.clone() });
        writeln!(self.out, "{}", encode_line(&line))
    }

    /// Call after every step: writes a checkpoint (and flushes) when the tick is a multiple of
    /// [`CHECKPOINT_EVERY`].
    pub fn after_step(&mut self, sim: &Sim) -> std::io::Result<()> {
        let tick = sim.res.tick;
        self.last_tick = tick;
        if tick % CHECKPOINT_EVERY == 0 {
            self.checkpoints += 1;
            let line = Line::Checkpoint(checkpoint_line(tick, &sim.hash()));
            writeln!(self.out, "{}", encode_line(&line))?;
            self.out.flush()?;
        }
        Ok(())
    }

    /// Flushes buffered lines to the file.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }

    /// Writes the footer and returns the writer.
    pub fn finish(mut self, sim: &Sim, summary: serde_json::Value) -> std::io::Result<W> {
        let mut summary = summary;
        if let serde_json::Value::Object(map) = &mut summary {
            map.insert("events".into(), self.events.into());
            map.insert("checkpoints".into(), self.checkpoints.into());
        }
        let line = Line::Footer(FooterLine { final_tick: sim.res.tick, final_hash: hex(sim.hash().total), summary });
        writeln!(self.out, "{}", encode_line(&line))?;
        self.out.flush()?;
        Ok(self.out)
    }
}

/// Builds the simulation a header describes: its scene (built-in name or path, relative paths
/// resolved against `base_dir` and then the working directory), seed, and config overrides.
pub fn sim_for_header(header: &Header, base_dir: Option<&Path>, overrides: &[Override]) -> Result<Sim, String> {
    let scene = match Scene::builtin(&header.scene) {
        Some(s) => s,
        None => {
            let p = Path::new(&header.scene);
            let candidate = base_dir.map(|b| b.join(p)).filter(|c| c.exists()).unwrap_or_else(|| p.to_path_buf());
            Scene::load(&candidate).map_err(|e| format!("scene: {e}"))?
        }
    };
    if (scene.dt - header.dt).abs() > 1e-9 {
        return Err(format!("header dt {} differs from the scene's dt {}", header.dt, scene.dt));
    }
    let mut sim = Sim::from_scene(&scene, header.seed)?;
    let mut config = Config::default();
    for (k, v) in &header.config {
        config.set(k, v)?;
    }
    config.apply(overrides)?;
    sim.res.config = config;
    Ok(sim)
}

/// Re-simulates a list of stamped events from a fresh simulation and writes the full recording
/// (header, events, checkpoints, footer). Tests and synthetic participants use this, so every
/// checkpoint in their files comes from the simulation itself.
pub fn record_events<W: Write>(out: W, header: &Header, events: &[StampedEvent], end_tick: u64, summary: serde_json::Value) -> Result<W, String> {
    let mut sim = sim_for_header(header, None, &[])?;
    let mut rec = Recorder::new(out, header).map_err(|e| e.to_string())?;
    let mut i = 0;
    let end = end_tick.max(events.last().map_or(0, |e| e.tick + 1));
    while sim.res.tick < end {
        let start = i;
        while i < events.len() && events[i].tick == sim.res.tick {
            let e = &events[i];
            let ms = (e.tick as f64 * header.dt as f64 * 1000.0).round() as u64;
            rec.event(e.tick, ms, e.tick, &e.event).map_err(|e| e.to_string())?;
            i += 1;
        }
        if i < events.len() && events[i].tick < sim.res.tick {
            return Err(format!("event {i} is stamped tick {} but the recording is at tick {}", events[i].tick, sim.res.tick));
        }
        sim.step_with(events[start..i].iter().map(|e| e.event.clone()))?;
        rec.after_step(&sim).map_err(|e| e.to_string())?;
    }
    rec.finish(&sim, summary).map_err(|e| e.to_string())
}

/// A replay input problem: which line, and what. Its `Display` is one line.
#[derive(Debug, thiserror::Error)]
#[error("{file}{}: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct ReplayError {
    /// The file.
    pub file: String,
    /// The 1-based line number, where one applies.
    pub line: Option<u64>,
    /// What is wrong.
    pub message: String,
}

/// One (entity, component) pair that differs at a divergent checkpoint.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Differing {
    /// The entity, as id bits in decimal, or "resources".
    pub entity: String,
    /// The component type.
    pub component: String,
}

/// The first checkpoint at which the replay and the recording disagree.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Divergence {
    /// The checkpoint's tick.
    pub tick: u64,
    /// The recorded hash.
    pub expected_hash: String,
    /// The re-simulated hash.
    pub actual_hash: String,
    /// Which entities and components differ.
    pub differing: Vec<Differing>,
}

/// The outcome of a replay.
pub struct ReplayOutcome {
    /// The header.
    pub header: Header,
    /// The simulation at the end of the replay.
    pub sim: Sim,
    /// Whether the file had a footer (and `--until` did not stop early).
    pub complete: bool,
    /// Checkpoints compared (including the footer's final hash).
    pub checkpoints_checked: u64,
    /// The first divergence, if any. The replay goes on to the end of the file, but compares no
    /// further checkpoints.
    pub first_divergence: Option<Divergence>,
    /// Event counts by kind.
    pub events: BTreeMap<String, u64>,
    /// Whether checkpoints were compared at all (false for what-if runs).
    pub verifying: bool,
}

/// Options of a replay.
#[derive(Clone, Debug, Default)]
pub struct ReplayOptions {
    /// Stop at this tick.
    pub until: Option<u64>,
    /// Config overrides (what-if): checkpoints are then not compared.
    pub overrides: Vec<Override>,
}

/// The (entity, component) pairs that differ between a recorded checkpoint and the world: the
/// entities whose hash differs crossed with the component types whose hash differs, keeping
/// only pairs where the entity (still) has that component.
fn differing(expected: &CheckpointLine, actual: &WorldHash, world: &hecs::World) -> Vec<Differing> {
    let comps: Vec<&str> = COMPONENTS
        .iter()
        .copied()
        .filter(|c| expected.components.get(*c).map(String::as_str) != actual.component(c).map(hex).as_deref())
        .collect();
    let actual_entities: BTreeMap<String, String> = actual.entities.iter().map(|(e, h)| (e.to_string(), hex(*h))).collect();
    let mut ents: Vec<String> = expected
        .entities
        .iter()
        .filter(|(e, h)| actual_entities.get(*e) != Some(*h))
        .map(|(e, _)| e.clone())
        .chain(actual_entities.keys().filter(|e| !expected.entities.contains_key(*e)).cloned())
        .collect();
    ents.sort_by_key(|e| e.parse::<u64>().unwrap_or(u64::MAX));
    ents.dedup();
    let mut out = Vec::new();
    for c in &comps {
        if *c == "resources" {
            out.push(Differing { entity: "resources".into(), component: "resources".into() });
            continue;
        }
        let before = out.len();
        for e in &ents {
            let bits = e.parse::<u64>().unwrap_or(0);
            if crate::hash::has_component(world, bits, c) || !actual_entities.contains_key(e) {
                out.push(Differing { entity: e.clone(), component: (*c).to_string() });
            }
        }
        if out.len() == before {
            out.push(Differing { entity: "?".into(), component: (*c).to_string() });
        }
    }
    out
}

/// Reads lines with a length limit, never holding more than one line in memory.
struct LineReader<R: Read> {
    inner: BufReader<R>,
    buf: Vec<u8>,
    number: u64,
}

enum NextLine {
    Line(String),
    /// The file ended with bytes that have no newline: a line cut by a killed writer.
    Cut,
    End,
}

impl<R: Read> LineReader<R> {
    fn next(&mut self) -> Result<NextLine, String> {
        self.buf.clear();
        self.number += 1;
        loop {
            let chunk = self.inner.fill_buf().map_err(|e| e.to_string())?;
            if chunk.is_empty() {
                return Ok(if self.buf.is_empty() { NextLine::End } else { NextLine::Cut });
            }
            if let Some(pos) = chunk.iter().position(|&b| b == b'\n') {
                self.buf.extend_from_slice(&chunk[..pos]);
                self.inner.consume(pos + 1);
                break;
            }
            let n = chunk.len();
            self.buf.extend_from_slice(chunk);
            self.inner.consume(n);
            if self.buf.len() > MAX_LINE {
                return Err(format!("line longer than {} bytes; not a grove recording", MAX_LINE));
            }
        }
        if self.buf.len() > MAX_LINE {
            return Err(format!("line longer than {} bytes; not a grove recording", MAX_LINE));
        }
        String::from_utf8(std::mem::take(&mut self.buf)).map(NextLine::Line).map_err(|_| "not valid UTF-8 text".into())
    }
}

/// Replays a recording from a reader. `file` names it in errors; `base_dir` resolves a relative
/// scene path. Checkpoints are verified unless `options.overrides` is non-empty (a what-if run).
pub fn replay_reader<R: Read>(reader: R, file: &str, base_dir: Option<&Path>, options: &ReplayOptions) -> Result<ReplayOutcome, ReplayError> {
    let err = |line: Option<u64>, message: String| ReplayError { file: file.to_string(), line, message };
    let mut lines = LineReader { inner: BufReader::with_capacity(64 * 1024, reader), buf: Vec::new(), number: 0 };
    let first = match lines.next().map_err(|m| err(Some(1), m))? {
        NextLine::End => return Err(err(None, "empty file; expected a grove recording header".into())),
        NextLine::Cut => return Err(err(Some(1), "the header line is cut off (no newline)".into())),
        NextLine::Line(l) => l,
    };
    // Look at the version before anything else, so a future format gets a clear message.
    if let Ok(v) = serde_json::from_str::<serde_json::Value>(first.trim()) {
        if v.get("type").and_then(|t| t.as_str()) == Some("header") {
            if let Some(ver) = v.get("format_version").and_then(|x| x.as_u64()) {
                if !READABLE_VERSIONS.contains(&(ver as u32)) {
                    return Err(err(
                        Some(1),
                        format!("format version {ver} is not supported; this grove reads versions {:?} (upgrade grove to read newer files)", READABLE_VERSIONS),
                    ));
                }
            }
        }
    }
    let header = match decode_line(&first).map_err(|m| err(Some(1), m))? {
        Line::Header(h) => h,
        _ => return Err(err(Some(1), "missing header: the first line must be the recording header".into())),
    };
    if header.format != FORMAT_NAME {
        return Err(err(Some(1), format!("format '{}' is not '{FORMAT_NAME}'", header.format)));
    }
    let verifying = options.overrides.is_empty();
    let mut sim = sim_for_header(&header, base_dir, &options.overrides).map_err(|m| err(Some(1), m))?;
    let mut outcome_events: BTreeMap<String, u64> = BTreeMap::new();
    let mut checkpoints_checked = 0;
    let mut first_divergence = None;
    let mut complete = false;
    let mut last_tick = 0u64;
    let mut stopped_early = false;
    let until = options.until.unwrap_or(u64::MAX);

    // The events read for the coming tick, applied with the step that reaches the next line's
    // tick (each was validated when read).
    let mut pending: Vec<InputEvent> = Vec::new();
    let advance = |sim: &mut Sim, pending: &mut Vec<InputEvent>, to: u64| {
        while sim.res.tick < to.min(until) {
            let _ = sim.step_with(pending.drain(..));
        }
    };

    loop {
        let n = lines.number + 1;
        let text = match lines.next().map_err(|m| err(Some(n), m))? {
            NextLine::End | NextLine::Cut => break,
            NextLine::Line(l) => l,
        };
        if text.trim().is_empty() {
            return Err(err(Some(n), "empty line".into()));
        }
        if complete {
            return Err(err(Some(n), "a line after the footer".into()));
        }
        let line = decode_line(&text).map_err(|m| err(Some(n), m))?;
        let tick = match &line {
            Line::Header(_) => return Err(err(Some(n), "a second header".into())),
            Line::Event(e) => e.tick,
            Line::Checkpoint(c) => c.tick,
            Line::Footer(f) => f.final_tick,
        };
        if tick < last_tick {
            return Err(err(Some(n), format!("tick {tick} comes after tick {last_tick}: ticks out of order")));
        }
        last_tick = tick;
        if tick > until {
            stopped_early = true;
            break;
        }
        advance(&mut sim, &mut pending, tick);
        match line {
            Line::Header(_) => {}
            Line::Event(e) => {
                *outcome_events.entry(e.event.kind().to_string()).or_default() += 1;
                e.event.validate().map_err(|m| err(Some(n), m))?;
                pending.push(e.event);
            }
            Line::Checkpoint(c) => {
                if verifying && first_divergence.is_none() {
                    let h = sim.hash();
                    checkpoints_checked += 1;
                    if hex(h.total) != c.hash {
                        first_divergence = Some(Divergence { tick, expected_hash: c.hash.clone(), actual_hash: hex(h.total), differing: differing(&c, &h, &sim.world) });
                    }
                }
            }
            Line::Footer(f) => {
                if verifying && first_divergence.is_none() {
                    let h = sim.hash();
                    checkpoints_checked += 1;
                    if hex(h.total) != f.final_hash {
                        first_divergence = Some(Divergence { tick, expected_hash: f.final_hash.clone(), actual_hash: hex(h.total), differing: Vec::new() });
                    }
                }
                complete = true;
            }
        }
    }
    if stopped_early {
        advance(&mut sim, &mut pending, until);
    }
    // Events of a tick the recording ends at wait in the input queue, as a live session leaves them.
    for event in pending {
        let _ = sim.push_input(event);
    }
    Ok(ReplayOutcome { header, sim, complete: complete && !stopped_early, checkpoints_checked, first_divergence, events: outcome_events, verifying })
}

/// Replays a recording file. Directories, missing files and unreadable files give an error.
pub fn replay_file(path: &Path, options: &ReplayOptions) -> Result<ReplayOutcome, ReplayError> {
    let file = path.display().to_string();
    if path.is_dir() {
        return Err(ReplayError { file, line: None, message: "is a directory, not a recording".into() });
    }
    let f = std::fs::File::open(path).map_err(|e| ReplayError { file: file.clone(), line: None, message: crate::scene::io_message(&e) })?;
    replay_reader(f, &file, path.parent(), options)
}

/// Reads just the stamped events of a recording (no simulation), e.g. to re-record or edit it.
pub fn read_events(path: &Path) -> Result<(Header, Vec<StampedEvent>), ReplayError> {
    let file = path.display().to_string();
    let err = |line: Option<u64>, message: String| ReplayError { file: file.clone(), line, message };
    let f = std::fs::File::open(path).map_err(|e| err(None, crate::scene::io_message(&e)))?;
    let mut lines = LineReader { inner: BufReader::new(f), buf: Vec::new(), number: 0 };
    let mut header = None;
    let mut events = Vec::new();
    loop {
        let n = lines.number + 1;
        match lines.next().map_err(|m| err(Some(n), m))? {
            NextLine::End | NextLine::Cut => break,
            NextLine::Line(text) => match decode_line(&text).map_err(|m| err(Some(n), m))? {
                Line::Header(h) => header = Some(h),
                Line::Event(e) => events.push(StampedEvent { tick: e.tick, event: e.event }),
                _ => {}
            },
        }
    }
    Ok((header.ok_or_else(|| err(Some(1), "missing header".into()))?, events))
}
