//! What a scenario's trace shows of each step (`grove test --trace`): the world's interaction
//! state before and after the step ([`Snapshot`]: the ray, what it met, the selection) and what
//! the step did in words ([`did`]: planted, selected, removed, snapped, …, or nothing).
//!
//! Reads: the controller, the hit marker, the selection, the trees, the catalogue, the task and
//! the interaction log, through the simulation's getters and the script's names. Writes
//! nothing: a traced run runs the very ticks of an untraced one.

use glam::Vec3;

use crate::events::Happening;
use crate::sim::Sim;
use crate::targets::Names;

use super::aims;

/// The selected tree's box, seen from above.
#[derive(Clone, Debug, PartialEq)]
pub struct SelectedBox {
    /// Centre, metres.
    pub center: Vec3,
    /// Half extents along the box's own axes, metres.
    pub half_extents: Vec3,
    /// Rotation about +Y, radians.
    pub yaw: f32,
    /// The tree in words, e.g. `birch-mesh (planted 1st)`.
    pub words: String,
}

/// The interaction state at one tick.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// The tick.
    pub tick: u64,
    /// Where the controller's ray starts, metres.
    pub ray_origin: Vec3,
    /// Its unit direction.
    pub ray_dir: Vec3,
    /// The point the ray meets, if it meets anything.
    pub hit: Option<Vec3>,
    /// What it meets, in words, with the distance (`nothing within 100 m`).
    pub met: String,
    /// The selected tree, if any.
    pub selected: Option<SelectedBox>,
    /// Every tree's base (X, Z), metres.
    pub trees: Vec<(f32, f32)>,
    /// The running task's targets (X, Z), metres, in the task file's order (target n is the
    /// n-th, counting from 1).
    pub targets: Vec<(f32, f32)>,
}

impl Snapshot {
    /// The state of `sim` now.
    pub fn take(sim: &Sim, names: &Names) -> Snapshot {
        let c = sim.world.query::<&crate::components::Controller>().iter().next().copied().unwrap_or_default();
        let m = sim.hit_marker();
        let sel = sim.selection();
        let selected = sel.tree.filter(|id| sim.tree(*id).is_some()).map(|id| SelectedBox {
            center: sel.center,
            half_extents: sel.half_extents,
            yaw: sel.yaw,
            words: aims::tree_words(sim, names, id),
        });
        let trees = sim
            .tree_ids()
            .into_iter()
            .filter_map(|id| sim.tree(id))
            .map(|t| (t.transform.translation.x, t.transform.translation.z))
            .collect();
        let targets = sim
            .res
            .task
            .as_ref()
            .map_or_else(Vec::new, |t| t.def.targets.iter().map(|d| (d.position.x, d.position.z)).collect());
        Snapshot {
            tick: sim.res.tick,
            ray_origin: c.ray_origin(),
            ray_dir: c.ray_dir(),
            hit: m.visible.then_some(m.position),
            met: aims::met(sim, names, &m),
            selected,
            trees,
            targets,
        }
    }

    /// Where the ray is drawn to: the point it meets, or `length` metres along it.
    pub fn ray_end(&self, length: f32) -> Vec3 {
        self.hit.unwrap_or(self.ray_origin + self.ray_dir * length)
    }
}

fn xz(p: Vec3) -> String {
    format!("({:.1}, {:.1})", p.x, p.z)
}

/// What the log entries from `from` on say happened, in words (targets counted from 1); `[]`
/// when nothing did.
pub fn did(sim: &Sim, names: &Names, from: usize) -> Vec<String> {
    let tree = |id: u64| aims::tree_words(sim, names, id);
    let model =
        |m: crate::catalogue::ModelId| sim.res.catalogue.get(m).map_or_else(|| "?".to_string(), |i| i.name.clone());
    let mut out: Vec<String> = Vec::new();
    for e in sim.res.log.entries.get(from..).unwrap_or_default() {
        let words = match &e.what {
            Happening::Planted { tree: t, position, .. } => format!("planted {} at {}", tree(*t), xz(*position)),
            Happening::Removed { tree: t, .. } => format!("removed {}", tree(*t)),
            Happening::Selected { tree: t } => format!("selected {}", tree(*t)),
            Happening::Deselected => "deselected".into(),
            Happening::Scaled { tree: t, scale } => format!("scaled {} to {scale:.2}", tree(*t)),
            Happening::Rotated { tree: t, yaw } => format!("turned {} to {:.0}°", tree(*t), yaw.to_degrees()),
            Happening::Moved { tree: t, position } => format!("moved {} to {}", tree(*t), xz(*position)),
            Happening::SnapArmed { .. } => "anchor ball white".into(),
            Happening::SnapDisarmed { .. } => "anchor ball green".into(),
            Happening::Snapped { tree: t, position } => {
                format!("snapped {} to the ground at {}", tree(*t), xz(*position))
            }
            Happening::ReleasedGreen { tree: t } => format!("released {} green (not snapped)", tree(*t)),
            Happening::ModeChanged { mode } => format!("mode {}", mode.name()),
            Happening::MenuOpened => "menu opened".into(),
            Happening::ModelChosen { model: m } => format!("chose {}", model(*m)),
            Happening::TaskStarted { task } => format!("task {task} started"),
            Happening::TargetSatisfied { target, .. } => format!("target {} satisfied", target + 1),
            Happening::TaskCompleted => "task completed".into(),
            Happening::TaskEnded => "task ended".into(),
            Happening::PlantingRefused { position, .. } => format!("planting on water at {} refused", xz(*position)),
            Happening::TechniqueChanged { technique } => format!("technique {technique}"),
        };
        // Runs of the same words (the ball flickering while a tree is carried) once.
        if out.last() != Some(&words) {
            out.push(words);
        }
    }
    out
}

/// The simulation's tick (for readers outside this crate, which read the world only through
/// getters).
pub fn tick(sim: &Sim) -> u64 {
    sim.res.tick
}
