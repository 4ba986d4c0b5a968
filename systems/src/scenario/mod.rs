//! Scenario files: interaction tests written without Rust (`docs/scenarios.md`).
//!
//! A scenario file is RON: a scene and seed, a list of [`Step`]s and a list of end
//! expectations ([`Expect`]). [`Loaded::load`] reads and checks one (every name, number and the
//! ticks it may ask for, before anything runs); [`run::run`] plays it through
//! [`crate::script::Script`] calls, the same calls a Rust test makes, so the two never drift
//! apart; [`update`] pins world hashes in the file's text; [`draft`] writes a scenario from a
//! recording.

pub mod aims;
pub mod draft;
mod errors;
mod failed;
pub mod intents;
pub mod observe;
pub mod run;
pub mod update;

pub use errors::{CheckError, DraftError, HashCountError, RunError, StepError};
pub use failed::{StepFailed, UnknownTechnique};

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{Quat, Vec3};
use serde::{Deserialize, Serialize};

use crate::catalogue::Catalogue;
use crate::expect::Expect;
use crate::files::{self, Kind};
use crate::input::Button;
use crate::limits::{MAX_SCENARIO_STEPS, MAX_SCENARIO_TICKS};
use crate::mode::Mode;
use crate::resources::{Override, Overrides};
use crate::scene::Scene;
use crate::targets::{Aim, TreeRef};

/// A controller button, as scenario files name it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Btn {
    /// Plants, selects, drags.
    Trigger,
    /// Removes.
    Bumper,
    /// The touchpad press.
    Touchpad,
    /// The menu button.
    Menu,
}

impl From<Btn> for Button {
    fn from(b: Btn) -> Button {
        match b {
            Btn::Trigger => Button::Trigger,
            Btn::Bumper => Button::Bumper,
            Btn::Touchpad => Button::Touchpad,
            Btn::Menu => Button::Menu,
        }
    }
}

impl From<Button> for Btn {
    fn from(b: Button) -> Btn {
        match b {
            Button::Trigger => Btn::Trigger,
            Button::Bumper => Btn::Bumper,
            Button::Touchpad => Btn::Touchpad,
            Button::Menu => Btn::Menu,
        }
    }
}

/// One step of a scenario. The intent steps (`Plant`, `Remove`, `Drag`, [`intents`]) play the
/// lower-level steps a participant would take and check that what they meant came of it; each
/// other step maps to one [`crate::script::Script`] call. The ticks each takes are listed in
/// `docs/scenarios.md`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Step {
    /// Choose a model, aim, press Trigger; fails unless a tree of that model was planted within
    /// the task's tolerance of the aim.
    Plant {
        /// The model's catalogue name.
        model: String,
        /// Where.
        at: Aim,
    },
    /// Aim at the middle of a tree, press Bumper; fails unless the tree is gone.
    Remove(TreeRef),
    /// Grab a tree at its middle, carry it so that its base comes to `to`, release; fails unless
    /// it snapped to the ground.
    Drag {
        /// The tree.
        tree: TreeRef,
        /// Where its base goes.
        to: Aim,
    },
    /// Choose a model by catalogue name (in manual mode the menu opens first).
    ChooseModel(String),
    /// Aim the controller ray at a point, a tree, a task target or a mark.
    PointAt(Aim),
    /// Aim at `from`, then `from + by`, `from + 2·by`, …: `count` aims, one tick each.
    Sweep {
        /// The first point (evaluated once, at the start of the sweep).
        from: Aim,
        /// The step between aims, metres.
        by: Vec3,
        /// The number of aims.
        count: u64,
    },
    /// Put the controller at a pose (position and unit rotation quaternion x, y, z, w).
    Controller {
        /// Position, metres.
        position: Vec3,
        /// Rotation (x, y, z, w).
        rotation: Quat,
    },
    /// Put the head (camera) at a pose.
    Head {
        /// Position, metres.
        position: Vec3,
        /// Rotation (x, y, z, w).
        rotation: Quat,
    },
    /// Press and release a button. After an aim, a Trigger or Bumper press fails unless the ray
    /// meets what the aim names ([`aims`]).
    Press(Btn),
    /// Press and release a button where the ray meets nothing (fails if it meets something).
    PressOnNothing(Btn),
    /// Put a button down.
    Hold(Btn),
    /// Let a button up.
    Release(Btn),
    /// Hold the thumb at (x, y) on the touchpad for `ticks` ticks, then lift it.
    Touchpad {
        /// Right is +1.
        x: f32,
        /// Front is +1.
        y: f32,
        /// How long, ticks.
        ticks: u64,
    },
    /// Hold the Scale pad at `value` for `ticks` ticks, then let it go.
    ScalePad {
        /// Grow is +1, shrink −1.
        value: f32,
        /// How long, ticks.
        ticks: u64,
    },
    /// Open the model menu.
    OpenMenu,
    /// Close the model menu without choosing.
    CloseMenu,
    /// Let ticks pass.
    Wait(u64),
    /// Let ticks pass one at a time until an expectation holds; fail after `timeout` ticks.
    WaitUntil {
        /// The condition.
        until: Expect,
        /// The most ticks to wait.
        timeout: u64,
    },
    /// Start a study task by id, e.g. "ray-casting-7".
    StartTask(String),
    /// Declare the running task finished.
    EndTask,
    /// Switch the interaction technique by name: "ray-casting", "manual" or a registered
    /// plug-in technique.
    SwitchTechnique(String),
    /// Give a tree a name for later steps (`Named("…")`).
    Name {
        /// The name.
        name: String,
        /// The tree.
        tree: TreeRef,
    },
    /// Remember where an aim points now, for later steps (`Mark(name: "…")`).
    Mark {
        /// The name.
        name: String,
        /// The point.
        at: Aim,
    },
    /// Check an expectation at this point.
    Expect(Expect),
}

impl Step {
    /// The step as a scenario file writes it, e.g. `Press(Trigger)`.
    pub fn text(&self) -> String {
        crate::targets::ron_line(self)
    }

    /// The most ticks the step can take.
    pub fn max_ticks(&self) -> u64 {
        match self {
            Step::ChooseModel(_) | Step::Press(_) | Step::PressOnNothing(_) => 2,
            Step::Plant { .. } => 5,
            Step::Remove(_) => 3,
            Step::Drag { .. } => 4 + intents::MAX_CARRY_TICKS,
            Step::Sweep { count, .. } => *count,
            Step::Touchpad { ticks, .. } | Step::ScalePad { ticks, .. } => ticks.saturating_add(1),
            Step::Wait(n) => *n,
            Step::WaitUntil { timeout, .. } => *timeout,
            Step::Name { .. } | Step::Mark { .. } | Step::Expect(_) => 0,
            _ => 1,
        }
    }
}

/// A technique by the name files use: `Some(mode)` for a built-in one ("ray-casting",
/// "manual"), `None` for a registered plug-in technique ([`crate::technique::installed`]).
pub fn technique(name: &str) -> Result<Option<Mode>, UnknownTechnique> {
    if let Some(mode) = [Mode::RayCasting, Mode::Manual].into_iter().find(|m| m.name() == name) {
        return Ok(Some(mode));
    }
    let registered = crate::technique::installed();
    match registered.get(name) {
        Some(_) => Ok(None),
        None => Err(UnknownTechnique { name: name.to_string(), known: registered.names() }),
    }
}

/// A scenario file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Its name in reports (default: the file name without `.ron`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// A built-in scene name ("study") or a scene file, relative to the scenario file.
    pub scene: String,
    /// The RNG seed (default: the scene's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Button steps may press where the ray meets nothing (without it, a Trigger or Bumper press
    /// after an aim fails there).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub press_on_nothing: bool,
    /// Parameter overrides, as `grove study --set` takes them.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub config: BTreeMap<String, f32>,
    /// The steps, in order.
    pub steps: Vec<Step>,
    /// Expectations checked after the last step.
    #[serde(default)]
    pub expect: Vec<Expect>,
}

/// Why a scenario file was refused. `Display` is one line naming the file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScenarioError {
    /// The file could not be read.
    #[error(transparent)]
    File(#[from] files::FileError),
    /// Not valid RON for a scenario.
    #[error("{file}: line {line}, column {column}: {message}")]
    Syntax {
        /// The file.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// Valid RON, but a name, a number or a limit is wrong.
    #[error("{file}: {message}")]
    Invalid {
        /// The file.
        file: String,
        /// What is wrong, naming the step or expectation.
        message: String,
    },
}

/// Parses scenario text (RON, with `Some(…)` optional around optional values); `file` names
/// it in errors.
pub fn parse(text: &str, file: &str) -> Result<Scenario, ScenarioError> {
    let options = ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    options.from_str(text).map_err(|e| ScenarioError::Syntax {
        file: file.to_string(),
        line: e.span.start.line,
        column: e.span.start.col,
        message: e.code.to_string().replace('\n', " "),
    })
}

/// A scenario read, checked and ready to run: its scene, configuration and the text it came
/// from (for `--update`).
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The file.
    pub path: PathBuf,
    /// Its name in reports.
    pub name: String,
    /// The file's text.
    pub text: String,
    /// The parsed scenario.
    pub scenario: Scenario,
    /// The scene.
    pub scene: Scene,
    /// How a recording's header names the scene: the built-in name, or the scene file's path
    /// relative to the working directory.
    pub scene_ref: String,
    /// The seed.
    pub seed: u64,
    /// The file's `config`: the overrides of the defaults.
    pub config: Overrides,
}

impl Loaded {
    /// Reads and checks a scenario file.
    pub fn load(path: &Path) -> Result<Loaded, ScenarioError> {
        let text = files::read_text(path, Kind::Scenario)?;
        Loaded::from_text(path, text)
    }

    /// Checks scenario text as if read from `path` (scene paths are relative to its folder).
    pub fn from_text(path: &Path, text: String) -> Result<Loaded, ScenarioError> {
        let shown = path.display().to_string();
        let invalid = |message: String| ScenarioError::Invalid { file: shown.clone(), message };
        let scenario = parse(&text, &shown)?;
        // A scene file is found as a recording's header finds one: inside the scenario's
        // folder or the working directory, ending in .ron, never quoted in an error.
        let dir = path.parent().unwrap_or(Path::new(""));
        let scene = crate::replay::scene_ref::resolve_scene(&scenario.scene, Some(dir)).map_err(|e| {
            invalid(
                e.to_string()
                    .replace("the recording's folder", "the scenario's folder")
                    .replace("a recording may", "a scenario may"),
            )
        })?;
        let scene_ref = if Scene::builtin(&scenario.scene).is_some() {
            scenario.scene.clone()
        } else {
            // As the kept recording's header names it: relative to the working directory.
            let cwd = std::env::current_dir().ok().and_then(|d| d.canonicalize().ok());
            let abs = [dir.join(&scenario.scene), PathBuf::from(&scenario.scene)]
                .iter()
                .find_map(|p| p.canonicalize().ok())
                .unwrap_or_default();
            cwd.and_then(|d| abs.strip_prefix(d).ok().map(Path::to_path_buf)).unwrap_or(abs).display().to_string()
        };
        let config_text: Overrides = scenario
            .config
            .iter()
            .map(|(k, v)| Override::new(k, &v.to_string()))
            .collect::<Result<_, _>>()
            .map_err(|e| invalid(format!("config: {e}")))?;
        config_text.config().map_err(|e| invalid(format!("config: {e}")))?;
        let catalogue = if scene.banks.is_empty() {
            Catalogue::builtin()
        } else {
            crate::bank::Banks::open(&scene.bank_dirs())
                .and_then(|b| b.session_catalogue())
                .map_err(|e| invalid(format!("scene banks: {e}")))?
                .0
        };
        check(&scenario, &catalogue).map_err(|e| invalid(e.to_string()))?;
        let name = scenario.name.clone().unwrap_or_else(|| {
            let file = path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
            file.strip_suffix(".ron").unwrap_or(&file).to_string()
        });
        let seed = scenario.seed.unwrap_or(scene.seed);
        Ok(Loaded { path: path.to_path_buf(), name, text, scenario, scene, scene_ref, seed, config: config_text })
    }
}

/// Checks every step and expectation: known models, tasks, techniques and log kinds; finite
/// numbers; no hash inside a wait; the steps and ticks within their limits.
pub fn check(s: &Scenario, catalogue: &Catalogue) -> Result<(), CheckError> {
    if s.steps.len() + s.expect.len() > MAX_SCENARIO_STEPS {
        return Err(CheckError::TooManySteps(s.steps.len() + s.expect.len()));
    }
    let mut ticks: u64 = 0;
    for (i, step) in s.steps.iter().enumerate() {
        let at = |error: StepError| CheckError::Step { number: i + 1, text: step.text(), error };
        check_step(step, catalogue).map_err(at)?;
        ticks = ticks.saturating_add(step.max_ticks());
        if ticks > MAX_SCENARIO_TICKS {
            return Err(at(StepError::TooManyTicks(ticks)));
        }
    }
    for (i, e) in s.expect.iter().enumerate() {
        e.validate(catalogue).map_err(|error| CheckError::Expect { number: i + 1, text: e.text(), error })?;
    }
    Ok(())
}

fn finite_point(what: &'static str, p: Vec3) -> Result<(), StepError> {
    if p.is_finite() && p.abs().max_element() <= crate::limits::MAX_COORD {
        Ok(())
    } else {
        Err(StepError::NotFinite { what, point: p })
    }
}

fn check_aim(aim: &Aim) -> Result<(), StepError> {
    match aim {
        Aim::Point(x, y, z) => finite_point("the point", Vec3::new(*x, *y, *z)),
        Aim::Target(0) => Err(StepError::TargetZero),
        Aim::Tree { tree, offset } => {
            check_tree(tree)?;
            finite_point("the offset", offset.unwrap_or_default())
        }
        Aim::Mark { offset, y, .. } => {
            finite_point("the offset", *offset)?;
            finite_point("y", Vec3::new(0.0, y.unwrap_or(0.0), 0.0))
        }
        Aim::Target(_) => Ok(()),
    }
}

fn check_tree(tree: &TreeRef) -> Result<(), StepError> {
    match tree {
        TreeRef::Planted(0) => Err(StepError::PlantedZero),
        TreeRef::Nearest(x, y, z) => finite_point("the point", Vec3::new(*x, *y, *z)),
        _ => Ok(()),
    }
}

fn check_step(step: &Step, catalogue: &Catalogue) -> Result<(), StepError> {
    match step {
        Step::ChooseModel(m) | Step::Plant { model: m, .. } if catalogue.by_name(m).is_none() => {
            Err(StepError::UnknownModel(catalogue.unknown_name(m)))
        }
        Step::Plant { at, .. } => check_aim(at),
        Step::Remove(tree) => check_tree(tree),
        Step::Drag { tree, to } => {
            check_tree(tree)?;
            check_aim(to)
        }
        Step::PointAt(aim) | Step::Mark { at: aim, .. } => check_aim(aim),
        Step::Sweep { from, by, .. } => {
            check_aim(from)?;
            finite_point("by", *by)
        }
        Step::Controller { position, rotation } | Step::Head { position, rotation } => {
            Ok(crate::input::InputEvent::ControllerPose {
                pose: crate::components::Pose { position: *position, rotation: *rotation },
            }
            .validate()?)
        }
        Step::Touchpad { x, y, .. } if !(x.is_finite() && y.is_finite() && x.abs() <= 1.0 && y.abs() <= 1.0) => {
            Err(StepError::Touchpad)
        }
        // The event's own rule (finite, within [−1, 1]).
        Step::ScalePad { value, .. } => {
            crate::input::InputEvent::ScaleAxis { value: *value }.validate().map_err(|_| StepError::ScalePad)
        }
        Step::WaitUntil { until: Expect::Hash(_), .. } => Err(StepError::WaitForHash),
        Step::WaitUntil { until, .. } | Step::Expect(until) => Ok(until.validate(catalogue)?),
        Step::StartTask(id) if crate::task::TaskDef::builtin(id).is_none() => Err(StepError::UnknownTask(id.clone())),
        Step::SwitchTechnique(name) => technique(name).map(|_| ()).map_err(StepError::from),
        Step::Name { tree, .. } => check_tree(tree),
        _ => Ok(()),
    }
}
