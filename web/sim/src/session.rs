//! [`Session`]: one simulation driven from JavaScript: events pushed as JSON, one tick per
//! step, and the recording's lines handed back as they are made.
//!
//! Every call either does what it says or returns an [`Error`] and leaves the session as it was:
//! an event is checked (its kind, numbers, names and tick) before it is queued, and a step or
//! the footer is refused before anything changes.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::io::Write;
use std::rc::Rc;

use grove_systems::input::InputEvent;
use grove_systems::limits::MAX_TICKS;
use grove_systems::replay::codec::event_from_value;
use grove_systems::replay::names::check_event;
use grove_systems::replay::{sim_for_header_with_scene, Header, Recorder};
use grove_systems::snapshot::Snapshot;
use grove_systems::Sim;
use serde::Deserialize;

use crate::error::Error;
use crate::options::{Options, Start};

/// At most this many events wait for later ticks.
pub const MAX_PENDING: usize = 1 << 20;

/// Where the recorder writes: lines wait here until the call that made them returns them.
#[derive(Clone, Default)]
struct Sink(Rc<RefCell<Vec<u8>>>);

impl Write for Sink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Sink {
    /// The complete lines written since the last call, without their newlines.
    fn take(&self) -> Vec<String> {
        let bytes = std::mem::take(&mut *self.0.borrow_mut());
        String::from_utf8_lossy(&bytes).lines().map(str::to_string).collect()
    }
}

/// An event waiting for its tick.
struct Pending {
    tick: u64,
    ms: Option<u64>,
    frame: Option<u64>,
    event: InputEvent,
}

/// An event as a recording's event line holds it (its `sum`, if any, is ignored: it belongs to
/// the line's place in its own file).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EventLineIn {
    #[serde(rename = "type")]
    kind: Option<String>,
    tick: u64,
    ms: Option<u64>,
    frame: Option<u64>,
    event: serde_json::Value,
    #[allow(dead_code)]
    sum: Option<String>,
}

/// One simulation with its optional recorder.
pub struct Session {
    sim: Sim,
    header: Header,
    /// Completed steps (the simulation's tick).
    tick: u64,
    pending: VecDeque<Pending>,
    sink: Sink,
    recorder: Option<Recorder<Sink>>,
    finished: bool,
}

impl Session {
    /// A simulation from its options ([`Options`]); the lines made so far (the header line of
    /// a recording the session makes itself; none otherwise).
    pub fn new(options: &str) -> Result<(Session, Vec<String>), Error> {
        crate::install_techniques();
        let mut options = Options::parse(options)?;
        if let Some(stage) = options.stage.take() {
            return Self::stage(&stage, &options);
        }
        let record = options.record || options.header.is_some();
        let Start { header, scene, given_header, technique } = options.start()?;
        let sim = sim_for_header_with_scene(&header, scene, &[], &Default::default())?;
        let sink = Sink::default();
        let recorder = match (record, given_header) {
            (false, _) => None,
            (true, true) => Some(Recorder::continuing(sink.clone())),
            (true, false) => Some(Recorder::new(sink.clone(), &header).map_err(|e| Error::input("recorder", e))?),
        };
        let mut session = Session { sim, header, tick: 0, pending: VecDeque::new(), sink, recorder, finished: false };
        if let Some(technique) = technique {
            session.queue(0, None, None, InputEvent::SwitchTechnique { technique })?;
        }
        let lines = session.sink.take();
        Ok((session, lines))
    }

    /// The model stage of `stage` ([`crate::options::StageOptions`]): no other option may be
    /// given, and nothing is recorded.
    fn stage(stage: &crate::options::StageOptions, rest: &Options) -> Result<(Session, Vec<String>), Error> {
        let given = rest.scene.is_some() || rest.scene_text.is_some() || rest.seed.is_some() || !rest.set.is_empty() || rest.record || rest.header.is_some() || rest.task.is_some() || rest.participant.is_some() || rest.technique.is_some();
        if given {
            return Err(Error::input("options", "`stage` is given with another option: a stage is a scene of its own and records nothing"));
        }
        let sim = stage.sim()?;
        let header = Header::new("model stage", 1, sim.dt());
        Ok((Session { sim, header, tick: 0, pending: VecDeque::new(), sink: Sink::default(), recorder: None, finished: false }, Vec::new()))
    }

    /// The recording's header (made here, or the one handed over).
    pub fn header(&self) -> &Header {
        &self.header
    }

    /// Completed steps.
    pub fn tick(&self) -> u64 {
        self.tick
    }

    /// The simulation.
    pub fn sim(&self) -> &Sim {
        &self.sim
    }

    /// Queues an event: an event line's object (`{"tick": …, "event": {…}}`, with `ms` and
    /// `frame` if known) for that tick, or an event alone (`{"kind": …}`) for the coming step.
    /// Ticks never go back: an event stamped before the simulation's tick or before an event
    /// already queued is refused.
    pub fn push(&mut self, json: &str) -> Result<(), Error> {
        let value: serde_json::Value = serde_json::from_str(json).map_err(|e| Error::input("event", e))?;
        let is_line = value.as_object().is_some_and(|m| m.contains_key("event") || m.contains_key("tick"));
        let (tick, ms, frame, event) = if is_line {
            let line: EventLineIn = serde_json::from_value(value).map_err(|e| Error::input("event line", e))?;
            if line.kind.as_deref().is_some_and(|k| k != "event") {
                return Err(Error::input("event line", format!("type {:?} is not \"event\"", line.kind.unwrap_or_default())));
            }
            (line.tick, line.ms, line.frame, line.event)
        } else {
            (self.tick, None, None, value)
        };
        let event = event_from_value(event).map_err(|e| Error::Event(e.to_string()))?;
        self.queue(tick, ms, frame, event)
    }

    fn queue(&mut self, tick: u64, ms: Option<u64>, frame: Option<u64>, event: InputEvent) -> Result<(), Error> {
        if self.finished {
            return Err(Error::Finished);
        }
        if tick >= MAX_TICKS {
            return Err(Error::TickLimit { tick });
        }
        if tick < self.tick {
            return Err(Error::OutOfOrder { tick, reason: format!("the simulation is at tick {}", self.tick) });
        }
        if let Some(last) = self.pending.back()
            && tick < last.tick
        {
            return Err(Error::OutOfOrder { tick, reason: format!("an event stamped tick {} was pushed before it", last.tick) });
        }
        if self.pending.len() >= MAX_PENDING {
            return Err(Error::Backlog(MAX_PENDING));
        }
        check_event(&event, &self.sim).map_err(|e| Error::Event(e.to_string()))?;
        self.pending.push_back(Pending { tick, ms, frame, event });
        Ok(())
    }

    /// Applies the events stamped with the coming tick and runs one fixed step; returns the
    /// recording's lines this made (its events, and a checkpoint every 60 ticks).
    pub fn step(&mut self) -> Result<Vec<String>, Error> {
        if self.finished {
            return Err(Error::Finished);
        }
        if self.tick >= MAX_TICKS {
            return Err(Error::TickLimit { tick: self.tick + 1 });
        }
        let tick = self.tick;
        let mut events = Vec::new();
        while self.pending.front().is_some_and(|p| p.tick == tick) {
            let Some(p) = self.pending.pop_front() else { break };
            if let Some(r) = self.recorder.as_mut() {
                let ms = p.ms.unwrap_or_else(|| (tick as f64 * self.header.dt as f64 * 1000.0).round() as u64);
                r.event(tick, ms, p.frame.unwrap_or(tick), &p.event).map_err(|e| Error::input("recorder", e))?;
            }
            events.push(p.event);
        }
        // Every event was checked when it was queued.
        self.sim.step_with(events).map_err(|e| Error::Event(e.to_string()))?;
        self.tick += 1;
        if let Some(r) = self.recorder.as_mut() {
            r.after_step(&self.sim).map_err(|e| Error::input("recorder", e))?;
        }
        Ok(self.sink.take())
    }

    /// The world as a renderer and a task panel read it.
    pub fn snapshot(&self) -> Snapshot {
        self.sim.snapshot()
    }

    /// The ground planes as a renderer draws them: each plane's name and entity id bits, its
    /// vertices (x, y, z after one another, metres) and its triangles (three vertex indices
    /// each, counter-clockwise seen from above), by entity id.
    pub fn ground(&self) -> Vec<serde_json::Value> {
        let mut planes = Vec::new();
        self.sim.for_each_plane(|id, p| {
            let vertices: Vec<f32> = p.vertices.iter().flat_map(|v| v.to_array()).collect();
            let triangles: Vec<u32> = p.triangles.iter().flatten().copied().collect();
            planes.push((id, serde_json::json!({ "id": id, "name": p.name, "vertices": vertices, "triangles": triangles })));
        });
        planes.sort_by_key(|(id, _)| *id);
        planes.into_iter().map(|(_, v)| v).collect()
    }

    /// The world hash, 16 hex digits.
    pub fn hash(&self) -> String {
        grove_systems::hash::hex(self.sim.hash().total)
    }

    /// Ends the recording: events still queued are applied first (a step for each of their
    /// ticks), then the footer is written; returns the lines this made. Afterwards the session
    /// takes no more events or steps. Without a recorder, nothing happens.
    pub fn finish(&mut self) -> Result<Vec<String>, Error> {
        if self.finished {
            return Err(Error::Finished);
        }
        if self.recorder.is_none() {
            return Ok(Vec::new());
        }
        if let Some(last) = self.pending.back() {
            let end = last.tick + 1;
            if end > MAX_TICKS {
                return Err(Error::TickLimit { tick: end });
            }
        }
        let mut lines = Vec::new();
        while !self.pending.is_empty() {
            lines.extend(self.step()?);
        }
        let snapshot = self.sim.snapshot();
        let summary = serde_json::json!({
            "trees": snapshot.trees.len(),
            "task": snapshot.task.as_ref().map(|t| t.id.clone()),
            "task_completed": snapshot.task.as_ref().map(|t| t.completed),
        });
        if let Some(r) = self.recorder.take() {
            r.finish(&self.sim, summary).map_err(|e| Error::input("recorder", e))?;
        }
        self.finished = true;
        lines.extend(self.sink.take());
        Ok(lines)
    }
}

impl std::fmt::Debug for Session {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Session").field("tick", &self.tick).field("pending", &self.pending.len()).field("recording", &self.recorder.is_some()).field("finished", &self.finished).finish()
    }
}
