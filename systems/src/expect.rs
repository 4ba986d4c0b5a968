//! Expectations about a simulation's state, checked by scripts and scenario files alike.
//!
//! An [`Expect`] is a plain value (written in RON in a scenario file, `docs/scenarios.md`);
//! [`Expect::check`] evaluates it against a [`Sim`] and the script's [`Names`], and a failure
//! is a [`Mismatch`]: what was expected and what was found, each in words.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::catalogue::Catalogue;
use crate::components::{Transform, Tree};
use crate::events::Happening;
use crate::hash::hex;
use crate::sim::Sim;
use crate::targets::{Names, TreeRef, ground_distance};

crate::message_error::message_error! {
    /// Why an expectation's names or numbers are refused ([`Expect::validate`]): one line.
    InvalidExpect
}

/// The anchor ball as a participant sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Ball {
    /// Not shown (no drag over ground).
    Hidden,
    /// Shown, green: releasing now would not snap.
    Green,
    /// Shown, white: releasing now snaps the tree onto the ground.
    White,
}

impl Ball {
    fn word(self) -> &'static str {
        match self {
            Ball::Hidden => "hidden",
            Ball::Green => "green",
            Ball::White => "white",
        }
    }
}

/// What is selected.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Selected {
    /// No tree.
    Nothing,
    /// This tree.
    Tree(TreeRef),
    /// Some tree of this model.
    Model(String),
}

/// One expectation about the state of the simulation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Expect {
    /// A tree of `model` stands with its base within `within` metres of `point`, measured along
    /// the ground (X and Z), as task targets are.
    TreeNear {
        /// The model's catalogue name.
        model: String,
        /// The point, metres.
        point: Vec3,
        /// The largest distance, metres.
        within: f32,
    },
    /// The world holds exactly this many trees.
    TreeCount(usize),
    /// The anchor ball is hidden, green or white.
    AnchorBall(Ball),
    /// What is selected.
    Selected(Selected),
    /// The running task is completed, at most `within_s` seconds after it started.
    TaskCompleted {
        /// The longest allowed task time, seconds.
        within_s: f32,
    },
    /// The running task's n-th target (counting from 1) is satisfied.
    TargetSatisfied(usize),
    /// No errors: with a task, its error count (removals, off-target plantings, drags released
    /// green) is zero; without one, no drag was released green and no planting was refused.
    NoErrors,
    /// The interaction log holds exactly `count` entries of `kind` (e.g. "planted").
    Logged {
        /// The kind, one of [`Happening::KINDS`].
        kind: String,
        /// The exact number.
        count: usize,
    },
    /// The interaction log holds at least `count` entries of `kind`.
    LoggedAtLeast {
        /// The kind, one of [`Happening::KINDS`].
        kind: String,
        /// The smallest number.
        count: usize,
    },
    /// The world hash equals this pinned value (16 hex digits; `""` until `grove test --update`
    /// pins it).
    Hash(String),
}

/// An expectation that does not hold: both sides in words.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{what}: expected {expected}, actual {actual}")]
pub struct Mismatch {
    /// What was checked, e.g. "the anchor ball".
    pub what: String,
    /// The expected value.
    pub expected: String,
    /// The value found.
    pub actual: String,
}

fn p3(p: Vec3) -> String {
    format!("({:.2}, {:.2}, {:.2})", p.x, p.y, p.z)
}

impl Expect {
    /// The expectation as a scenario file writes it, e.g. `TreeCount(2)`.
    pub fn text(&self) -> String {
        crate::targets::ron_line(self)
    }

    /// Checks the names and numbers an expectation carries against a catalogue: known models and
    /// log kinds, finite non-negative distances, a hash of 16 hex digits (or empty).
    pub fn validate(&self, catalogue: &Catalogue) -> Result<(), InvalidExpect> {
        self.validate_message(catalogue).map_err(InvalidExpect)
    }

    fn validate_message(&self, catalogue: &Catalogue) -> Result<(), String> {
        let model = |m: &str| if catalogue.by_name(m).is_some() { Ok(()) } else { Err(catalogue.unknown_name(m)) };
        match self {
            Expect::TreeNear { model: m, point, within } => {
                model(m)?;
                if !point.is_finite() || point.abs().max_element() > crate::limits::MAX_COORD {
                    return Err(format!(
                        "TreeNear point {point} is not a finite point within {} m",
                        crate::limits::MAX_COORD
                    ));
                }
                if !(within.is_finite() && *within >= 0.0) {
                    return Err(format!("TreeNear within {within} must be a finite, non-negative distance"));
                }
                Ok(())
            }
            Expect::Selected(Selected::Model(m)) => model(m),
            Expect::TaskCompleted { within_s } if !(within_s.is_finite() && *within_s >= 0.0) => {
                Err(format!("TaskCompleted within_s {within_s} must be a finite, non-negative number of seconds"))
            }
            Expect::Logged { kind, .. } | Expect::LoggedAtLeast { kind, .. }
                if !Happening::KINDS.contains(&kind.as_str()) =>
            {
                Err(format!("unknown log kind \"{kind}\"; known: {}", Happening::KINDS.join(", ")))
            }
            Expect::Hash(h) if !(h.is_empty() || (h.len() == 16 && h.bytes().all(|b| b.is_ascii_hexdigit()))) => Err(
                format!("Hash(\"{h}\") is not 16 hex digits (write Hash(\"\") and run grove test --update to pin it)"),
            ),
            _ => Ok(()),
        }
    }

    /// Evaluates the expectation now.
    pub fn check(&self, sim: &Sim, names: &Names) -> Result<(), Mismatch> {
        let fail = |what: &str, expected: String, actual: String| -> Result<(), Mismatch> {
            Err(Mismatch { what: what.to_string(), expected, actual })
        };
        match self {
            Expect::TreeNear { model, point, within } => {
                let id = sim.res.catalogue.by_name(model).map(|m| m.id);
                let nearest = sim
                    .world
                    .query::<(&Tree, &Transform)>()
                    .iter()
                    .filter(|(t, _)| Some(t.model) == id)
                    .map(|(_, tr)| (ground_distance(tr.translation, *point), tr.translation))
                    .min_by(|a, b| a.0.total_cmp(&b.0));
                let expected = format!("a {model} tree within {within} m of {}", p3(*point));
                match nearest {
                    Some((d, _)) if d <= *within => Ok(()),
                    Some((d, at)) => fail(
                        "tree near a point",
                        expected,
                        format!("the nearest {model} tree stands {d:.2} m away, at {}", p3(at)),
                    ),
                    None => fail("tree near a point", expected, format!("no {model} tree")),
                }
            }
            Expect::TreeCount(n) => {
                let count = sim.world.query::<&Tree>().iter().count();
                if count == *n { Ok(()) } else { fail("the number of trees", n.to_string(), count.to_string()) }
            }
            Expect::AnchorBall(want) => {
                let b = sim.anchor_ball();
                let got = match (b.visible, b.armed) {
                    (false, _) => Ball::Hidden,
                    (true, false) => Ball::Green,
                    (true, true) => Ball::White,
                };
                if got == *want {
                    Ok(())
                } else {
                    let actual = if b.visible {
                        format!("{} ({:.3} m above the ground)", got.word(), b.distance)
                    } else {
                        got.word().to_string()
                    };
                    fail("the anchor ball", want.word().to_string(), actual)
                }
            }
            Expect::Selected(want) => {
                let sel = sim.selection().tree;
                let model_of = |id: u64| {
                    sim.tree(id)
                        .and_then(|t| sim.res.catalogue.get(t.tree.model))
                        .map_or_else(|| "?".to_string(), |m| m.name.clone())
                };
                let actual = sel.map_or_else(|| "nothing".to_string(), |id| format!("a {} tree", model_of(id)));
                let (ok, expected) = match want {
                    Selected::Nothing => (sel.is_none(), "nothing".to_string()),
                    Selected::Model(m) => (sel.is_some_and(|id| &model_of(id) == m), format!("a {m} tree")),
                    Selected::Tree(r) => match names.tree(sim, r) {
                        Ok(id) => (sel == Some(id), format!("the tree {} (a {})", r.text(), model_of(id))),
                        Err(e) => return fail("the selection", format!("the tree {}", r.text()), e.to_string()),
                    },
                };
                if ok { Ok(()) } else { fail("the selection", expected, actual) }
            }
            Expect::TaskCompleted { within_s } => {
                let expected = format!("the task completed within {within_s} s");
                let Some(task) = &sim.res.task else { return fail("the task", expected, "no task was started".into()) };
                let done = task.satisfied.iter().filter(|s| s.is_some()).count();
                match task.completed_tick {
                    None => fail(
                        "the task",
                        expected,
                        format!(
                            "{} not completed ({done} of {} targets satisfied)",
                            task.def.id,
                            task.def.targets.len()
                        ),
                    ),
                    Some(t) => {
                        let secs = crate::task::ticks_to_seconds(t - task.started_tick, sim.res.dt);
                        if secs <= *within_s as f64 {
                            Ok(())
                        } else {
                            fail("the task", expected, format!("completed in {secs:.2} s"))
                        }
                    }
                }
            }
            Expect::TargetSatisfied(n) => {
                let expected = format!("target {n} satisfied");
                let Some(task) = &sim.res.task else { return fail("the task", expected, "no task was started".into()) };
                match n.checked_sub(1).and_then(|i| task.satisfied.get(i)) {
                    Some(Some(_)) => Ok(()),
                    Some(None) => fail("the task", expected, format!("target {n} of {} not satisfied", task.def.id)),
                    None => fail(
                        "the task",
                        expected,
                        format!("{} has {} targets (counting from 1)", task.def.id, task.satisfied.len()),
                    ),
                }
            }
            Expect::NoErrors => match &sim.res.task {
                Some(task) if task.errors.total() > 0 => {
                    let e = task.errors;
                    fail(
                        "errors",
                        "none".into(),
                        format!(
                            "{} ({} removals, {} off target, {} released green)",
                            e.total(),
                            e.removals,
                            e.off_target,
                            e.released_green
                        ),
                    )
                }
                Some(_) => Ok(()),
                None => {
                    let (green, refused) = (sim.res.log.count("released_green"), sim.res.log.count("planting_refused"));
                    if green + refused == 0 {
                        Ok(())
                    } else {
                        fail(
                            "errors",
                            "none".into(),
                            format!("{green} drags released green, {refused} plantings refused"),
                        )
                    }
                }
            },
            Expect::Logged { kind, count } => {
                let got = sim.res.log.count(kind);
                if got == *count {
                    Ok(())
                } else {
                    fail(&format!("\"{kind}\" log entries"), count.to_string(), got.to_string())
                }
            }
            Expect::LoggedAtLeast { kind, count } => {
                let got = sim.res.log.count(kind);
                if got >= *count {
                    Ok(())
                } else {
                    fail(&format!("\"{kind}\" log entries"), format!("at least {count}"), got.to_string())
                }
            }
            Expect::Hash(want) => {
                let got = hex(sim.hash().total);
                if want.is_empty() {
                    fail("the world hash", "a pinned value (none yet: run grove test --update)".into(), got)
                } else if got == *want {
                    Ok(())
                } else {
                    fail("the world hash", want.clone(), got)
                }
            }
        }
    }
}
