//! Running a scenario: each step becomes the [`Script`] call of the same name, each expectation
//! [`Script::check`]; the first that fails ends the run with a [`Failure`] naming the step, the
//! expectation, and the expected and actual values.

use crate::components::Pose;
use crate::expect::Expect;
use crate::input::{InputEvent, StampedEvent};
use crate::replay::{Header, RecordError, record_events};
use crate::resources::Override;
use crate::script::Script;
use crate::sim::Sim;

use super::aims::{self, Aimed, RunState, hold_checked};
use super::failed::StepFailed;
use super::observe::{self, Snapshot};
use super::{Loaded, RunError, Step, intents, technique};

/// How to run a scenario.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Parameter overrides applied after the file's `config` (`grove test --set`).
    pub overrides: Vec<Override>,
    /// Keep going past a world-hash mismatch and collect the actual hashes, to pin them
    /// (`grove test --update`).
    pub update: bool,
}

/// Why a scenario failed: where, and what.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// The step (counting from 1), or `None` for an end expectation.
    pub step: Option<usize>,
    /// The step or end expectation as the file writes it.
    pub at: String,
    /// What went wrong: a mismatch (expected and actual) or a target that cannot be found.
    pub message: String,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.step {
            Some(n) => write!(f, "step {n} {}: {}", self.at, self.message),
            None => write!(f, "end expectation {}: {}", self.at, self.message),
        }
    }
}

/// What a run did.
pub struct Outcome {
    /// The first failure, if any.
    pub failure: Option<Failure>,
    /// Ticks simulated.
    pub ticks: u64,
    /// The world hash each `Hash` expectation met, in order (steps, then the end), as far as
    /// the run got; all of them when `failure` is `None`.
    pub hashes: Vec<String>,
    /// The header a recording of the run gets.
    pub header: Header,
    /// The input events of the run.
    pub events: Vec<StampedEvent>,
    /// The simulation at the end.
    pub sim: Sim,
}

impl Outcome {
    /// The run as a recording (header, events, checkpoints, footer), re-simulated from its
    /// events, so that `grove replay` and `grove view` show what happened.
    pub fn recording(&self) -> Result<Vec<u8>, RecordError> {
        record_events(
            Vec::new(),
            &self.header,
            &self.events,
            self.ticks,
            serde_json::json!({ "scenario": self.header.participant }),
        )
    }
}

/// The simulation a loaded scenario starts from, and the header that names it.
pub fn start(loaded: &Loaded, options: &RunOptions) -> Result<(Sim, Header), RunError> {
    let mut sim = Sim::from_scene(&loaded.scene, loaded.seed)?;
    let mut header = Header::new(&loaded.scene_ref, loaded.seed, loaded.scene.dt);
    header.participant = Some(format!("scenario:{}", loaded.name));
    header.synthetic = true;
    header.config = loaded.config.clone();
    for o in &options.overrides {
        header.config.set(o.clone());
    }
    if !loaded.scene.banks.is_empty() {
        header.models = crate::bank::Banks::open(&loaded.scene.bank_dirs())?.session_catalogue()?.1;
    }
    sim.res.config = header.config.config()?;
    Ok((sim, header))
}

/// Runs a loaded scenario headless.
pub fn run(loaded: &Loaded, options: &RunOptions) -> Result<Outcome, RunError> {
    run_inner(loaded, options, None).map(|(o, _)| o)
}

/// One step of a traced run: what it was, its ticks, the state before and after it, and what
/// it did.
#[derive(Clone, Debug, PartialEq)]
pub struct StepTrace {
    /// The step, counting from 1.
    pub number: usize,
    /// The step as the file writes it.
    pub text: String,
    /// The state before it.
    pub before: Snapshot,
    /// The state after it (as far as it got, when it failed).
    pub after: Snapshot,
    /// What it did, in words; empty when nothing happened.
    pub did: Vec<String>,
}

/// Runs a loaded scenario, recording each step ([`StepTrace`]) and calling `frame` with the
/// world at the start and after each step that ran a tick, for pictures. The run is the very
/// run [`run`] makes.
pub fn run_traced(
    loaded: &Loaded,
    options: &RunOptions,
    frame: &mut dyn FnMut(&Sim),
) -> Result<(Outcome, Vec<StepTrace>), RunError> {
    run_inner(loaded, options, Some(frame))
}

fn run_inner(
    loaded: &Loaded,
    options: &RunOptions,
    mut frame: Option<&mut dyn FnMut(&Sim)>,
) -> Result<(Outcome, Vec<StepTrace>), RunError> {
    let (sim, header) = start(loaded, options)?;
    let mut script = Script::new(sim);
    let mut hashes = Vec::new();
    let mut failure = None;
    let mut traces = Vec::new();
    let mut state = RunState { press_on_nothing: loaded.scenario.press_on_nothing, ..Default::default() };
    if let Some(f) = frame.as_mut() {
        f(script.sim());
    }
    for (i, step) in loaded.scenario.steps.iter().enumerate() {
        let before =
            frame.is_some().then(|| (Snapshot::take(script.sim(), script.names()), script.sim().res.log.entries.len()));
        let result = apply(&mut script, &mut state, step, options.update, &mut hashes);
        if let (Some(f), Some((before, from))) = (frame.as_mut(), before) {
            let after = Snapshot::take(script.sim(), script.names());
            if after.tick != before.tick {
                f(script.sim());
            }
            traces.push(StepTrace {
                number: i + 1,
                text: step.text(),
                did: observe::did(script.sim(), script.names(), from),
                before,
                after,
            });
        }
        if let Err(failed) = result {
            failure = Some(Failure { step: Some(i + 1), at: step.text(), message: failed.to_string() });
            break;
        }
    }
    if failure.is_none() {
        for e in &loaded.scenario.expect {
            if let Err(failed) = expect(&script, e, options.update, &mut hashes) {
                failure = Some(Failure { step: None, at: e.text(), message: failed.to_string() });
                break;
            }
        }
    }
    let (sim, events) = script.into_parts();
    Ok((Outcome { failure, ticks: sim.res.tick, hashes, header, events, sim }, traces))
}

/// Checks one expectation; with `update`, a world hash is collected rather than compared.
fn expect(script: &Script, e: &Expect, update: bool, hashes: &mut Vec<String>) -> Result<(), StepFailed> {
    if let Expect::Hash(_) = e {
        hashes.push(crate::hash::hex(script.sim().hash().total));
        if update {
            return Ok(());
        }
    }
    Ok(script.check(e)?)
}

/// Plays one step through the script.
pub fn apply(
    s: &mut Script,
    state: &mut RunState,
    step: &Step,
    update: bool,
    hashes: &mut Vec<String>,
) -> Result<(), StepFailed> {
    match step {
        Step::Plant { model, at } => intents::plant(s, state, model, at)?,
        Step::Remove(tree) => intents::remove(s, state, tree)?,
        Step::Drag { tree, to } => intents::drag(s, state, tree, to)?,
        Step::ChooseModel(m) => {
            s.choose_model(m.as_str());
        }
        Step::PointAt(aim) => {
            let p = s.aim_point(aim)?;
            s.point_at(p);
            state.aimed = Some(Aimed::new(s.sim(), s.names(), aim, p));
        }
        Step::Sweep { from, by, count } => {
            let p = s.aim_point(from)?;
            for k in 0..*count {
                s.point_at(p + *by * k as f32);
            }
            if *count > 0 {
                let last = p + *by * (*count - 1) as f32;
                let aim = crate::targets::Aim::Point(last.x, last.y, last.z);
                state.aimed = Some(Aimed {
                    label: format!("the sweep's last point {}", aim.text().trim_start_matches("Point")),
                    ..Aimed::new(s.sim(), s.names(), &aim, last)
                });
            }
        }
        Step::Controller { position, rotation } => {
            s.try_push(InputEvent::ControllerPose { pose: Pose { position: *position, rotation: *rotation } })?.wait(1);
            state.aimed = None;
        }
        Step::Head { position, rotation } => {
            s.try_push(InputEvent::HeadPose { pose: Pose { position: *position, rotation: *rotation } })?.wait(1);
        }
        Step::Press(b) => {
            let checked = hold_checked(s, state, *b);
            s.release((*b).into());
            checked?;
        }
        Step::PressOnNothing(b) => {
            s.hold((*b).into());
            let checked = aims::check_nothing(s.sim(), s.names());
            s.release((*b).into());
            checked?;
        }
        Step::Hold(b) => {
            hold_checked(s, state, *b)?;
        }
        Step::Release(b) => {
            s.release((*b).into());
        }
        Step::Touchpad { x, y, ticks } => {
            s.touchpad(*x, *y, *ticks);
        }
        Step::ScalePad { value, ticks } => {
            s.scale_pad(*value, *ticks);
        }
        Step::OpenMenu => {
            s.push(InputEvent::OpenMenu).wait(1);
        }
        Step::CloseMenu => {
            s.push(InputEvent::CloseMenu).wait(1);
        }
        Step::Wait(n) => {
            s.wait(*n);
        }
        Step::WaitUntil { until, timeout } => {
            s.wait_until(until, *timeout)?;
        }
        Step::StartTask(id) => {
            s.start_task(id);
        }
        Step::EndTask => {
            s.end_task();
        }
        Step::SwitchTechnique(name) => {
            // A built-in technique as the mode switch it always was (the same events as the
            // committed recordings); a plug-in by name.
            match technique(name)? {
                Some(mode) => s.switch_mode(mode),
                None => s.switch_technique(name),
            };
        }
        Step::Name { name, tree } => {
            s.name_tree(name, tree)?;
        }
        Step::Mark { name, at } => {
            s.mark(name, at)?;
        }
        Step::Expect(e) => expect(s, e, update, hashes)?,
    }
    Ok(())
}
