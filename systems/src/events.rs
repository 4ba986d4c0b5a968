//! The interaction event log: what the systems did, tick by tick.
//!
//! Systems append to [`EventLog`]; the task system, study reports and the replay viewer read it.
//! The log is part of the simulation state and is covered by the world hash.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::catalogue::ModelId;
use crate::mode::Mode;

/// What happened.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Happening {
    /// A tree was planted (ray-casting mode) or spawned from the menu (manual mode).
    Planted {
        /// The tree, by entity id bits.
        tree: u64,
        /// Its model.
        model: ModelId,
        /// Where its origin was placed, metres.
        position: Vec3,
    },
    /// A tree was removed.
    Removed {
        /// The tree, by entity id bits.
        tree: u64,
        /// Its model.
        model: ModelId,
    },
    /// A tree was selected; its bounding box is shown.
    Selected {
        /// The tree, by entity id bits.
        tree: u64,
    },
    /// The selection was cleared.
    Deselected,
    /// A tree was scaled with a corner handle.
    Scaled {
        /// The tree, by entity id bits.
        tree: u64,
        /// The new uniform scale.
        scale: f32,
    },
    /// A tree was rotated with an edge handle or the touchpad.
    Rotated {
        /// The tree, by entity id bits.
        tree: u64,
        /// The new yaw, radians.
        yaw: f32,
    },
    /// A tree finished a move (a drag released or a touchpad move ended).
    Moved {
        /// The tree, by entity id bits.
        tree: u64,
        /// Its new origin, metres.
        position: Vec3,
    },
    /// While dragging, the anchor ball turned white: releasing now would snap.
    SnapArmed {
        /// The tree, by entity id bits.
        tree: u64,
    },
    /// While dragging, the anchor ball turned green again.
    SnapDisarmed {
        /// The tree, by entity id bits.
        tree: u64,
    },
    /// A released tree snapped onto the plane below.
    Snapped {
        /// The tree, by entity id bits.
        tree: u64,
        /// Its new origin, metres.
        position: Vec3,
    },
    /// A drag was released while the anchor ball was green (or hidden): no snap.
    ReleasedGreen {
        /// The tree, by entity id bits.
        tree: u64,
    },
    /// The interaction mode changed.
    ModeChanged {
        /// The new mode.
        mode: Mode,
    },
    /// The model menu was opened.
    MenuOpened,
    /// A model was chosen.
    ModelChosen {
        /// The chosen model.
        model: ModelId,
    },
    /// A task started.
    TaskStarted {
        /// The task id.
        task: String,
    },
    /// A task target was satisfied for the first time.
    TargetSatisfied {
        /// Index of the target in the task file.
        target: usize,
        /// The tree that satisfied it, by entity id bits.
        tree: u64,
    },
    /// Every target of the task is satisfied.
    TaskCompleted,
    /// The user ended the task.
    TaskEnded,
    /// Trigger on water in ray-casting mode: water is not ground, so nothing was planted.
    PlantingRefused {
        /// The water body, by entity id bits.
        water: u64,
        /// The point on the surface the ray hit, metres.
        position: Vec3,
    },
    /// The active technique changed to or from a plug-in technique (a change between the two
    /// built-in ones is a `ModeChanged` only, as it always was).
    TechniqueChanged {
        /// The new technique's name.
        technique: String,
    },
}

impl Happening {
    /// Every kind name [`Happening::kind`] returns, in declaration order.
    pub const KINDS: &'static [&'static str] = &[
        "planted",
        "removed",
        "selected",
        "deselected",
        "scaled",
        "rotated",
        "moved",
        "snap_armed",
        "snap_disarmed",
        "snapped",
        "released_green",
        "mode_changed",
        "menu_opened",
        "model_chosen",
        "task_started",
        "target_satisfied",
        "task_completed",
        "task_ended",
        "planting_refused",
        "technique_changed",
    ];

    /// A short, stable name for the kind of event.
    pub fn kind(&self) -> &'static str {
        match self {
            Happening::Planted { .. } => "planted",
            Happening::Removed { .. } => "removed",
            Happening::Selected { .. } => "selected",
            Happening::Deselected => "deselected",
            Happening::Scaled { .. } => "scaled",
            Happening::Rotated { .. } => "rotated",
            Happening::Moved { .. } => "moved",
            Happening::SnapArmed { .. } => "snap_armed",
            Happening::SnapDisarmed { .. } => "snap_disarmed",
            Happening::Snapped { .. } => "snapped",
            Happening::ReleasedGreen { .. } => "released_green",
            Happening::ModeChanged { .. } => "mode_changed",
            Happening::MenuOpened => "menu_opened",
            Happening::ModelChosen { .. } => "model_chosen",
            Happening::TaskStarted { .. } => "task_started",
            Happening::TargetSatisfied { .. } => "target_satisfied",
            Happening::TaskCompleted => "task_completed",
            Happening::TaskEnded => "task_ended",
            Happening::PlantingRefused { .. } => "planting_refused",
            Happening::TechniqueChanged { .. } => "technique_changed",
        }
    }
}

/// One log entry: a happening and the tick it happened in.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogEntry {
    /// The tick during which it happened.
    pub tick: u64,
    /// What happened.
    pub what: Happening,
}

/// The postcard bytes of an [`EventLog`]'s entries, kept for the world hash: the log only grows,
/// so each entry is serialized once rather than at every checkpoint. A cache in the resources,
/// not hashed itself; a log shorter than what it holds (another log) starts it again.
#[derive(Debug, Default)]
pub struct LogBytes(std::sync::Mutex<(usize, Vec<u8>)>);

impl LogBytes {
    /// Appends to `out` the postcard bytes of every entry of `log`, in order (without the
    /// entries' count).
    pub fn extend(&self, log: &EventLog, out: &mut Vec<u8>) {
        let mut cached = self.0.lock().unwrap_or_else(|e| e.into_inner());
        let (done, bytes) = &mut *cached;
        if *done > log.entries.len() {
            *done = 0;
            bytes.clear();
        }
        for e in &log.entries[*done..] {
            // Serializing plain data into a Vec cannot fail.
            *bytes = postcard::to_extend(e, std::mem::take(bytes)).unwrap_or_default();
        }
        *done = log.entries.len();
        out.extend_from_slice(bytes);
    }
}

/// The append-only interaction event log.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct EventLog {
    /// Entries in the order they happened.
    pub entries: Vec<LogEntry>,
}

impl EventLog {
    /// Appends a happening at `tick`.
    pub fn push(&mut self, tick: u64, what: Happening) {
        self.entries.push(LogEntry { tick, what });
    }

    /// Entries logged at `tick` or later.
    pub fn since(&self, tick: u64) -> impl Iterator<Item = &LogEntry> {
        let start = self.entries.partition_point(|e| e.tick < tick);
        self.entries[start..].iter()
    }

    /// Number of entries of one kind.
    pub fn count(&self, kind: &str) -> usize {
        self.entries.iter().filter(|e| e.what.kind() == kind).count()
    }
}
