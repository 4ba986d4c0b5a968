//! The verifying replay one line at a time: a recording's world stepped and its checkpoints
//! compared as each checked line is handed over, so that a reader may hold a recording that is
//! still being written (a session server verifying a session as it streams) and look at the
//! world whenever it likes. [`super::replay_reader`] hands it every line of a file; both verify
//! the same way, by this one piece of code.
//!
//! A line is taken after the format's rules have passed it ([`super::LineRules`]): an event
//! waits for the step that leaves its tick, a checkpoint (or the footer's final hash) is compared
//! with the world once the world has reached its tick. After a divergence the world goes on, and
//! no further checkpoint is compared.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::hash::{hex, world_hash_keeping, WorldHash, HASHED};
use crate::input::InputEvent;
use crate::resource_hash::{differing_fields, ResourceBytes};
use crate::sim::Sim;

use super::names::{check_event, NameError};
use super::{CheckpointLine, Line};

/// One (entity, component) pair that differs at a divergent checkpoint.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Differing {
    /// The entity, as id bits in decimal, or "resources".
    pub entity: String,
    /// The component type, or for "resources" the field ([`crate::resource_hash::FIELDS`]).
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

/// The (entity, component) pairs that differ between a recorded checkpoint and the world: the
/// entities whose hash differs crossed with the component types whose hash differs, keeping
/// only pairs where the entity (still) has that component; and for the resources, the fields
/// that differ ([`crate::resource_hash::differing_fields`], from the resources at the last
/// checkpoint that agreed, `agreed`, and now, `now`).
fn differing(expected: &CheckpointLine, actual: &WorldHash, world: &hecs::World, agreed: &ResourceBytes, now: &ResourceBytes) -> Vec<Differing> {
    let comps: Vec<&str> = HASHED
        .iter()
        .map(|h| h.name)
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
            let fields = match expected.components.get(*c).and_then(|h| u64::from_str_radix(h, 16).ok()) {
                Some(h) => differing_fields(agreed, now, h),
                None => vec!["resources"],
            };
            out.extend(fields.into_iter().map(|f| Differing { entity: "resources".into(), component: f.into() }));
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

/// A recording's world, stepped and verified as its lines are handed over.
pub struct Verifier {
    sim: Sim,
    /// The events of the coming tick, applied with the next step.
    pending: Vec<InputEvent>,
    verifying: bool,
    checkpoints_checked: u64,
    first_divergence: Option<Divergence>,
    complete: bool,
    /// The hashed resources at the last checkpoint that agreed (at first, the start, which the
    /// header fixes) and at the one just hashed: what a divergence in the resources is told from.
    agreed: ResourceBytes,
    now: ResourceBytes,
}

impl Verifier {
    /// Starts from the world a header describes ([`super::sim_for_header_in`]). With `verifying`
    /// false (a what-if run under overrides) no checkpoint is compared.
    pub fn new(sim: Sim, verifying: bool) -> Verifier {
        let agreed = ResourceBytes::of(&sim.res);
        Verifier { sim, pending: Vec::new(), verifying, checkpoints_checked: 0, first_divergence: None, complete: false, agreed, now: ResourceBytes::default() }
    }

    /// Steps the world until its tick is `to` (nothing when it is there already), the events
    /// waiting applied with the first step; `each` sees the world after every step. An event the
    /// world refuses is dropped, as a live session drops it.
    pub fn advance(&mut self, to: u64, mut each: impl FnMut(&Sim)) {
        while self.sim.res.tick < to {
            let _ = self.sim.step_with(self.pending.drain(..));
            each(&self.sim);
        }
    }

    /// Takes the next line (checked by the format's rules) with its tick: the world is stepped
    /// to the tick (`each` sees every step), then an event waits for the next step and a
    /// checkpoint or the footer is compared. `full` gives a checkpoint with its per-component
    /// and per-entity maps when the line's own were left empty, read only at a divergence. An
    /// event naming what the world does not have (a model, task or technique) is refused.
    pub fn take(&mut self, line: Line, tick: u64, full: impl FnOnce() -> Option<CheckpointLine>, each: impl FnMut(&Sim)) -> Result<(), NameError> {
        self.advance(tick, each);
        match line {
            Line::Header(_) => {}
            Line::Event(e) => {
                // Its numbers were validated when the line was read (`codec::parse_body`).
                check_event(&e.event, &self.sim)?;
                self.pending.push(e.event);
            }
            Line::Checkpoint(c) => {
                if self.verifying && self.first_divergence.is_none() {
                    let h = world_hash_keeping(&self.sim.world, &self.sim.res, Some(&mut self.now));
                    self.checkpoints_checked += 1;
                    if hex(h.total) != c.hash {
                        let whole = full().unwrap_or_else(|| c.clone());
                        let differing = differing(&whole, &h, &self.sim.world, &self.agreed, &self.now);
                        self.first_divergence = Some(Divergence { tick, expected_hash: c.hash, actual_hash: hex(h.total), differing });
                    } else {
                        std::mem::swap(&mut self.agreed, &mut self.now);
                    }
                }
            }
            Line::Footer(f) => {
                if self.verifying && self.first_divergence.is_none() {
                    let h = self.sim.hash();
                    self.checkpoints_checked += 1;
                    if hex(h.total) != f.final_hash {
                        self.first_divergence = Some(Divergence { tick, expected_hash: f.final_hash, actual_hash: hex(h.total), differing: Vec::new() });
                    }
                }
                self.complete = true;
            }
        }
        Ok(())
    }

    /// The world now.
    pub fn sim(&self) -> &Sim {
        &self.sim
    }

    /// Checkpoints compared so far (the footer's final hash included).
    pub fn checkpoints_checked(&self) -> u64 {
        self.checkpoints_checked
    }

    /// The first checkpoint at which the world and the recording disagreed, if one did.
    pub fn first_divergence(&self) -> Option<&Divergence> {
        self.first_divergence.as_ref()
    }

    /// Whether the footer has been taken.
    pub fn complete(&self) -> bool {
        self.complete
    }

    /// Ends the replay: the events of the tick the recording ends at wait in the world's input
    /// queue, as a live session leaves them. Returns the world, the checkpoints compared and the
    /// first divergence.
    pub fn finish(mut self) -> (Sim, u64, Option<Divergence>) {
        for event in self.pending.drain(..) {
            let _ = self.sim.push_input(event);
        }
        (self.sim, self.checkpoints_checked, self.first_divergence)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::replay::{header_line, rechain, replay_reader, sim_for_header, LineRules, ReplayOptions};

    fn lines() -> Vec<String> {
        include_str!("../../../replays/scenarios/plant-two.jsonl").lines().map(str::to_string).collect()
    }

    /// The lines handed over one at a time, as a server receives them: what was found after
    /// each line (checkpoints compared, the divergence's tick), and the verifier at the end.
    fn one_by_one(lines: &[String]) -> (Vec<(u64, Option<u64>)>, Verifier) {
        let header = header_line(&lines[0]).unwrap();
        let mut rules = LineRules::after(&header);
        let mut v = Verifier::new(sim_for_header(&header, None, &[]).unwrap(), true);
        let mut seen = Vec::new();
        for l in &lines[1..] {
            let ruled = rules.check(l.clone()).unwrap();
            v.take(ruled.line, ruled.tick, || None, |_| {}).unwrap();
            seen.push((v.checkpoints_checked(), v.first_divergence().map(|d| d.tick)));
        }
        (seen, v)
    }

    #[test]
    fn lines_taken_one_at_a_time_verify_as_the_whole_file_does() {
        let lines = lines();
        let (seen, v) = one_by_one(&lines);
        assert!(v.complete());
        let text = lines.join("\n") + "\n";
        let whole = replay_reader(text.as_bytes(), "plant-two", None, &ReplayOptions::default()).unwrap();
        let (sim, checked, divergence) = v.finish();
        assert_eq!((checked, divergence.is_none()), (whole.checkpoints_checked, whole.first_divergence.is_none()));
        assert_eq!(checked, 3, "two checkpoints and the footer's final hash");
        assert_eq!(sim.hash().total, whole.sim.hash().total);
        assert_eq!(seen.last(), Some(&(3, None)));
    }

    #[test]
    fn a_changed_checkpoint_is_found_at_its_own_line_with_what_the_file_replay_finds() {
        let mut lines = lines();
        let at = lines.iter().position(|l| l.contains("\"tick\":120") && l.starts_with("{\"type\":\"checkpoint\"")).unwrap();
        let hash = &lines[at]["{\"type\":\"checkpoint\",\"tick\":120,\"hash\":\"".len()..][..16];
        lines[at] = lines[at].replacen(hash, "0123456789abcdef", 1);
        let lines = rechain(&lines).unwrap();
        let (seen, v) = one_by_one(&lines);
        // Nothing before the line, the divergence from it on (line `at` is the `at`-th taken).
        assert!(seen[..at - 1].iter().all(|(_, d)| d.is_none()), "{seen:?}");
        assert_eq!(seen[at - 1], (2, Some(120)));
        assert_eq!(seen.last(), Some(&(2, Some(120))), "no checkpoint compared after the divergence");
        let text = lines.join("\n") + "\n";
        let whole = replay_reader(text.as_bytes(), "plant-two", None, &ReplayOptions::default()).unwrap();
        let d = v.first_divergence().unwrap();
        assert_eq!(Some(d), whole.first_divergence.as_ref());
        assert_eq!(d.expected_hash, "0123456789abcdef");
    }
}
