//! Study tasks: definitions (from `assets/tasks/`) and the state the task system keeps.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::catalogue::{Catalogue, ModelId};
use crate::mode::Mode;

/// The task files that ship with grove, embedded at compile time: `(id, RON text)`.
pub const BUILTIN_TASKS: &[(&str, &str)] = &[
    ("ray-casting-7", include_str!("../../assets/tasks/ray-casting-7.ron")),
    ("manual-7", include_str!("../../assets/tasks/manual-7.ron")),
];

/// One target of a task: a place and the model that must stand there.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TargetDef {
    /// Target position, metres; only X and Z count for the tolerance.
    pub position: Vec3,
    /// The required model's catalogue name.
    pub model: String,
}

impl TargetDef {
    /// The required model, resolved against a catalogue; `None` if it has no such model.
    pub fn model_id(&self, catalogue: &Catalogue) -> Option<ModelId> {
        catalogue.by_name(&self.model).map(|m| m.id)
    }
}

/// A task file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaskDef {
    /// The task id, also the file stem, e.g. "ray-casting-7".
    pub id: String,
    /// The interaction mode the task is done in.
    pub mode: Mode,
    /// The scene file stem under `assets/scenes/`, e.g. "study".
    pub scene: String,
    /// How far (horizontally) a tree may stand from its target, metres.
    #[serde(default = "default_tolerance")]
    pub tolerance: f32,
    /// Whether a tree must be grounded to count.
    #[serde(default = "yes")]
    pub require_grounded: bool,
    /// The targets.
    pub targets: Vec<TargetDef>,
}

fn default_tolerance() -> f32 {
    0.5
}
fn yes() -> bool {
    true
}

crate::message_error::message_error! {
    /// Why a task file was refused: one line.
    TaskError
}

impl TaskDef {
    /// Parses and checks a task file against a catalogue.
    pub fn from_ron(text: &str, catalogue: &Catalogue) -> Result<TaskDef, TaskError> {
        Self::from_ron_message(text, catalogue).map_err(TaskError)
    }

    fn from_ron_message(text: &str, catalogue: &Catalogue) -> Result<TaskDef, String> {
        let def: TaskDef = ron::from_str(text).map_err(|e| format!("line {}, column {}: {}", e.span.start.line, e.span.start.col, e.code))?;
        if def.targets.is_empty() {
            return Err("a task needs at least one target".into());
        }
        if !(def.tolerance.is_finite() && def.tolerance > 0.0) {
            return Err("tolerance must be a positive number".into());
        }
        for (i, t) in def.targets.iter().enumerate() {
            if !t.position.is_finite() {
                return Err(format!("target {i} has a NaN or infinite position"));
            }
            if catalogue.by_name(&t.model).is_none() {
                return Err(format!("target {i}: {}", catalogue.unknown_name(&t.model)));
            }
        }
        Ok(def)
    }

    /// A task that ships with grove, by id.
    pub fn builtin(id: &str) -> Option<TaskDef> {
        // Each built-in task is parsed once per process.
        static PARSED: std::sync::OnceLock<Vec<Option<TaskDef>>> = std::sync::OnceLock::new();
        let i = BUILTIN_TASKS.iter().position(|(name, _)| *name == id)?;
        let parsed = PARSED.get_or_init(|| {
            let catalogue = Catalogue::builtin();
            BUILTIN_TASKS.iter().map(|(_, text)| TaskDef::from_ron(text, &catalogue).ok()).collect()
        });
        parsed[i].clone()
    }

    /// The required model of each target, resolved against a catalogue.
    pub fn target_models(&self, catalogue: &Catalogue) -> Vec<Option<ModelId>> {
        self.targets.iter().map(|t| t.model_id(catalogue)).collect()
    }
}

/// The first time a target was satisfied.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TargetHit {
    /// The tick at which it was first satisfied.
    pub tick: u64,
    /// The tree that satisfied it, by entity id bits.
    pub tree: u64,
    /// The tree's model.
    pub model: ModelId,
    /// Where the tree stood, metres.
    pub position: Vec3,
}

/// Errors made during a task, counted from the interaction event log.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct TaskErrors {
    /// Trees removed.
    pub removals: u32,
    /// Trees planted or snapped where no target of any model is within tolerance.
    pub off_target: u32,
    /// Drags released while the anchor ball was green (no snap).
    pub released_green: u32,
}

impl TaskErrors {
    /// The total number of errors.
    pub fn total(&self) -> u32 {
        self.removals + self.off_target + self.released_green
    }
}

/// What the task system measures while a task runs. Every field comes from the simulation and
/// its event log.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TaskState {
    /// The task being run.
    pub def: TaskDef,
    /// The tick of the StartTask event.
    pub started_tick: u64,
    /// Per target, the first time it was satisfied.
    pub satisfied: Vec<Option<TargetHit>>,
    /// The tick at which every target was satisfied.
    pub completed_tick: Option<u64>,
    /// The tick of the EndTask event, if any.
    pub ended_tick: Option<u64>,
    /// Error counts.
    pub errors: TaskErrors,
    /// How often the menu was opened.
    pub menu_opens: u32,
    /// Total distance travelled by the ray's hit point, metres.
    pub ray_path_length: f32,
    /// Ticks spent aiming (nothing held, menu closed).
    pub aiming_ticks: u64,
    /// Ticks with the menu open.
    pub menu_ticks: u64,
    /// Ticks spent manipulating a tree (dragging, handles, touchpad).
    pub manipulating_ticks: u64,
    /// The last hit point seen, for the ray path length.
    pub last_hit: Option<Vec3>,
    /// How many log entries the task system has read.
    pub log_cursor: usize,
    /// Where a room layout put the targets (`crate::room_layout`); absent for the task file's
    /// layout, and then not hashed, so that every earlier world hash stays as it was.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layout: Option<crate::room_layout::RoomPlacement>,
}

impl TaskState {
    /// A fresh state for a task that starts at `tick`.
    pub fn new(def: TaskDef, tick: u64) -> TaskState {
        let n = def.targets.len();
        TaskState {
            def,
            started_tick: tick,
            satisfied: vec![None; n],
            completed_tick: None,
            ended_tick: None,
            errors: TaskErrors::default(),
            menu_opens: 0,
            ray_path_length: 0.0,
            aiming_ticks: 0,
            menu_ticks: 0,
            manipulating_ticks: 0,
            last_hit: None,
            log_cursor: usize::MAX,
            layout: None,
        }
    }

    /// A fresh state whose targets are laid out as `layout` says (the task file's without one,
    /// or when the room's floor has no point far enough from its edges); the tolerance is scaled
    /// with the spacing.
    pub fn laid_out(mut def: TaskDef, tick: u64, layout: Option<&crate::room_layout::TaskLayout>) -> TaskState {
        let Some(crate::room_layout::TaskLayout::Room { floor, keep_out }) = layout else { return TaskState::new(def, tick) };
        let file: Vec<Vec3> = def.targets.iter().map(|t| t.position).collect();
        let Some((placed, placement)) = crate::room_layout::place(&file, floor, keep_out) else { return TaskState::new(def, tick) };
        for (t, p) in def.targets.iter_mut().zip(placed) {
            t.position = p;
        }
        def.tolerance *= placement.scale;
        TaskState { layout: Some(placement), ..TaskState::new(def, tick) }
    }

    /// Whether every target is satisfied.
    pub fn is_complete(&self) -> bool {
        self.completed_tick.is_some()
    }

    /// The tick at which the task's clock stopped, if it has: when the last target was
    /// satisfied (the task definition's end), or else at the participant's EndTask. A task
    /// that has neither keeps running; its time is then measured up to "now", whatever the
    /// caller's now is (the live window's tick, or the last tick of a recording).
    pub fn end_tick(&self) -> Option<u64> {
        match (self.completed_tick, self.ended_tick) {
            (Some(c), Some(e)) => Some(c.min(e)),
            (c, e) => c.or(e),
        }
    }

    /// Whether the task's clock has stopped (see [`TaskState::end_tick`]).
    pub fn is_over(&self) -> bool {
        self.end_tick().is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_tasks_have_seven_targets_and_both_model_kinds() {
        let cat = Catalogue::builtin();
        for (id, text) in BUILTIN_TASKS {
            let def = TaskDef::from_ron(text, &cat).unwrap_or_else(|e| panic!("{id}: {e}"));
            assert_eq!(&def.id, id);
            assert_eq!(def.targets.len(), 7);
            let kinds: std::collections::BTreeSet<_> =
                def.targets.iter().map(|t| format!("{:?}", cat.by_name(&t.model).unwrap().kind)).collect();
            assert_eq!(kinds.len(), 2, "{id} must use both mesh and billboard models");
        }
    }

    #[test]
    fn tick_counts_become_exact_seconds() {
        let dt = 1.0f32 / 60.0;
        // 5455 ticks at 60 Hz are 90 + 55/60 s; summing f32 steps would give 90.9166714...
        assert_eq!(ticks_to_seconds(5455, dt), 5455.0 / 60.0);
        assert_eq!(ticks_to_seconds(60, dt), 1.0);
        assert_eq!(ticks_to_seconds(0, dt), 0.0);
        // A step that is not 1 over a whole number keeps the plain product.
        assert_eq!(ticks_to_seconds(4, 0.3), 4.0 * 0.3f32 as f64);
    }

    #[test]
    fn both_tasks_use_the_same_targets() {
        let a = TaskDef::builtin("ray-casting-7").unwrap();
        let b = TaskDef::builtin("manual-7").unwrap();
        assert_eq!(a.targets, b.targets);
        assert_eq!(a.mode, Mode::RayCasting);
        assert_eq!(b.mode, Mode::Manual);
    }
}

/// The scale of the study during a task laid out in a room (`crate::room_layout`), else 1: new
/// trees are planted or spawned at it and the box's handles are picked at the handle radius times
/// it, so that the study stands in the room as a scale model (its spacing, its tolerance, its
/// trees and their handles scaled alike).
pub fn layout_scale(task: Option<&TaskState>) -> f32 {
    task.and_then(|t| t.layout.as_ref()).map_or(1.0, |l| l.scale)
}

/// Converts a tick count to seconds exactly: `ticks / rate`, where `rate` is the whole number of
/// ticks per second that the step `dt` (seconds) stands for (60 for a step of 1/60 s stored as
/// an `f32`). Steps that are not 1 over a whole number fall back to `ticks × dt`.
pub fn ticks_to_seconds(ticks: u64, dt: f32) -> f64 {
    let rate = 1.0 / dt as f64;
    if rate.is_finite() && rate >= 1.0 && (rate - rate.round()).abs() < 1e-3 {
        ticks as f64 / rate.round()
    } else {
        ticks as f64 * dt as f64
    }
}

/// One placed tree in a task report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TreeReport {
    /// Index of the target it satisfied.
    pub target: usize,
    /// The model's catalogue name.
    pub model: String,
    /// Seconds from the task start until the target was first satisfied.
    pub time_s: f64,
    /// The tick at which the target was first satisfied.
    pub tick: u64,
    /// Where the tree stood, metres.
    pub position: [f32; 3],
}

/// A target that the scene's ground has no plane for at its height, moved onto the plane below
/// (`crate::task_layout`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MovedTarget {
    /// Its index in the task file's targets, from 0.
    pub target: usize,
    /// Where the task file puts it, metres.
    pub from: [f32; 3],
    /// Where it lies on the scene's ground, metres.
    pub to: [f32; 3],
}

/// A task's outcome, as `grove replay --json` and `grove study` report it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TaskReport {
    /// The task id.
    pub id: String,
    /// The mode name ("ray-casting" or "manual").
    pub mode: String,
    /// Whether every target was satisfied.
    pub completed: bool,
    /// The tick of the StartTask event.
    pub start_tick: u64,
    /// The tick the task time ends at (see [`TaskState::end_tick`]): the last target or the
    /// participant's EndTask, whichever comes first; else the end of the replay.
    pub end_tick: u64,
    /// Seconds from the start to the end of the task (see [`TaskState::end_tick`]).
    pub time_s: f64,
    /// Total errors.
    pub errors: u32,
    /// Errors by kind.
    pub error_kinds: TaskErrors,
    /// Satisfied targets, in target order.
    pub trees: Vec<TreeReport>,
    /// Number of distinct models among the satisfied targets.
    pub model_types: usize,
    /// How often the menu was opened.
    pub menu_opens: u32,
    /// Distance travelled by the ray's hit point, metres.
    pub ray_path_m: f32,
    /// Seconds spent aiming.
    pub aiming_s: f64,
    /// Seconds with the menu open.
    pub menu_s: f64,
    /// Seconds spent manipulating trees.
    pub manipulating_s: f64,
    /// The targets the scene's ground moved (a room without the study scene's terrace): the
    /// layout the trial used, when it is not the task file's; empty when none moved. Always
    /// written: a study shard's partial result (postcard) is not self-describing.
    #[serde(default)]
    pub moved_targets: Vec<MovedTarget>,
    /// Where a room layout put the targets (`layout: room`, `crate::room_layout`); null for the
    /// task file's layout. Always written, as `moved_targets`.
    #[serde(default)]
    pub layout: Option<crate::room_layout::RoomPlacement>,
}

impl TaskReport {
    /// The result as one line, as `grove replay` and the desktop window print it.
    pub fn result_line(&self) -> String {
        format!(
            "task {} ({}): {}, {:.2} s, {} trees, {} errors",
            self.id,
            self.mode,
            if self.completed { "completed" } else { "not completed" },
            self.time_s,
            self.trees.len(),
            self.errors
        )
    }

    /// Builds the report from a task state, the step and the tick the replay reached.
    pub fn new(task: &TaskState, dt: f32, now_tick: u64, catalogue: &Catalogue) -> TaskReport {
        let secs = |ticks: u64| ticks_to_seconds(ticks, dt);
        let end = task.end_tick().unwrap_or(now_tick);
        let trees: Vec<TreeReport> = task
            .satisfied
            .iter()
            .enumerate()
            .filter_map(|(i, h)| {
                h.map(|h| TreeReport {
                    target: i,
                    model: catalogue.get(h.model).map_or_else(|| format!("model-{}", h.model.0), |m| m.name.clone()),
                    time_s: secs(h.tick - task.started_tick),
                    tick: h.tick,
                    position: h.position.to_array(),
                })
            })
            .collect();
        let mut models: Vec<&str> = trees.iter().map(|t| t.model.as_str()).collect();
        models.sort_unstable();
        models.dedup();
        TaskReport {
            id: task.def.id.clone(),
            mode: task.def.mode.name().to_string(),
            completed: task.is_complete(),
            start_tick: task.started_tick,
            end_tick: end,
            time_s: secs(end.saturating_sub(task.started_tick)),
            errors: task.errors.total(),
            error_kinds: task.errors,
            model_types: models.len(),
            trees,
            menu_opens: task.menu_opens,
            ray_path_m: task.ray_path_length,
            aiming_s: secs(task.aiming_ticks),
            menu_s: secs(task.menu_ticks),
            manipulating_s: secs(task.manipulating_ticks),
            moved_targets: Vec::new(),
            layout: task.layout.clone(),
        }
    }
}
