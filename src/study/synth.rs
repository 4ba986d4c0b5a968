//! Synthetic participants: closed-loop generation of study recordings.
//!
//! A synthetic participant watches the simulation the way a person watches the display (where
//! the ray hits, which tree is selected, whether the anchor ball is white) and answers only with
//! input events: controller and head poses, button presses, touchpad axes and menu actions. The
//! human-performance model is in [`super::participant`] and `docs/participants.md`. The events
//! are then written as a recording by re-simulating them from scratch
//! ([`grove_systems::replay::record_events`]), so every checkpoint and every timing in the file
//! comes from the simulation, never from the generator.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use grove_systems::resources::Override;
use grove_systems::catalogue::ModelId;
use grove_systems::components::{AnchorBall, HitMarker, HitTarget, Pose, Transform};
use grove_systems::events::Happening;
use grove_systems::input::{Button, InputEvent, StampedEvent};
use grove_systems::replay::{record_events, Header};
use grove_systems::resources::Mode;
use grove_systems::scene::Scene;
use grove_systems::script::Script;
use grove_systems::task::TaskDef;
use grove_systems::technique::{Operator, Technique};
use grove_systems::Sim;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::error::SynthError;
use super::shard::Shard;
use super::participant::{angle_between, angular_width, scatter_direction, sweep, Skill};

/// A controller pose is sent every this many ticks while the hand moves (30 Hz at 60 Hz ticks),
/// like a tracking system that reports at half the simulation rate.
pub const POSE_EVERY: u64 = 2;
/// The most corrective sub-movements before a participant accepts where the ray is.
pub const MAX_CORRECTIONS: usize = 6;
/// The fraction of the tolerance radius a participant aims to be within before committing.
pub const AIM_MARGIN: f32 = 0.6;

/// The recordings of one participant's two tasks.
pub struct ParticipantSession {
    /// The header of the recording.
    pub header: Header,
    /// The input events.
    pub events: Vec<StampedEvent>,
    /// The tick to record up to.
    pub end_tick: u64,
}

pub(crate) struct Participant {
    pub(crate) script: Script,
    pub(crate) rng: ChaCha8Rng,
    pub(crate) skill: Skill,
    pub(crate) hand: Vec3,
    pub(crate) dir: Vec3,
    pub(crate) dt: f64,
}

impl Participant {
    pub(crate) fn ticks(&self, seconds: f64) -> u64 {
        (seconds / self.dt).round().max(1.0) as u64
    }

    pub(crate) fn sim(&self) -> &Sim {
        self.script.sim()
    }

    fn pose(&self, dir: Vec3) -> Pose {
        Pose::looking_at(self.hand, self.hand + dir)
    }

    pub(crate) fn think(&mut self) {
        let jitter: f64 = self.rng.random_range(0.85..1.15);
        let n = self.ticks(self.skill.mental * jitter);
        self.script.wait(n);
    }

    pub(crate) fn press(&mut self, button: Button) {
        let down = self.ticks(0.1);
        let rest = self.ticks((self.skill.press - 0.1).max(self.dt));
        self.script.push(InputEvent::ButtonDown { button }).wait(down);
        self.script.push(InputEvent::ButtonUp { button }).wait(rest);
    }

    /// Moves the ray from its direction to `to` along a minimum-jerk path in `ticks` ticks,
    /// running `during(tick_index)` before each tick (for concurrent touchpad use).
    fn sweep_ray(&mut self, to: Vec3, ticks: u64, mut during: impl FnMut(&mut Script, u64)) {
        let from = self.dir;
        for k in 1..=ticks {
            during(&mut self.script, k);
            if k % POSE_EVERY == 0 || k == ticks {
                let d = sweep(from, to, k as f64 / ticks as f64);
                let pose = self.pose(d);
                self.script.push(InputEvent::ControllerPose { pose });
            }
            self.script.wait(1);
        }
        self.dir = to.normalize();
    }

    fn look_at(&mut self, point: Vec3) {
        let head = self.script.head().pose.position;
        self.script.push(InputEvent::HeadPose { pose: Pose::looking_at(head, point) });
    }

    /// Aims the ray at `point`, a target of angular width `width`, with Fitts timing and
    /// endpoint scatter, then corrects until `ok` holds (or gives up). `sloppy` skips the
    /// corrections and widens the scatter: an early click.
    fn aim(&mut self, point: Vec3, width: f64, sloppy: bool, ok: &dyn Fn(&Sim) -> bool) {
        self.look_at(point);
        let mut sigma = self.skill.endpoint_sigma(width) * if sloppy { 4.0 } else { 1.0 };
        for attempt in 0..=MAX_CORRECTIONS {
            let target = (point - self.hand).normalize();
            let amplitude = angle_between(self.dir, target);
            if attempt > 0 && ok(self.sim()) {
                return;
            }
            let time = self.skill.aim_time(amplitude, width);
            let end = scatter_direction(&mut self.rng, target, sigma);
            let n = self.ticks(time);
            self.sweep_ray(end, n, |_, _| {});
            if sloppy || ok(self.sim()) {
                return;
            }
            // Corrective sub-movements are shorter and more precise.
            sigma *= 0.6;
        }
    }

    fn hit(&self) -> HitMarker {
        self.sim().hit_marker()
    }

    pub(crate) fn ground_at(&self, x: f32, z: f32) -> f32 {
        self.sim().ground_below(Vec3::new(x, 50.0, z), 0.0).map_or(0.0, |h| h.point.y)
    }

    pub(crate) fn choose(&mut self, model: ModelId) {
        self.press(Button::Menu);
        let n = self.ticks(self.skill.menu_time());
        self.script.wait(n);
        // The study's synthetic participants name shipped models by index, as the committed
        // recordings have it; everything else names models by name.
        self.script.push(InputEvent::ChooseModel { model: model.into() }).wait(1);
    }

    pub(crate) fn last_planted(&self) -> Option<(u64, Vec3)> {
        self.sim().log().entries.iter().rev().find_map(|e| match e.what {
            Happening::Planted { tree, position, .. } => Some((tree, position)),
            _ => None,
        })
    }

    pub(crate) fn tree(&self, id: u64) -> Option<(Transform, ModelId, f32)> {
        self.sim().tree(id).map(|t| (t.transform, t.tree.model, t.scale.0))
    }

    pub(crate) fn tree_center(&self, id: u64) -> Option<Vec3> {
        let (t, m, s) = self.tree(id)?;
        let info = self.sim().catalogue().get(m)?;
        Some(t.translation + Vec3::Y * (info.bounds_min.y + info.bounds_max.y) * 0.5 * s)
    }

    /// Points at a tree and presses Bumper to remove it.
    fn remove(&mut self, id: u64) {
        let Some(c) = self.tree_center(id) else { return };
        let width = angular_width(1.0, (c - self.hand).length() as f64);
        self.aim(c, width, false, &move |sim: &Sim| {
            let h = sim.hit_marker();
            h.visible && h.target == HitTarget::Tree(id)
        });
        self.press(Button::Bumper);
    }

    fn ray_casting_target(&mut self, pos: Vec3, model: ModelId, tolerance: f32) {
        let error = self.rng.random::<f64>() < self.skill.error_rate;
        let wrong_model = error && self.rng.random::<bool>();
        let mut sloppy = error && !wrong_model;
        self.think();
        let models = self.sim().catalogue().len() as u8;
        let chosen = if wrong_model { ModelId((model.0 + 1 + self.rng.random_range(0..models - 1)) % models) } else { model };
        if self.sim().menu().current_model != chosen {
            self.choose(chosen);
        }
        let goal = Vec2::new(pos.x, pos.z);
        let margin = tolerance * AIM_MARGIN;
        for _ in 0..8 {
            let point = Vec3::new(pos.x, self.ground_at(pos.x, pos.z), pos.z);
            let width = angular_width(2.0 * margin as f64, (point - self.hand).length() as f64);
            let ok = move |sim: &Sim| {
                let h = sim.hit_marker();
                h.visible && matches!(h.target, HitTarget::Plane(_)) && Vec2::new(h.position.x, h.position.z).distance(goal) < margin
            };
            // An early click skips the corrections once; the plant then usually lands off target.
            self.aim(point, width, sloppy, &ok);
            sloppy = false;
            let before = self.last_planted().map(|p| p.0);
            self.press(Button::Trigger);
            let Some((id, at)) = self.last_planted().filter(|p| Some(p.0) != before) else {
                // Nothing was planted (the ray was on a tree or on nothing): look again.
                self.think();
                continue;
            };
            let off = Vec2::new(at.x, at.z).distance(goal) > tolerance;
            let wrong = self.tree(id).is_some_and(|t| t.1 != model);
            if !off && !wrong {
                return;
            }
            // The participant notices the mistake, removes the tree and tries again.
            self.think();
            self.remove(id);
            if wrong {
                self.choose(model);
            }
        }
    }

    fn selected(&self) -> Option<u64> {
        self.sim().selection().tree
    }

    fn anchor(&self) -> AnchorBall {
        self.sim().anchor_ball()
    }

    fn manual_target(&mut self, pos: Vec3, model: ModelId, tolerance: f32) -> Result<(), SynthError> {
        let error = self.rng.random::<f64>() < self.skill.error_rate;
        let wrong_model = error && self.rng.random::<bool>();
        let early_release = error && !wrong_model;
        self.think();
        let models = self.sim().catalogue().len() as u8;
        let chosen = if wrong_model { ModelId((model.0 + 1 + self.rng.random_range(0..models - 1)) % models) } else { model };
        self.choose(chosen);
        let id = self.selected().ok_or_else(|| stuck("no tree appeared after choosing a model from the menu"))?;
        self.drag_into_place(id, pos, tolerance, early_release)?;
        if wrong_model {
            self.think();
            self.remove(id);
            self.think();
            self.choose(model);
            let id = self.selected().ok_or_else(|| stuck("no tree appeared after choosing a model from the menu"))?;
            self.drag_into_place(id, pos, tolerance, false)?;
        }
        Ok(())
    }

    /// Grabs a tree and drags it to the target with ray and touchpad until the anchor ball is
    /// white over the target, then releases.
    fn drag_into_place(&mut self, id: u64, pos: Vec3, tolerance: f32, early_release: bool) -> Result<(), SynthError> {
        let goal = Vec2::new(pos.x, pos.z);
        for grab in 0..4 {
            let c = self.tree_center(id).ok_or_else(|| stuck("the tree to drag is gone"))?;
            let width = angular_width(1.0, (c - self.hand).length() as f64);
            self.aim(c, width, false, &move |sim: &Sim| {
                let h = sim.hit_marker();
                h.visible && h.target == HitTarget::Tree(id)
            });
            if self.hit().target != HitTarget::Tree(id) {
                continue;
            }
            let press = self.ticks(0.1);
            self.script.push(InputEvent::ButtonDown { button: Button::Trigger }).wait(press);
            for attempt in 0..MAX_CORRECTIONS {
                let Some(drag) = self.sim().interaction().drag else { break };
                let (_, m, s) = self.tree(id).ok_or_else(|| stuck("the dragged tree is gone"))?;
                let lowest = self.sim().catalogue().get(m).map_or(0.0, |i| i.lowest_point()) * s;
                let base = Vec3::new(pos.x, self.ground_at(pos.x, pos.z) - lowest, pos.z);
                let grab_point = base - drag.offset;
                let want = grab_point - self.hand;
                let dir_sigma = self.skill.endpoint_sigma(angular_width(2.0 * (tolerance * AIM_MARGIN) as f64, want.length() as f64));
                let amplitude = angle_between(self.dir, want);
                let rot_time = self.skill.aim_time(amplitude, angular_width(2.0 * (tolerance * AIM_MARGIN) as f64, want.length() as f64));
                let rate = self.sim().config().touchpad_move_rate as f64;
                let delta = want.length() as f64 - drag.grab_distance as f64;
                // Rate control is imprecise: the thumb comes off a little early or late.
                let timing: f64 = if attempt == 0 { self.rng.random_range(0.93..1.07) } else { 1.0 };
                let touch_ticks = if delta.abs() > 0.05 { self.ticks(delta.abs() / rate * timing) } else { 0 };
                let rot_ticks = self.ticks(rot_time);
                let end = scatter_direction(&mut self.rng, want, dir_sigma * if attempt == 0 { 1.0 } else { 0.6 });
                let sign = delta.signum() as f32;
                let total = rot_ticks.max(touch_ticks);
                // The ray sweeps over the rotation time; the thumb pushes for the touch time.
                let from = self.dir;
                for k in 1..=total {
                    if k == 1 && touch_ticks > 0 {
                        self.script.push(InputEvent::TouchpadAxes { axes: Vec2::new(0.0, sign) });
                    }
                    if k == touch_ticks + 1 && touch_ticks > 0 {
                        self.script.push(InputEvent::TouchpadAxes { axes: Vec2::ZERO });
                    }
                    if k <= rot_ticks && (k % POSE_EVERY == 0 || k == rot_ticks) {
                        let d = sweep(from, end, k as f64 / rot_ticks as f64);
                        let pose = self.pose(d);
                        self.script.push(InputEvent::ControllerPose { pose });
                    }
                    self.script.wait(1);
                }
                if touch_ticks >= total && touch_ticks > 0 {
                    self.script.push(InputEvent::TouchpadAxes { axes: Vec2::ZERO }).wait(1);
                }
                self.dir = end.normalize();
                let ball = self.anchor();
                let here = self.tree(id).map(|t| Vec2::new(t.0.translation.x, t.0.translation.z)).unwrap_or(goal);
                if early_release && grab == 0 && attempt == 0 {
                    break;
                }
                if ball.visible && ball.armed && here.distance(goal) < tolerance * AIM_MARGIN {
                    break;
                }
            }
            let rest = self.ticks((self.skill.press - 0.1).max(self.dt));
            self.script.push(InputEvent::ButtonUp { button: Button::Trigger }).wait(rest);
            let grounded = self.sim().tree(id).is_some_and(|t| t.grounded.0);
            let here = self.tree(id).map(|t| Vec2::new(t.0.translation.x, t.0.translation.z)).unwrap_or(Vec2::splat(f32::MAX));
            if grounded && here.distance(goal) <= tolerance {
                return Ok(());
            }
            self.think();
        }
        Err(stuck(&format!("could not place the tree at ({:.2}, {:.2}) after several tries", pos.x, pos.z)))
    }
}

/// A participant who cannot go on, and why.
pub(crate) fn stuck(why: &str) -> SynthError {
    SynthError::Participant(why.to_string())
}

/// Generates one participant's session for a task, under the configuration `overrides`
/// (`name=value`, empty for the defaults). With overrides, a participant who cannot finish
/// still gives a session (an incomplete trial, as a person would leave it) and a warning through
/// `warn`; without, that is an error.
///
/// With a plug-in `technique` (`None`: the task's built-in one) the recording's header names the
/// plug-in and its version, and its participant model decides how each target is placed
/// ([`super::synth_plugin`]).
pub fn synthesize_with(task: &TaskDef, technique: Option<&Technique>, participant: usize, seed: u64, overrides: &[Override], warn: &dyn Fn(&str)) -> Result<ParticipantSession, SynthError> {
    let scene = Scene::builtin(&task.scene).ok_or_else(|| SynthError::UnknownScene { task: task.id.clone(), scene: task.scene.clone() })?;
    // Each participant has one skill for both tasks; each task has its own simulation seed.
    let mut skill_rng = ChaCha8Rng::seed_from_u64(seed ^ (participant as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
    let skill = Skill::sample(&mut skill_rng);
    let task_salt = task.id.bytes().fold(0u64, |h, b| h.wrapping_mul(131).wrapping_add(b as u64));
    let sim_seed = seed.wrapping_mul(1000).wrapping_add(participant as u64);
    let mut sim = Sim::from_scene(&scene, sim_seed).map_err(grove_systems::Error::from)?;
    let mut config = sim.config().clone();
    config.apply(overrides).map_err(SynthError::Settings)?;
    sim.set_up().config(config);
    let rng = ChaCha8Rng::seed_from_u64(seed ^ task_salt ^ (participant as u64) << 32);
    let script = Script::new(sim);
    let hand = script.controller().pose.position;
    let dir = script.controller().pose.forward();
    let dt = script.sim().dt() as f64;
    let mut p = Participant { script, rng, skill, hand, dir, dt };

    let mut header = Header::new(&task.scene, sim_seed, scene.dt);
    header.task = Some(task.id.clone());
    header.participant = Some(format!("P{:02}", participant + 1));
    header.synthetic = true;
    header.config = overrides.iter().cloned().collect();

    p.script.wait(30);
    p.script.push(InputEvent::SwitchMode { mode: task.mode }).wait(1);
    if let Some(t) = technique {
        p.script.push(InputEvent::SwitchTechnique { technique: t.name.to_string() }).wait(1);
        header.technique = Some(grove_systems::replay::HeaderTechnique { name: t.name.to_string(), version: t.version });
    }
    p.script.push(InputEvent::StartTask { task: task.id.clone(), layout: None }).wait(1);
    let models = task.target_models(p.sim().catalogue());
    // Far targets first, so that trees already planted never stand in the way of the ray.
    let mut order: Vec<usize> = (0..task.targets.len()).collect();
    order.sort_by(|&a, &b| {
        let da = (task.targets[a].position - p.hand).length();
        let db = (task.targets[b].position - p.hand).length();
        db.total_cmp(&da).then(a.cmp(&b))
    });
    // A plug-in whose participant aims with the head and dwells: its dwell, seconds.
    let gaze_dwell = technique.filter(|t| t.participant.contains(&Operator::AimHead)).map(|t| {
        t.participant.iter().find_map(|o| if let Operator::Dwell(s) = o { Some(*s as f64) } else { None }).unwrap_or(0.0)
    });
    for i in order {
        let model = models[i].ok_or(SynthError::UnknownModel(i + 1))?;
        let pos = task.targets[i].position;
        let placed = match task.mode {
            _ if gaze_dwell.is_some() => p.gaze_target(pos, model, task.tolerance, gaze_dwell.unwrap_or(0.0)),
            Mode::RayCasting => {
                p.ray_casting_target(pos, model, task.tolerance);
                Ok(())
            }
            Mode::Manual => p.manual_target(pos, model, task.tolerance),
        };
        if let Err(e) = placed {
            if overrides.is_empty() {
                return Err(e);
            }
            // Under a what-if setting the participant may be unable to go on: they stop here.
            warn(&format!("P{:02} {}: {e}; the participant stops and the trial stays incomplete", participant + 1, task.id));
            break;
        }
    }
    p.think();
    p.script.push(InputEvent::EndTask).wait(30);
    let end_tick = p.sim().tick();
    let completed = p.sim().task().is_some_and(|t| t.is_complete());
    if !completed && !overrides.is_empty() {
        warn(&format!("P{:02} {}: did not complete the task under the what-if setting", participant + 1, task.id));
    } else if !completed {
        if std::env::var_os("GROVE_SYNTH_DEBUG").is_some() {
            for e in &p.sim().log().entries {
                eprintln!("{} {:?}", e.tick, e.what);
            }
            eprintln!("{:?}", p.sim().task().map(|t| &t.satisfied));
        }
        return Err(SynthError::Incomplete { participant: participant + 1, task: task.id.clone() });
    }
    let (_, events) = p.script.into_parts();
    Ok(ParticipantSession { header, events, end_tick })
}

/// The wall-clock time the first synthetic session starts: 2019-06-03T09:00:00Z, seconds since
/// the Unix epoch. Participant `p` (0-based) starts `p` hours later.
pub const FIRST_SESSION_START: i64 = 1_559_552_400;
/// Seconds of rest between a participant's two blocks.
pub const REST_BETWEEN_BLOCKS_S: i64 = 120;

/// An RFC 3339 UTC time from seconds since the Unix epoch.
fn rfc3339(secs: i64) -> String {
    chrono::DateTime::from_timestamp(secs, 0).map(|t| t.to_rfc3339_opts(chrono::SecondsFormat::Secs, true)).unwrap_or_default()
}

/// One condition of a study: a task done with a technique.
pub struct Condition {
    /// The task (its targets and its built-in mode).
    pub task: TaskDef,
    /// A plug-in technique, or `None` for the task's built-in one.
    pub technique: Option<Technique>,
    /// The condition's name in file names: the task id for a built-in technique, the
    /// technique's name for a plug-in.
    pub name: String,
}

/// The conditions of the given techniques: ray-casting and manual do their own tasks; a
/// plug-in does the task of its base mode with its own technique.
pub fn conditions(names: &[&str]) -> Result<Vec<Condition>, SynthError> {
    let registered = grove_systems::technique::installed();
    let mut out: Vec<Condition> = Vec::new();
    for name in names {
        let t = registered.get(name).ok_or_else(|| SynthError::UnknownTechnique(registered.unknown(name)))?;
        if out.iter().any(|c| c.technique.as_ref().map_or(c.task.mode.name(), |t| t.name) == t.name) {
            return Err(SynthError::TechniqueTwice(name.to_string()));
        }
        let id = match t.base {
            Mode::RayCasting => "ray-casting-7",
            Mode::Manual => "manual-7",
        };
        let task = TaskDef::builtin(id).ok_or_else(|| SynthError::MissingTask(id.to_string()))?;
        let (technique, name) = if t.is_builtin() { (None, id.to_string()) } else { (Some(t.clone()), t.name.to_string()) };
        out.push(Condition { task, technique, name });
    }
    Ok(out)
}

/// Writes `participants` × 2 recordings to `out` (one per participant per task), under the
/// configuration `overrides` (empty for the defaults): [`write_conditions`] with ray-casting and
/// manual. Existing files are never overwritten unless `force` is set. With a `shard`, only the
/// participants of that shard (by their id, `P07`, see [`super::shard`]) are written; each
/// participant's recordings are the same as without shards.
pub fn write_study(out: &Path, participants: usize, seed: u64, force: bool, overrides: &[Override], shard: Option<Shard>, progress: &dyn Fn(&str)) -> Result<Vec<PathBuf>, SynthError> {
    write_conditions(out, &conditions(&["ray-casting", "manual"])?, participants, seed, force, overrides, shard, progress)
}

/// Writes one recording per participant per condition to `out`. Each participant does the
/// conditions as blocks in the order of a balanced Latin square ([`super::latin::order`]; for
/// two conditions, even participants start with the first); headers carry the block and the
/// session start time. Existing files are never overwritten unless `force` is set. With a
/// `shard`, only that shard's participants are written.
#[allow(clippy::too_many_arguments)]
pub fn write_conditions(out: &Path, tasks: &[Condition], participants: usize, seed: u64, force: bool, overrides: &[Override], shard: Option<Shard>, progress: &dyn Fn(&str)) -> Result<Vec<PathBuf>, SynthError> {
    if out.exists() && !out.is_dir() {
        return Err(SynthError::OutIsAFile(out.to_path_buf()));
    }
    let mut planned = Vec::new();
    for p in (0..participants).filter(|p| shard.is_none_or(|s| s.holds(&format!("P{:02}", p + 1)))) {
        for (block, i) in super::latin::order(p, tasks.len()).into_iter().enumerate() {
            let t = &tasks[i];
            planned.push((p, block as u32 + 1, t, out.join(format!("P{:02}-{}.jsonl", p + 1, t.name))));
        }
    }
    if !force {
        if let Some((_, _, _, f)) = planned.iter().find(|(_, _, _, f)| f.exists()) {
            return Err(SynthError::Exists { file: f.clone(), out: out.to_path_buf() });
        }
    }
    std::fs::create_dir_all(out).map_err(|source| SynthError::Io { path: out.to_path_buf(), source })?;
    let mut written = Vec::new();
    let mut next_start = FIRST_SESSION_START;
    for (p, block, task, path) in planned {
        progress(&format!("P{:02} {}", p + 1, task.name));
        let mut session = synthesize_with(&task.task, task.technique.as_ref(), p, seed, overrides, progress)?;
        if block == 1 {
            next_start = FIRST_SESSION_START + 3600 * p as i64;
        }
        session.header.block = Some(block);
        session.header.session_start = Some(rfc3339(next_start));
        // The next block starts after this recording and a rest, on a whole second.
        let seconds = grove_systems::task::ticks_to_seconds(session.end_tick, session.header.dt).ceil() as i64;
        next_start += seconds + REST_BETWEEN_BLOCKS_S;
        let summary = serde_json::json!({ "generator": "grove synth", "seed": seed });
        // Write to a temporary file and rename, so a failure never leaves half a recording.
        let tmp = path.with_extension("jsonl.tmp");
        let file = std::fs::File::create(&tmp).map_err(|source| SynthError::Io { path: tmp.clone(), source })?;
        let w = record_events(std::io::BufWriter::new(file), &session.header, &session.events, session.end_tick, summary).map_err(|source| SynthError::Record { path: path.clone(), source })?;
        drop(w);
        std::fs::rename(&tmp, &path).map_err(|source| SynthError::Io { path: path.clone(), source })?;
        written.push(path);
    }
    Ok(written)
}
