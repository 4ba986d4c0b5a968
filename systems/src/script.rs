//! [`Script`]: drive a simulation like a participant would, and record what was done.
//!
//! A script owns a [`Sim`] and changes it only through [`Sim::push_input`] and [`Sim::step`],
//! exactly like a live session or a replay. Every event it pushes is recorded as a
//! [`StampedEvent`] with the tick it applies at, so a scripted scenario can be saved as a replay
//! and played back to the same world hash.
//!
//! Each action queues its events and then runs the ticks it says (at least one), so after any
//! call the simulation has seen its effect:
//!
//! | call | events and ticks |
//! |---|---|
//! | [`Script::point_at`] | controller pose aimed at a point; 1 tick |
//! | [`Script::move_controller`] | controller pose; 1 tick |
//! | [`Script::move_head`] | head pose; 1 tick |
//! | [`Script::press`] | button down; 1 tick; button up; 1 tick |
//! | [`Script::hold`] / [`Script::release`] | button down / up; 1 tick |
//! | [`Script::touchpad`] | axes; `ticks` ticks; axes (0, 0); 1 tick |
//! | [`Script::choose_model`] | (manual mode: open menu; 1 tick;) choose model; 1 tick |
//! | [`Script::switch_mode`], [`Script::switch_technique`], [`Script::start_task`], [`Script::end_task`] | the event; 1 tick |
//! | [`Script::wait`] | `ticks` ticks |
//! | [`Script::wait_until`] | one tick at a time until an expectation holds, at most `timeout` |
//! | [`Script::aim`] | controller pose aimed at a named point (a tree, a task target, a mark); 1 tick |
//! | [`Script::name_tree`], [`Script::mark`], [`Script::check`], [`Script::expect`] | no ticks |
//!
//! Targets are named, never entity ids ([`crate::targets`]): `TreeRef::Last` is the tree planted
//! most recently, `TreeRef::Named("oak")` one named with [`Script::name_tree`]. Expectations
//! ([`crate::expect::Expect`]) are the ones scenario files use, so a Rust script and a scenario
//! file (`docs/scenarios.md`, read into these calls by [`crate::scenario`]) check the same way.
//!
//! The methods return `&mut Self`, so steps chain:
//! `script.point_at(p).press(Button::Trigger).wait(10);`
//!
//! # Panics
//! An event with invalid numbers (NaN, an unnormalised rotation, axes outside [−1, 1]) is a bug
//! in the script, not user input, so the action methods panic with the reason. Use
//! [`Script::try_push`] to handle it instead.

use glam::{Vec2, Vec3};

use crate::catalogue::ModelRef;
use crate::components::{Controller, Head, Pose};
use crate::expect::{Expect, Mismatch};
use crate::input::{Button, InputEvent, StampedEvent};
use crate::mode::Mode;
use crate::sim::Sim;
use crate::targets::{Aim, Names, TargetError, TreeRef};

/// A simulation driven by scripted input, with a recording of that input.
pub struct Script {
    sim: Sim,
    recorded: Vec<StampedEvent>,
    /// Events queued for the next tick, applied by [`Sim::step_with`].
    pending: Vec<InputEvent>,
    /// The trees and points the script has named, and where its planting began.
    names: Names,
}

impl Script {
    /// A script driving `sim` from its current tick.
    pub fn new(sim: Sim) -> Script {
        let names = Names::new(&sim);
        Script { sim, recorded: Vec::new(), pending: Vec::new(), names }
    }

    /// Queues one event for the next tick and records it, or says why it is invalid.
    pub fn try_push(&mut self, event: InputEvent) -> Result<&mut Self, crate::input::InvalidEvent> {
        let tick = self.sim.res.tick;
        event.validate()?;
        self.pending.push(event.clone());
        self.recorded.push(StampedEvent { tick, event });
        Ok(self)
    }

    /// Queues one event for the next tick and records it, without stepping.
    ///
    /// # Panics
    /// If the event carries invalid numbers.
    pub fn push(&mut self, event: InputEvent) -> &mut Self {
        let kind = event.kind();
        if let Err(e) = self.try_push(event) {
            panic!("Script: invalid {kind} event: {e}");
        }
        self
    }

    /// Hands the pending events to the simulation's input queue without stepping, for callers
    /// that take the simulation over before the next tick.
    fn flush(&mut self) {
        for event in std::mem::take(&mut self.pending) {
            // Validated when pushed, so this cannot fail.
            let _ = self.sim.push_input(event);
        }
    }

    /// Runs `ticks` steps, the first with the events pushed since the last step.
    pub fn wait(&mut self, ticks: u64) -> &mut Self {
        for _ in 0..ticks {
            let events = std::mem::take(&mut self.pending);
            // Every pending event was validated when it was pushed.
            if let Err(e) = self.sim.step_with(events) {
                panic!("Script: invalid event: {e}");
            }
        }
        self
    }

    /// Aims the controller ray from where the controller is at `point` (one controller pose
    /// event, no roll), then runs one tick.
    pub fn point_at(&mut self, point: Vec3) -> &mut Self {
        let from = self.controller().pose.position;
        self.move_controller(Pose::looking_at(from, point))
    }

    /// Puts the controller at `pose` (its ray starts at the position, along the forward
    /// direction), then runs one tick.
    pub fn move_controller(&mut self, pose: Pose) -> &mut Self {
        self.push(InputEvent::ControllerPose { pose }).wait(1)
    }

    /// Moves the head (camera) to `pose`, then runs one tick.
    pub fn move_head(&mut self, pose: Pose) -> &mut Self {
        self.push(InputEvent::HeadPose { pose }).wait(1)
    }

    /// Presses and releases a button: down, one tick, up, one tick. With the ray still, this is
    /// a click.
    pub fn press(&mut self, button: Button) -> &mut Self {
        self.hold(button).release(button)
    }

    /// Puts a button down, then runs one tick.
    pub fn hold(&mut self, button: Button) -> &mut Self {
        self.push(InputEvent::ButtonDown { button }).wait(1)
    }

    /// Lets a button up, then runs one tick.
    pub fn release(&mut self, button: Button) -> &mut Self {
        self.push(InputEvent::ButtonUp { button }).wait(1)
    }

    /// Holds the thumb at `(x, y)` on the touchpad for `ticks` ticks, then lifts it (axes back
    /// to (0, 0)) and runs one more tick, in which the gesture ends. The tree moves or turns in
    /// exactly `ticks` ticks.
    pub fn touchpad(&mut self, x: f32, y: f32, ticks: u64) -> &mut Self {
        self.push(InputEvent::TouchpadAxes { axes: Vec2::new(x, y) }).wait(ticks);
        self.push(InputEvent::TouchpadAxes { axes: Vec2::ZERO }).wait(1)
    }

    /// Holds the Scale pad at `value` for `ticks` ticks, then lets it go (back to 0) and runs one
    /// more tick, in which the gesture ends. The tree grows or shrinks in exactly `ticks` ticks.
    pub fn scale_pad(&mut self, value: f32, ticks: u64) -> &mut Self {
        self.push(InputEvent::ScaleAxis { value }).wait(ticks);
        self.push(InputEvent::ScaleAxis { value: 0.0 }).wait(1)
    }

    /// Chooses a model. In manual mode the menu is opened first (one tick), as a participant
    /// has to for every new tree; the tree then appears in front of the head in the tick of the
    /// choice. In ray-casting mode it only sets the model that Trigger plants.
    /// Pass a name (`"birch-mesh"`, or a model added to a bank) for a stable reference; a
    /// shipped model's [`crate::catalogue::ModelId`] is written as its index, as the study's
    /// recordings have it.
    pub fn choose_model(&mut self, model: impl Into<ModelRef>) -> &mut Self {
        let model = model.into();
        if self.sim.res.mode == Mode::Manual && !self.sim.res.menu.open {
            self.push(InputEvent::OpenMenu).wait(1);
        }
        self.push(InputEvent::ChooseModel { model }).wait(1)
    }

    /// Switches the interaction mode, then runs one tick.
    pub fn switch_mode(&mut self, mode: Mode) -> &mut Self {
        self.push(InputEvent::SwitchMode { mode }).wait(1)
    }

    /// Switches to a registered technique by name, then runs one tick.
    pub fn switch_technique(&mut self, name: &str) -> &mut Self {
        self.push(InputEvent::SwitchTechnique { technique: name.to_string() }).wait(1)
    }

    /// Starts a study task by id (e.g. "ray-casting-7"), then runs one tick.
    pub fn start_task(&mut self, id: &str) -> &mut Self {
        self.push(InputEvent::StartTask { task: id.to_string(), layout: None }).wait(1)
    }

    /// Declares the running task finished, then runs one tick.
    pub fn end_task(&mut self) -> &mut Self {
        self.push(InputEvent::EndTask).wait(1)
    }

    /// The tree a reference names, by entity id bits (it must still stand).
    pub fn tree_id(&self, tree: &TreeRef) -> Result<u64, TargetError> {
        self.names.tree(&self.sim, tree)
    }

    /// The world point an aim names, now.
    pub fn aim_point(&self, aim: &Aim) -> Result<Vec3, TargetError> {
        self.names.point(&self.sim, aim)
    }

    /// Aims the controller ray at a named point ([`Script::point_at`] on it), then runs one
    /// tick; nothing happens if the point cannot be found.
    pub fn aim(&mut self, aim: &Aim) -> Result<&mut Self, TargetError> {
        let p = self.aim_point(aim)?;
        Ok(self.point_at(p))
    }

    /// Aims at the middle of a tree's pick shape ([`crate::targets::tree_middle`]), then runs
    /// one tick.
    pub fn point_at_tree(&mut self, tree: TreeRef) -> Result<&mut Self, TargetError> {
        self.aim(&Aim::Tree { tree, offset: None })
    }

    /// Gives a tree a name that later targets can use (`TreeRef::Named`); runs no tick.
    pub fn name_tree(&mut self, name: &str, tree: &TreeRef) -> Result<&mut Self, TargetError> {
        let id = self.tree_id(tree)?;
        self.names.name_tree(name, id);
        Ok(self)
    }

    /// Remembers where an aim points now under a name (`Aim::Mark`); runs no tick.
    pub fn mark(&mut self, name: &str, at: &Aim) -> Result<&mut Self, TargetError> {
        let p = self.aim_point(at)?;
        self.names.mark(name, p);
        Ok(self)
    }

    /// The trees and points the script has named, and where its planting began.
    pub fn names(&self) -> &Names {
        &self.names
    }

    /// The trees planted since the script started, by entity id bits, in order.
    pub fn planted(&self) -> Vec<u64> {
        self.names.planted(&self.sim)
    }

    /// Checks an expectation now, without stepping.
    pub fn check(&self, expect: &Expect) -> Result<(), Mismatch> {
        expect.check(&self.sim, &self.names)
    }

    /// Checks an expectation now.
    ///
    /// # Panics
    /// With the mismatch (expected and actual) when it does not hold: for Rust tests, where a
    /// failed expectation is the test's failure.
    pub fn expect(&mut self, expect: &Expect) -> &mut Self {
        if let Err(m) = self.check(expect) {
            panic!("Script: at tick {}, {} does not hold: {m}", self.sim.res.tick, expect.text());
        }
        self
    }

    /// Runs one tick at a time until `expect` holds, at most `timeout` ticks, and returns the
    /// ticks run (0 if it already held). On timeout the mismatch names the condition and what
    /// was found at the last tick.
    pub fn wait_until(&mut self, expect: &Expect, timeout: u64) -> Result<u64, Mismatch> {
        let mut waited = 0;
        loop {
            match self.check(expect) {
                Ok(()) => return Ok(waited),
                Err(m) if waited >= timeout => {
                    return Err(Mismatch {
                        what: format!("timed out after {timeout} ticks waiting until {}: {}", expect.text(), m.what),
                        ..m
                    });
                }
                Err(_) => {
                    self.wait(1);
                    waited += 1;
                }
            }
        }
    }

    /// Every event pushed so far, stamped with the tick it applied at, in order.
    pub fn recorded(&self) -> &[StampedEvent] {
        &self.recorded
    }

    /// The simulation.
    pub fn sim(&self) -> &Sim {
        &self.sim
    }

    /// The simulation, mutably (for set-up; changes made here are not recorded).
    pub fn sim_mut(&mut self) -> &mut Sim {
        self.flush();
        &mut self.sim
    }

    /// The simulation, ending the script.
    pub fn into_sim(mut self) -> Sim {
        self.flush();
        self.sim
    }

    /// The simulation and the recording, ending the script.
    pub fn into_parts(mut self) -> (Sim, Vec<StampedEvent>) {
        self.flush();
        (self.sim, self.recorded)
    }

    /// A copy of the controller (default if the world has none).
    pub fn controller(&self) -> Controller {
        self.sim.controller().unwrap_or_default()
    }

    /// A copy of the head (default if the world has none).
    pub fn head(&self) -> Head {
        self.sim.head()
    }
}
