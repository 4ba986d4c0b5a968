//! Recordings and replays: the versioned JSON Lines format, a writer and a verifying reader.
//!
//! `docs/replay-format.md` documents the format. In short, a recording is one JSON object per
//! line: a header, then input events ordered by tick, checkpoints every [`CHECKPOINT_EVERY`]
//! ticks, and a footer. Every line ends with a `"sum"` field, a checksum of the rest of the line
//! that in version 2 also covers the previous line's checksum ([`codec`]), so that a flipped
//! byte, or a deleted, duplicated or moved line, is caught rather than silently replayed.
//!
//! Tick semantics: an event stamped `tick: t` applies at the start of tick `t`, that is, it is
//! pushed when `sim.res.tick == t`, before the step. A checkpoint stamped `tick: T` is the world
//! hash when `sim.res.tick == T` (after `T` steps, before the events of tick `T`).
//!
//! The reader ([`reader`]) streams the file line by line with a bounded line length, and bounds
//! the ticks a file can ask for ([`crate::limits`]), so a hostile file is refused in bounded time
//! and memory. The scene a header names is resolved by [`scene_ref`].

pub mod codec;
mod fast_checkpoint;
mod fast_pose;
pub mod line_rules;
mod lines;
pub mod names;
pub mod player;
pub mod reader;
pub mod report;
pub mod scene_ref;
pub mod session_header;
pub mod upgrade;
pub mod verdict;
pub mod verifier;

use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};

pub use codec::{chained_sum, decode_line, decode_line_chained, encode_line, encode_line_chained, line_sum, rechain, sign_body, split_sum, LineFormatError};
pub use line_rules::{header_line, LineRuleError, LineRules, RuledLine};
pub use names::NameError;
pub use scene_ref::SceneRefError;
pub use player::Player;
pub use reader::{read_events, replay_file, replay_reader, ReplayError, ReplayOptions, ReplayOutcome};
pub use report::ReplayReport;
pub use session_header::{session_start_at, SessionFields, SessionHeaderError};
pub use upgrade::{upgrade, UpgradeSummary};
pub use verifier::{Differing, Divergence, Verifier};

use crate::bank::{Banks, HeaderModel};
use crate::hash::{hex, WorldHash};
use crate::input::{InputEvent, StampedEvent};
use crate::resources::{Override, Overrides};
use crate::sim::Sim;

/// The format version this build writes.
pub const FORMAT_VERSION: u32 = 2;
/// The versions this build reads.
pub const READABLE_VERSIONS: &[u32] = &[1, 2];
/// The value of the header's `format` field.
pub const FORMAT_NAME: &str = "grove-replay";
/// Ticks between checkpoints. A reader refuses a line whose tick is more than this past the
/// last checkpoint (or the start): the recorder never skips one.
pub const CHECKPOINT_EVERY: u64 = 60;
/// The longest line the reader accepts, bytes.
pub const MAX_LINE: usize = crate::limits::MAX_LINE_BYTES;

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
    /// Configuration overrides in effect during the session, checked when the header is read.
    #[serde(default)]
    pub config: Overrides,
    /// Optional: the wall-clock time (UTC, RFC 3339, e.g. "2019-06-03T09:00:00Z") at which this
    /// recording started. Reports order a participant's recordings by it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub session_start: Option<String>,
    /// Optional: the 1-based block this recording belongs to in the participant's session.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub block: Option<u32>,
    /// Optional: the models of model banks the session's catalogue held beyond the shipped ones,
    /// in id order (ids 8, 9, …), with their content hashes. A replay finds them by name in the
    /// banks it is given and refuses when one is missing or its files changed. Absent when the
    /// session used only the shipped models.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub models: Vec<HeaderModel>,
    /// Optional: the plug-in technique the session used, with its version. A replay refuses a
    /// recording whose technique is not registered, or registered with another version. Absent
    /// when the session used only the built-in techniques, which its `switch_mode` events name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub technique: Option<HeaderTechnique>,
    /// Optional: the input device the session was made with ([`HeaderDevice`]). Absent in
    /// recordings made before devices were recorded (read as [`HeaderDevice::unknown`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub device: Option<HeaderDevice>,
}

/// The input device of a recording: the WebXR input source that pointed (or the preview's
/// mouse) and grove's mapping of it onto the controller (`docs/headset.md`, "Devices and their
/// mappings"). Each field is 1 to 64 lowercase letters, digits and `-`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeaderDevice {
    /// The input profile, the first of the XR input source's `profiles` (`meta-quest-touch-plus`,
    /// `generic-hand`, `generic-touchscreen` …), `mouse` for the preview.
    pub profile: String,
    /// The XR input source's target-ray mode (`tracked-pointer`, `transient-pointer`, `screen`),
    /// `none` for the preview's mouse.
    pub target_ray_mode: String,
    /// grove's mapping: `controller`, `controller-no-squeeze`, `hands`, `transient-pointer`,
    /// `screen` or `mouse`.
    pub mapping: String,
}

impl HeaderDevice {
    /// What a recording without a device reads as: a controller (every session before devices
    /// were recorded had one, or a desktop's mouse, keyboard or gamepad acting as one) of an
    /// unknown profile and target-ray mode.
    pub fn unknown() -> HeaderDevice {
        HeaderDevice { profile: "unknown".into(), target_ray_mode: "unknown".into(), mapping: "controller".into() }
    }
}

impl Header {
    /// The recording's device, or [`HeaderDevice::unknown`] when the header names none.
    pub fn device_or_unknown(&self) -> HeaderDevice {
        self.device.clone().unwrap_or_else(HeaderDevice::unknown)
    }
}

/// A recording's technique: its name and version ([`crate::technique::Technique`]).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeaderTechnique {
    /// The technique's name, e.g. "gaze-dwell".
    pub name: String,
    /// The technique's version when the recording was made.
    pub version: u32,
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
            config: Overrides::default(),
            session_start: None,
            block: None,
            models: Vec::new(),
            technique: None,
            device: None,
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

/// Builds a checkpoint line from a world hash.
pub fn checkpoint_line(tick: u64, h: &WorldHash) -> CheckpointLine {
    CheckpointLine {
        tick,
        hash: hex(h.total),
        components: h.components.iter().map(|(n, v)| (n.to_string(), hex(*v))).collect(),
        entities: h.entities.iter().map(|(e, v)| (e.to_string(), hex(*v))).collect(),
    }
}

/// Writes a recording while a session runs, in the current format version ([`FORMAT_VERSION`],
/// checksums chained line to line). Every event other than a pose (buttons, menu, model, mode
/// and task events) is flushed as soon as it is written, and every checkpoint (once a simulated
/// second); poses wait for the next flush or [`Recorder::flush`]. A killed writer therefore
/// loses no press, only at most the poses since the last flush.
pub struct Recorder<W: Write> {
    out: W,
    events: u64,
    checkpoints: u64,
    last_tick: u64,
    /// The previous line's checksum, which the next line's chains on.
    prev: u32,
}

impl<W: Write> Recorder<W> {
    /// Starts a recording by writing its header (with this build's format version, whatever
    /// `header.format_version` says).
    pub fn new(mut out: W, header: &Header) -> std::io::Result<Recorder<W>> {
        let mut header = header.clone();
        header.format_version = FORMAT_VERSION;
        writeln!(out, "{}", encode_line(&Line::Header(header)))?;
        out.flush()?;
        // The chain starts after the header (see `codec`).
        Ok(Recorder { out, events: 0, checkpoints: 0, last_tick: 0, prev: 0 })
    }

    /// Continues a recording whose header line someone else wrote (a server that hands the
    /// header to a page, which records the rest): nothing is written yet, and the first line's
    /// checksum chains on 0, as the line after a header always does (see `codec`).
    pub fn continuing(out: W) -> Recorder<W> {
        Recorder { out, events: 0, checkpoints: 0, last_tick: 0, prev: 0 }
    }

    fn write(&mut self, line: &Line) -> std::io::Result<()> {
        let (text, sum) = encode_line_chained(line, self.prev);
        self.prev = sum;
        writeln!(self.out, "{text}")
    }

    /// Records an event that applies at `tick`; flushes at once unless it is a pose.
    pub fn event(&mut self, tick: u64, ms: u64, frame: u64, event: &InputEvent) -> std::io::Result<()> {
        self.events += 1;
        self.last_tick = self.last_tick.max(tick);
        self.write(&Line::Event(EventLine { tick, ms, frame, event: event.clone() }))?;
        if !matches!(event, InputEvent::ControllerPose { .. } | InputEvent::HeadPose { .. } | InputEvent::TouchpadAxes { .. }) {
            self.out.flush()?;
        }
        Ok(())
    }

    /// Call after every step: writes a checkpoint (and flushes) when the tick is a multiple of
    /// [`CHECKPOINT_EVERY`].
    pub fn after_step(&mut self, sim: &Sim) -> std::io::Result<()> {
        let tick = sim.res.tick;
        self.last_tick = tick;
        if tick % CHECKPOINT_EVERY == 0 {
            self.checkpoints += 1;
            self.write(&Line::Checkpoint(checkpoint_line(tick, &sim.hash())))?;
            self.out.flush()?;
        }
        Ok(())
    }

    /// The writer, e.g. to see what has reached it.
    pub fn get_ref(&self) -> &W {
        &self.out
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
        self.write(&Line::Footer(FooterLine { final_tick: sim.res.tick, final_hash: hex(sim.hash().total), summary }))?;
        self.out.flush()?;
        Ok(self.out)
    }
}

/// Why the simulation a header describes could not be built ([`sim_for_header`]). Its `Display`
/// is one line, without the file's name (the caller adds it).
#[derive(Debug, thiserror::Error)]
pub enum HeaderError {
    /// A name the header uses does not exist, or a field is not well formed.
    #[error(transparent)]
    Names(#[from] NameError),
    /// The scene it names was refused.
    #[error(transparent)]
    Scene(#[from] SceneRefError),
    /// The model banks, or a model the header lists, could not be used.
    #[error(transparent)]
    Banks(#[from] crate::bank::BankError),
    /// The header's fixed step differs from the scene's.
    #[error("header dt {header} differs from the scene's dt {scene}")]
    Dt {
        /// The header's `dt`.
        header: f32,
        /// The scene's `dt`.
        scene: f32,
    },
    /// The simulation could not be built from the scene.
    #[error(transparent)]
    Sim(#[from] crate::sim::SimError),
    /// A config override (the header's or the caller's) was refused.
    #[error(transparent)]
    Config(#[from] crate::resources::ConfigError),
}

/// Why [`record_events`] could not write a recording.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The header's simulation could not be built.
    #[error(transparent)]
    Header(#[from] HeaderError),
    /// Writing to the output failed (the error's own message).
    #[error("{0}")]
    Write(std::io::Error),
    /// The events are not ordered by tick.
    #[error("event {index} is stamped tick {tick} but the recording is at tick {at}")]
    OutOfOrder {
        /// The event's index in the list.
        index: usize,
        /// Its tick.
        tick: u64,
        /// The tick the recording had reached.
        at: u64,
    },
    /// An event was refused by the simulation.
    #[error(transparent)]
    Event(#[from] crate::input::InvalidEvent),
}

/// Builds the simulation a header describes: its scene (a built-in name, or a `.ron` file inside
/// `base_dir` or the working directory, see [`scene_ref::resolve_scene`]), seed, and config
/// overrides.
pub fn sim_for_header(header: &Header, base_dir: Option<&Path>, overrides: &[Override]) -> Result<Sim, HeaderError> {
    sim_for_header_in(header, base_dir, overrides, &Banks::default())
}

/// Like [`sim_for_header`], with the model banks in which the header's models
/// ([`Header::models`]) are looked up; a missing or changed model is an error naming it.
pub fn sim_for_header_in(header: &Header, base_dir: Option<&Path>, overrides: &[Override], banks: &Banks) -> Result<Sim, HeaderError> {
    names::check_header(header)?;
    let scene = scene_ref::resolve_scene(&header.scene, base_dir)?;
    sim_for_header_with_scene(header, scene, overrides, banks)
}

/// Like [`sim_for_header_in`], with the scene already read (a page, or the WebAssembly module,
/// which has no file system, is handed the scene's text); the header's own `scene` field is then
/// only a name.
pub fn sim_for_header_with_scene(header: &Header, scene: crate::scene::Scene, overrides: &[Override], banks: &Banks) -> Result<Sim, HeaderError> {
    names::check_header(header)?;
    // The scene's own banks are searched first, as in the session that recorded it.
    let mut all = Banks::open(&scene.bank_dirs())?;
    all.banks.extend(banks.banks.iter().cloned());
    let catalogue = all.catalogue_for(&header.models)?;
    if (scene.dt - header.dt).abs() > 1e-9 {
        return Err(HeaderError::Dt { header: header.dt, scene: scene.dt });
    }
    let mut sim = Sim::from_scene_with(&scene, header.seed, catalogue)?;
    let mut config = header.config.config()?;
    config.apply(overrides)?;
    sim.res.config = config;
    Ok(sim)
}

/// Re-simulates a list of stamped events from a fresh simulation and writes the full recording
/// (header, events, checkpoints, footer). Tests and synthetic participants use this, so every
/// checkpoint in their files comes from the simulation itself.
pub fn record_events<W: Write>(out: W, header: &Header, events: &[StampedEvent], end_tick: u64, summary: serde_json::Value) -> Result<W, RecordError> {
    record_events_in(out, header, events, end_tick, summary, &Banks::default())
}

/// Like [`record_events`], for a header that lists models of these banks.
pub fn record_events_in<W: Write>(out: W, header: &Header, events: &[StampedEvent], end_tick: u64, summary: serde_json::Value, banks: &Banks) -> Result<W, RecordError> {
    record_events_beside(out, header, events, end_tick, summary, None, banks)
}

/// Like [`record_events_in`], with a scene the header names by path read relative to `base_dir`
/// (the recording's folder, as `replay_file` reads it) instead of the working directory.
pub fn record_events_beside<W: Write>(out: W, header: &Header, events: &[StampedEvent], end_tick: u64, summary: serde_json::Value, base_dir: Option<&Path>, banks: &Banks) -> Result<W, RecordError> {
    let mut sim = sim_for_header_in(header, base_dir, &[], banks)?;
    let mut rec = Recorder::new(out, header).map_err(RecordError::Write)?;
    let mut i = 0;
    let end = end_tick.max(events.last().map_or(0, |e| e.tick + 1));
    while sim.res.tick < end {
        let start = i;
        while i < events.len() && events[i].tick == sim.res.tick {
            let e = &events[i];
            let ms = (e.tick as f64 * header.dt as f64 * 1000.0).round() as u64;
            rec.event(e.tick, ms, e.tick, &e.event).map_err(RecordError::Write)?;
            i += 1;
        }
        if i < events.len() && events[i].tick < sim.res.tick {
            return Err(RecordError::OutOfOrder { index: i, tick: events[i].tick, at: sim.res.tick });
        }
        sim.step_with(events[start..i].iter().map(|e| e.event.clone()))?;
        rec.after_step(&sim).map_err(RecordError::Write)?;
    }
    rec.finish(&sim, summary).map_err(RecordError::Write)
}

