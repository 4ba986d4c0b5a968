//! A recording played forward one tick at a time, as the verifying replay steps it (the events
//! stamped with tick T applied with the step from T), for readers that look at every world on
//! the way: the HTML report's trace and the video writer.

use std::path::Path;

use crate::bank::Banks;
use crate::input::{InputEvent, StampedEvent};
use crate::resources::Override;
use crate::sim::Sim;

use super::lines::Lines;
use super::{Header, Line, ReplayError, sim_for_header_in};

/// A recording's events and the world they drive.
pub struct Player {
    /// The header.
    pub header: Header,
    events: Vec<StampedEvent>,
    next: usize,
    final_tick: u64,
    sim: Sim,
}

impl Player {
    /// Reads `path` (every line checked as [`super::replay_file`] checks it) and builds its
    /// world under `overrides`, with the header's models looked up in `banks`.
    pub fn open(path: &Path, overrides: &[Override], banks: &Banks) -> Result<Player, ReplayError> {
        let file = path.display().to_string();
        let err = |(line, message): (Option<u64>, String)| ReplayError { file: file.clone(), line, message };
        let (f, _) = crate::files::open(path, crate::files::Kind::Recording).map_err(|e| err((None, e.reason())))?;
        let mut lines = Lines::open(f).map_err(err)?;
        let mut events = Vec::new();
        let mut final_tick = None;
        while let Some(checked) = lines.next().map_err(err)? {
            match checked.line {
                Line::Event(e) => {
                    e.event.validate().map_err(|m| err((Some(checked.number), m.to_string())))?;
                    events.push(StampedEvent { tick: e.tick, event: e.event });
                }
                Line::Footer(f) => final_tick = Some(f.final_tick),
                _ => {}
            }
        }
        let header = lines.header.clone();
        let sim =
            sim_for_header_in(&header, path.parent(), overrides, banks).map_err(|m| err((None, m.to_string())))?;
        // A recording cut short (no footer) ends with its last event.
        let final_tick = final_tick.unwrap_or_else(|| events.last().map_or(0, |e| e.tick + 1));
        Ok(Player { header, events, next: 0, final_tick, sim })
    }

    /// The world now.
    pub fn sim(&self) -> &Sim {
        &self.sim
    }

    /// The tick the recording ends at (its footer's, or just after its last event).
    pub fn final_tick(&self) -> u64 {
        self.final_tick
    }

    /// The tick of the first `start_task` event, if any: where the task's clock starts.
    pub fn task_start_tick(&self) -> Option<u64> {
        self.events.iter().find(|e| matches!(e.event, InputEvent::StartTask { .. })).map(|e| e.tick)
    }

    /// The tick of the first `end_task` event, if any.
    pub fn task_end_tick(&self) -> Option<u64> {
        self.events.iter().find(|e| matches!(e.event, InputEvent::EndTask)).map(|e| e.tick)
    }

    /// Every event of the recording, in order.
    pub fn events(&self) -> &[StampedEvent] {
        &self.events
    }

    /// Runs one step with the events stamped at or before the current tick; returns them. An
    /// event the world refuses is dropped, as the verifying replay drops it, and the step runs.
    pub fn step(&mut self) -> &[StampedEvent] {
        let tick = self.sim.res.tick;
        let first = self.next;
        while self.next < self.events.len() && self.events[self.next].tick <= tick {
            self.next += 1;
        }
        let batch = &self.events[first..self.next];
        if self.sim.step_with(batch.iter().map(|e| e.event.clone())).is_err() && self.sim.res.tick == tick {
            self.sim.step();
        }
        batch
    }

    /// Steps until the world's tick is `tick` (nothing when it is there or past it already).
    pub fn advance_to(&mut self, tick: u64) {
        while self.sim.res.tick < tick {
            self.step();
        }
    }
}
