//! Task system: the study's task clock, target checks and measures.
//!
//! Reads: `Resources::task`, `Resources::log` (new entries), `Resources::menu`,
//! `Resources::interaction`, `Resources::catalogue`, `Resources::spatial` (its tree changes),
//! `Resources::task_search`, `Tree`, `Transform`, `Grounded`, `HitMarker`, `Controller`,
//! `Selection`.
//! Writes: `Resources::task` (satisfied targets, completion, errors, measures),
//! `Resources::log` (target_satisfied, task_completed), `Resources::task_search`.
//!
//! The clock starts at the StartTask event and stops when every target is satisfied, or at the
//! EndTask event if that comes first (the participant pressed "Finish task"). A target
//! is satisfied when a tree of the required model, grounded if the task requires it, stands
//! within the tolerance (horizontal distance); each tree counts for one target only.

use glam::{Vec2, Vec3};
use hecs::{Entity, World};

use crate::components::{Controller, Grounded, HitMarker, Selection, Transform, Tree};
use crate::events::Happening;
use crate::resources::Resources;
use crate::single;
use crate::task::{TargetHit, TaskState};

fn near_any_target(task: &TaskState, p: Vec3) -> bool {
    task.def.targets.iter().any(|t| Vec2::new(t.position.x - p.x, t.position.z - p.z).length() <= task.def.tolerance)
}

/// Marks the targets that a tree now satisfies, in target order, each tree counting for one
/// target; returns `(target, tree id)` of each newly satisfied one. The candidates are every
/// tree, or only the tree `only` when no other can be new (see [`run`]).
fn satisfy_targets(
    world: &mut World,
    task: &mut TaskState,
    catalogue: &crate::catalogue::Catalogue,
    dragged: Option<u64>,
    only: Option<u64>,
    tick: u64,
) -> Vec<(usize, u64)> {
    let require_grounded = task.def.require_grounded;
    let keep = |e: Entity, g: &Grounded| Some(e.to_bits().get()) != dragged && (g.0 || !require_grounded);
    let trees: Vec<(u64, crate::catalogue::ModelId, Vec3)> = match only {
        Some(id) => crate::interact::entity(id)
            .and_then(|e| {
                let (tree, t, g) = world.query_one_mut::<(&Tree, &Transform, &Grounded)>(e).ok()?;
                keep(e, g).then_some((id, tree.model, t.translation))
            })
            .into_iter()
            .collect(),
        None => world
            .query_mut::<(Entity, &Tree, &Transform, &Grounded)>()
            .into_iter()
            .filter(|&(e, _, _, g)| keep(e, g))
            .map(|(e, tree, t, _)| (e.to_bits().get(), tree.model, t.translation))
            .collect(),
    };
    if trees.is_empty() {
        return Vec::new();
    }
    let mut used: Vec<u64> = task.satisfied.iter().flatten().map(|h| h.tree).collect();
    let mut newly = Vec::new();
    for (i, target) in task.def.targets.iter().enumerate() {
        if task.satisfied[i].is_some() {
            continue;
        }
        let Some(want) = target.model_id(catalogue) else { continue };
        let mut best: Option<(f32, u64, Vec3)> = None;
        for &(id, model, p) in &trees {
            if model != want || used.contains(&id) {
                continue;
            }
            let d = Vec2::new(p.x - target.position.x, p.z - target.position.z).length();
            if d <= task.def.tolerance && best.is_none_or(|b| d < b.0 || (d == b.0 && id < b.1)) {
                best = Some((d, id, p));
            }
        }
        if let Some((_, id, position)) = best {
            task.satisfied[i] = Some(TargetHit { tick, tree: id, model: want, position });
            used.push(id);
            newly.push((i, id));
        }
    }
    newly
}

/// Runs the task system.
pub fn run(world: &mut World, res: &mut Resources) {
    let Some(task) = res.task.as_mut() else { return };
    // Once the clock has stopped (every target satisfied, or the participant ended the task),
    // nothing more is measured: what happens afterwards is not part of the task.
    if task.is_over() {
        return;
    }
    let tick = res.tick;

    // Errors and menu opens, from the log entries since the last tick.
    if task.log_cursor == usize::MAX {
        // The StartTask entry was logged this tick; count only what follows it.
        task.log_cursor =
            res.log.entries.iter().rposition(|e| matches!(e.what, Happening::TaskStarted { .. })).map_or(0, |i| i + 1);
    }
    for entry in &res.log.entries[task.log_cursor..] {
        match &entry.what {
            Happening::Removed { .. } => task.errors.removals += 1,
            Happening::ReleasedGreen { .. } => task.errors.released_green += 1,
            Happening::MenuOpened => task.menu_opens += 1,
            Happening::Planted { position, .. } | Happening::Snapped { position, .. } => {
                // In manual mode a new tree appears in front of the user and is moved into
                // place, so only a snap counts as a placement there.
                let placement =
                    matches!(entry.what, Happening::Snapped { .. }) || task.def.mode == crate::mode::Mode::RayCasting;
                if placement && !near_any_target(task, *position) {
                    task.errors.off_target += 1;
                }
            }
            _ => {}
        }
    }
    task.log_cursor = res.log.entries.len();

    // Where the time goes.
    let touchpad_active = single::get::<Controller>(world, &res.singles)
        .is_some_and(|c| c.touchpad.abs().max_element() > res.config.touchpad_dead_zone)
        && single::get::<Selection>(world, &res.singles).is_some_and(|s| s.tree.is_some());
    if res.menu.open {
        task.menu_ticks += 1;
    } else if res.interaction.drag.is_some() || res.interaction.handle_drag.is_some() || touchpad_active {
        task.manipulating_ticks += 1;
    } else {
        task.aiming_ticks += 1;
    }
    if let Some(h) = single::get::<HitMarker>(world, &res.singles) {
        if h.visible {
            if let Some(last) = task.last_hit {
                task.ray_path_length += last.distance(h.position);
            }
            task.last_hit = Some(h.position);
        } else {
            task.last_hit = None;
        }
    }

    // Targets. A search finds nothing new while no tree was added, removed or moved, the same
    // tree is dragged and no touchpad gesture moves one (the only moves that mark the trees
    // changed when they end rather than as they happen): a target it left unsatisfied has at
    // most the candidates it had then. So the search runs over every tree only when one of
    // those changed; during a touchpad gesture with nothing else changed, the gesture's tree is
    // the only one that can have moved, so it is the only candidate.
    let dragged = res.interaction.drag.map(|d| d.tree);
    let search = (res.spatial.tree_changes(), dragged, task.started_tick);
    let newly = if res.task_search != Some(search) {
        res.task_search = Some(search);
        satisfy_targets(world, task, &res.catalogue, dragged, None, tick)
    } else if let Some(g) = res.interaction.touchpad {
        satisfy_targets(world, task, &res.catalogue, dragged, Some(g.tree), tick)
    } else {
        Vec::new()
    };
    for (target, tree) in newly {
        res.log.push(tick, Happening::TargetSatisfied { target, tree });
    }
    if task.satisfied.iter().all(Option::is_some) {
        task.completed_tick = Some(tick);
        res.log.push(tick, Happening::TaskCompleted);
    }
}
