//! From a recorded session to a scenario file (`grove scenario from-recording`): steps from the
//! recording's input events, expectations drafted from the state the steps reach, for a person
//! to edit.
//!
//! The steps re-enact the session: each event becomes the step of the same meaning (a
//! controller pose a `Controller` step, a button `Hold` and `Release`, a touchpad hold a
//! `Touchpad` step, …) and the gaps between events become `Wait` steps. Controller and head
//! poses while no button is held are kept only where they change something: the last of each
//! run of poses. Each step takes its own ticks (docs/scenarios.md), so the re-enactment can lag
//! the recording by a few ticks; the expectations are therefore drafted from the draft's own
//! run, and [`Draft::same_as_recording`] says whether it ended in the recording's world.

use std::path::Path;

use glam::Vec2;

use crate::catalogue::Catalogue;
use crate::expect::{Ball, Expect, Selected};
use crate::input::{InputEvent, StampedEvent};
use crate::replay::Header;
use crate::targets::Names;

use super::run::{RunOptions, run};
use super::{Btn, DraftError, Loaded, Scenario, Step};

/// A drafted scenario.
pub struct Draft {
    /// The scenario file's text.
    pub text: String,
    /// The number of steps.
    pub steps: usize,
    /// The number of expectations.
    pub expectations: usize,
    /// Whether the draft's run ended with the recording's final world hash.
    pub same_as_recording: bool,
}

/// How long event `i` (a touchpad's or the Scale pad's) is held: until the next event of its kind
/// (`same`), or one tick; at least one.
fn held_ticks(events: &[StampedEvent], i: usize, same: impl Fn(&InputEvent) -> bool) -> u64 {
    let tick = events[i].tick;
    let until = events[i + 1..].iter().find(|n| same(&n.event)).map_or(tick + 1, |n| n.tick);
    until.saturating_sub(tick).max(1)
}

/// The steps that re-enact a recording's events, up to `end_tick`.
pub fn steps_from_events(events: &[StampedEvent], catalogue: &Catalogue, end_tick: u64) -> Vec<Step> {
    let mut steps = Vec::new();
    let mut tick = 0u64;
    let mut held = 0usize;
    let mut touch_until: Option<u64> = None;
    let mut scale_until: Option<u64> = None;
    for (i, e) in events.iter().enumerate() {
        let next = events.get(i + 1).map(|n| &n.event);
        let skip = match (&e.event, next) {
            (InputEvent::ControllerPose { .. }, Some(InputEvent::ControllerPose { .. })) => held == 0,
            (InputEvent::HeadPose { .. }, Some(InputEvent::HeadPose { .. })) => true,
            (InputEvent::TouchpadAxes { axes }, _) => *axes == Vec2::ZERO,
            (InputEvent::ScaleAxis { value }, _) => *value == 0.0,
            _ => false,
        };
        match &e.event {
            InputEvent::ButtonDown { .. } => held += 1,
            InputEvent::ButtonUp { .. } => held = held.saturating_sub(1),
            _ => {}
        }
        let touching = matches!(e.event, InputEvent::TouchpadAxes { .. }) && touch_until.is_some_and(|t| e.tick < t)
            || matches!(e.event, InputEvent::ScaleAxis { .. }) && scale_until.is_some_and(|t| e.tick < t);
        if skip || touching {
            continue;
        }
        if e.tick > tick {
            steps.push(Step::Wait(e.tick - tick));
            tick = e.tick;
        }
        let (step, ticks) = match &e.event {
            InputEvent::ControllerPose { pose } => {
                (Step::Controller { position: pose.position, rotation: pose.rotation }, 1)
            }
            InputEvent::HeadPose { pose } => (Step::Head { position: pose.position, rotation: pose.rotation }, 1),
            InputEvent::ButtonDown { button } => (Step::Hold(Btn::from(*button)), 1),
            InputEvent::ButtonUp { button } => (Step::Release(Btn::from(*button)), 1),
            InputEvent::TouchpadAxes { axes } => {
                let ticks = held_ticks(events, i, |n| matches!(n, InputEvent::TouchpadAxes { .. }));
                touch_until = Some(e.tick + ticks);
                (Step::Touchpad { x: axes.x, y: axes.y, ticks }, ticks + 1)
            }
            InputEvent::ScaleAxis { value } => {
                let ticks = held_ticks(events, i, |n| matches!(n, InputEvent::ScaleAxis { .. }));
                scale_until = Some(e.tick + ticks);
                (Step::ScalePad { value: *value, ticks }, ticks + 1)
            }
            InputEvent::OpenMenu => (Step::OpenMenu, 1),
            InputEvent::CloseMenu => (Step::CloseMenu, 1),
            InputEvent::ChooseModel { model } => {
                let name = catalogue
                    .resolve(model)
                    .ok()
                    .and_then(|id| catalogue.get(id))
                    .map_or_else(|| format!("{model:?}"), |m| m.name.clone());
                (Step::ChooseModel(name), 1)
            }
            InputEvent::SwitchMode { mode } => (Step::SwitchTechnique(mode.name().to_string()), 1),
            InputEvent::SwitchTechnique { technique } => (Step::SwitchTechnique(technique.clone()), 1),
            InputEvent::StartTask { task, .. } => (Step::StartTask(task.clone()), 1),
            InputEvent::EndTask => (Step::EndTask, 1),
        };
        steps.push(step);
        tick += ticks;
    }
    if end_tick > tick {
        steps.push(Step::Wait(end_tick - tick));
    }
    steps
}

/// Expectations that hold for a run's final state: the number of trees, each tree the run
/// planted near where it stands, the task's outcome, the selection, the anchor ball, no errors
/// where there were none, and the world hash.
pub fn expectations(sim: &crate::sim::Sim, names: &Names) -> Vec<Expect> {
    let mut out = vec![Expect::TreeCount(sim.tree_ids().len())];
    for id in names.planted(sim) {
        if let Some(t) = sim.tree(id) {
            let model = sim.res.catalogue.get(t.tree.model).map_or_else(String::new, |m| m.name.clone());
            let p = t.transform.translation;
            let round = |x: f32| (x * 100.0).round() / 100.0;
            out.push(Expect::TreeNear {
                model,
                point: glam::Vec3::new(round(p.x), round(p.y), round(p.z)),
                within: 0.5,
            });
        }
    }
    if let Some(task) = &sim.res.task {
        match task.completed_tick {
            Some(t) => {
                let secs = crate::task::ticks_to_seconds(t - task.started_tick, sim.res.dt);
                out.push(Expect::TaskCompleted { within_s: (secs + 1.0).ceil() as f32 });
            }
            None => out.extend(
                task.satisfied
                    .iter()
                    .enumerate()
                    .filter(|(_, s)| s.is_some())
                    .map(|(i, _)| Expect::TargetSatisfied(i + 1)),
            ),
        }
    }
    let selected = match sim.selection().tree.and_then(|id| sim.tree(id)) {
        Some(t) => Selected::Model(sim.res.catalogue.get(t.tree.model).map_or_else(String::new, |m| m.name.clone())),
        None => Selected::Nothing,
    };
    out.push(Expect::Selected(selected));
    let b = sim.anchor_ball();
    out.push(Expect::AnchorBall(match (b.visible, b.armed) {
        (false, _) => Ball::Hidden,
        (true, false) => Ball::Green,
        (true, true) => Ball::White,
    }));
    let candidates = vec![Expect::NoErrors, Expect::Hash(crate::hash::hex(sim.hash().total))];
    out.extend(candidates.into_iter().filter(|e| e.check(sim, names).is_ok()));
    out
}

/// Drafts a scenario for the output path `out` (its scene named relative to that file) from a
/// recording's header and events; `recording_dir` is the recording's folder (where a scene
/// file it names is looked up) and `final_hash` the recording's final world hash.
pub fn draft(
    header: &Header,
    events: &[StampedEvent],
    recording_dir: Option<&Path>,
    final_hash: &str,
    end_tick: u64,
    out: &Path,
) -> Result<Draft, DraftError> {
    let sim = crate::replay::sim_for_header(header, recording_dir, &[])?;
    let scene = if crate::scene::Scene::builtin(&header.scene).is_some() {
        header.scene.clone()
    } else {
        let base = recording_dir.filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        let at = base.join(&header.scene);
        at.canonicalize().map_err(|error| DraftError::ScenePath { path: at.clone(), error })?.display().to_string()
    };
    let config = header.config.as_slice().iter().map(|o| (o.name.to_string(), o.value)).collect();
    let mut scenario = Scenario {
        name: None,
        scene,
        seed: Some(header.seed),
        press_on_nothing: false,
        config,
        steps: steps_from_events(events, &sim.res.catalogue, end_tick),
        expect: Vec::new(),
    };
    let loaded = Loaded::from_text(out, write(&scenario)?)?;
    let outcome = run(&loaded, &RunOptions::default())?;
    if let Some(f) = outcome.failure {
        return Err(DraftError::DoesNotRun(f));
    }
    let names = Names::default();
    scenario.expect = expectations(&outcome.sim, &names);
    let same = crate::hash::hex(outcome.sim.hash().total) == final_hash;
    let text = format!(
        "// Drafted by `grove scenario from-recording` from a recording of scene {:?}, seed {}.\n// Edit the steps and expectations (docs/scenarios.md); run it with `grove test FILE`.\n{}\n",
        header.scene,
        header.seed,
        write(&scenario)?
    );
    Ok(Draft { text, steps: scenario.steps.len(), expectations: scenario.expect.len(), same_as_recording: same })
}

/// A scenario as RON text.
pub fn write(s: &Scenario) -> Result<String, ron::Error> {
    // Each step and expectation on a line of its own; `Some(…)` left out, as files may.
    let pretty = ron::ser::PrettyConfig::new()
        .depth_limit(2)
        .indentor("    ")
        .extensions(ron::extensions::Extensions::IMPLICIT_SOME);
    let text = ron::ser::to_string_pretty(s, pretty)?;
    // The struct's name makes the file say what it is; RON allows it before the parenthesis.
    let at = if text.starts_with('(') { Some(0) } else { text.find("\n(").map(|k| k + 1) };
    Ok(match at {
        Some(k) => format!("{}Scenario{}", &text[..k], &text[k..]),
        None => text,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::Pose;
    use crate::input::Button;
    use glam::Vec3;

    fn at(tick: u64, event: InputEvent) -> StampedEvent {
        StampedEvent { tick, event }
    }

    #[test]
    fn a_scale_pad_held_becomes_one_step_and_its_release_is_part_of_it() {
        let events = vec![at(5, InputEvent::ScaleAxis { value: 1.0 }), at(35, InputEvent::ScaleAxis { value: 0.0 })];
        let steps = steps_from_events(&events, &Catalogue::builtin(), 60);
        assert_eq!(steps, vec![Step::Wait(5), Step::ScalePad { value: 1.0, ticks: 30 }, Step::Wait(24)]);
    }

    #[test]
    fn poses_collapse_while_nothing_is_held_and_gaps_become_waits() {
        let pose = |x: f32| Pose::looking_at(Vec3::new(x, 1.0, 0.0), Vec3::new(x, 0.0, -3.0));
        let events = vec![
            at(3, InputEvent::ControllerPose { pose: pose(0.0) }),
            at(4, InputEvent::ControllerPose { pose: pose(1.0) }),
            at(10, InputEvent::ButtonDown { button: Button::Trigger }),
            at(12, InputEvent::ControllerPose { pose: pose(2.0) }),
            at(13, InputEvent::ControllerPose { pose: pose(3.0) }),
            at(14, InputEvent::ButtonUp { button: Button::Trigger }),
            at(20, InputEvent::TouchpadAxes { axes: Vec2::new(0.0, 1.0) }),
            at(50, InputEvent::TouchpadAxes { axes: Vec2::ZERO }),
        ];
        let steps = steps_from_events(&events, &Catalogue::builtin(), 60);
        let p = |x: f32| Step::Controller { position: pose(x).position, rotation: pose(x).rotation };
        assert_eq!(
            steps,
            vec![
                Step::Wait(4),
                p(1.0),
                Step::Wait(5),
                Step::Hold(Btn::Trigger),
                Step::Wait(1),
                p(2.0),
                p(3.0),
                Step::Release(Btn::Trigger),
                Step::Wait(5),
                Step::Touchpad { x: 0.0, y: 1.0, ticks: 30 },
                Step::Wait(9),
            ]
        );
    }

    #[test]
    fn a_shipped_model_chosen_by_index_is_written_by_name() {
        let events = vec![at(0, InputEvent::ChooseModel { model: crate::catalogue::ModelId(2).into() })];
        assert_eq!(steps_from_events(&events, &Catalogue::builtin(), 1), vec![Step::ChooseModel("birch-mesh".into())]);
    }
}
