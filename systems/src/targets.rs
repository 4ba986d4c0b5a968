//! Name-based targeting for scripts and scenario files: a tree by how the script came to know
//! it ([`TreeRef`]), a point to aim at ([`Aim`]), and the names and marks a script keeps
//! ([`Names`]).
//!
//! A script never needs an entity id: "the tree planted last", "the second tree planted",
//! "the tree I called `oak`", "the tree nearest (2, 0, −2)", "the running task's third target".
//! [`crate::script::Script`] resolves these against its simulation; scenario files
//! (`docs/scenarios.md`) write the same values in RON.

use std::collections::BTreeMap;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::components::{Transform, Tree};
use crate::events::Happening;
use crate::sim::Sim;

/// A tree, named by how the script knows it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum TreeRef {
    /// The tree planted (or spawned from the menu) most recently since the script started.
    Last,
    /// The n-th tree planted since the script started, counting from 1.
    Planted(usize),
    /// A tree given a name with [`crate::script::Script::name_tree`] (a `Name` step).
    Named(String),
    /// The tree whose base stands nearest this point, measured along the ground (X and Z).
    Nearest(f32, f32, f32),
}

/// A point to aim the controller ray at.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Aim {
    /// A world point, metres.
    Point(f32, f32, f32),
    /// The running task's n-th target (counting from 1), on the ground at its position.
    Target(usize),
    /// A tree's base as it stands now plus `offset`; without `offset`, the middle of the
    /// tree's pick shape ([`tree_middle`]), where a ray from anywhere around meets the tree.
    Tree {
        /// The tree.
        tree: TreeRef,
        /// Added to the tree's base position, metres.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        offset: Option<Vec3>,
    },
    /// A point remembered with [`crate::script::Script::mark`] (a `Mark` step), plus `offset`;
    /// with `y`, at that height instead.
    Mark {
        /// The mark's name.
        name: String,
        /// Added to the marked point, metres.
        #[serde(default)]
        offset: Vec3,
        /// A height (world Y, metres) that replaces the marked point's.
        #[serde(default)]
        y: Option<f32>,
    },
}

/// A value as a scenario file writes it, on one line: `Logged(kind: "planted", count: 2)`.
pub fn ron_line<T: Serialize + std::fmt::Debug>(value: &T) -> String {
    let config = ron::ser::PrettyConfig::new()
        .new_line("")
        .indentor("")
        .compact_structs(true)
        .compact_arrays(true)
        .compact_maps(true);
    // Optional values as the files write them: `offset: (0.0, 2.0, 0.0)`, not `Some((…))`.
    let options = ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    options.to_string_pretty(value, config).unwrap_or_else(|_| format!("{value:?}"))
}

impl TreeRef {
    /// The reference as a scenario file writes it, e.g. `Named("oak")`.
    pub fn text(&self) -> String {
        ron_line(self)
    }
}

impl Aim {
    /// The aim as a scenario file writes it, e.g. `Point(1.0, 0.0, -3.0)`.
    pub fn text(&self) -> String {
        ron_line(self)
    }
}

/// Why a tree or a point could not be found. `Display` is one line.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TargetError {
    /// `Last` before anything was planted.
    #[error("no tree has been planted yet")]
    NonePlanted,
    /// `Planted(n)` past the trees planted.
    #[error("tree Planted({n}) does not exist: {planted} trees have been planted so far (counting from 1)")]
    NotPlanted {
        /// The number asked for.
        n: usize,
        /// Trees planted so far.
        planted: usize,
    },
    /// An unknown tree name.
    #[error("no tree is named \"{0}\" (name one with a Name step first)")]
    NoName(String),
    /// An unknown mark.
    #[error("no point is marked \"{0}\" (mark one with a Mark step first)")]
    NoMark(String),
    /// The tree is gone.
    #[error("the tree {0} has been removed")]
    Removed(String),
    /// `Nearest` in a world without trees.
    #[error("there is no tree to be nearest to")]
    NoTrees,
    /// `Target(n)` with no task running.
    #[error("no task is running, so there is no Target({0})")]
    NoTask(usize),
    /// `Target(n)` past the task's targets.
    #[error("task {task} has {count} targets, so there is no Target({n}) (counting from 1)")]
    NoTarget {
        /// The task id.
        task: String,
        /// Its number of targets.
        count: usize,
        /// The number asked for.
        n: usize,
    },
}

/// The names and marks a script keeps, and where its own planting began in the event log.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Names {
    /// The length of the event log when the script started: trees planted after it count for
    /// `Last` and `Planted(n)`.
    pub log_start: usize,
    trees: BTreeMap<String, u64>,
    marks: BTreeMap<String, Vec3>,
}

impl Names {
    /// Names for a script that starts with this simulation.
    pub fn new(sim: &Sim) -> Names {
        Names { log_start: sim.res.log.entries.len(), ..Default::default() }
    }

    /// Gives a tree a name (replacing an earlier tree of that name).
    pub fn name_tree(&mut self, name: &str, tree: u64) {
        self.trees.insert(name.to_string(), tree);
    }

    /// Remembers a point under a name.
    pub fn mark(&mut self, name: &str, point: Vec3) {
        self.marks.insert(name.to_string(), point);
    }

    /// The name a tree was given last, if any.
    pub fn name_of(&self, tree: u64) -> Option<&str> {
        self.trees.iter().rev().find(|(_, id)| **id == tree).map(|(n, _)| n.as_str())
    }

    /// The trees planted since the script started, by id bits, in order.
    pub fn planted(&self, sim: &Sim) -> Vec<u64> {
        let entries = sim.res.log.entries.get(self.log_start..).unwrap_or_default();
        entries
            .iter()
            .filter_map(|e| match e.what {
                Happening::Planted { tree, .. } => Some(tree),
                _ => None,
            })
            .collect()
    }

    /// The tree a reference names, by id bits; it must still exist.
    pub fn tree(&self, sim: &Sim, r: &TreeRef) -> Result<u64, TargetError> {
        let id = match r {
            TreeRef::Last => *self.planted(sim).last().ok_or(TargetError::NonePlanted)?,
            TreeRef::Planted(n) => {
                let planted = self.planted(sim);
                *n.checked_sub(1)
                    .and_then(|i| planted.get(i))
                    .ok_or(TargetError::NotPlanted { n: *n, planted: planted.len() })?
            }
            TreeRef::Named(name) => *self.trees.get(name).ok_or_else(|| TargetError::NoName(name.clone()))?,
            TreeRef::Nearest(x, y, z) => nearest(sim, Vec3::new(*x, *y, *z)).ok_or(TargetError::NoTrees)?,
        };
        if sim.tree(id).is_none() {
            return Err(TargetError::Removed(r.text()));
        }
        Ok(id)
    }

    /// The world point an aim names.
    pub fn point(&self, sim: &Sim, aim: &Aim) -> Result<Vec3, TargetError> {
        match aim {
            Aim::Point(x, y, z) => Ok(Vec3::new(*x, *y, *z)),
            Aim::Target(n) => {
                let task = sim.res.task.as_ref().ok_or(TargetError::NoTask(*n))?;
                let targets = &task.def.targets;
                let t = n.checked_sub(1).and_then(|i| targets.get(i)).ok_or_else(|| TargetError::NoTarget {
                    task: task.def.id.clone(),
                    count: targets.len(),
                    n: *n,
                })?;
                Ok(t.position)
            }
            Aim::Tree { tree, offset } => {
                let id = self.tree(sim, tree)?;
                // `tree` checked that it exists.
                let base = sim.tree(id).map_or(Vec3::ZERO, |t| t.transform.translation);
                Ok(match offset {
                    Some(o) => base + *o,
                    None => tree_middle(sim, id).unwrap_or(base),
                })
            }
            Aim::Mark { name, offset, y } => {
                let mut p = *self.marks.get(name).ok_or_else(|| TargetError::NoMark(name.clone()))? + *offset;
                if let Some(y) = y {
                    p.y = *y;
                }
                Ok(p)
            }
        }
    }
}

/// The middle of a tree's pick shape as it stands now: on its axis, halfway between the
/// shape's lowest and highest point (or, should the band there be empty, in the middle of the
/// nearest band that is not); for a model without a pick shape, the centre of its box. A ray
/// aimed there meets the tree from any side, whatever its height: a 1.3 m shrub at 0.65 m, a
/// 9 m broadleaf at 4.5 m. `None` if there is no such tree.
pub fn tree_middle(sim: &Sim, tree: u64) -> Option<Vec3> {
    let t = sim.tree(tree)?;
    let model = sim.res.catalogue.get(t.tree.model)?;
    let (base, scale) = (t.transform.translation, t.scale.0);
    let local = match &model.pick {
        Some(p) => {
            let (h, middle) = (p.band_height(), (p.bottom + p.top) * 0.5);
            let centre = |i: usize| p.bottom + h * (i as f32 + 0.5);
            let y = match p.band(middle) {
                Some(i) if p.radii[i] > 0.0 => middle,
                // The nearest band that is not empty (the lower on a tie).
                _ => (0..crate::catalogue::PICK_BANDS)
                    .filter(|&i| p.radii[i] > 0.0)
                    .map(centre)
                    .min_by(|a, b| (a - middle).abs().total_cmp(&(b - middle).abs()))
                    .unwrap_or(middle),
            };
            Vec3::new(0.0, y, 0.0)
        }
        None => glam::Quat::from_rotation_y(t.transform.yaw) * ((model.bounds_min + model.bounds_max) * 0.5),
    };
    Some(base + local * scale)
}

/// The tree whose base is nearest `p` along the ground; ties go to the lower id.
pub fn nearest(sim: &Sim, p: Vec3) -> Option<u64> {
    let mut best: Option<(f32, u64)> = None;
    for (e, _, t) in sim.world.query::<(hecs::Entity, &Tree, &Transform)>().iter() {
        let d = ground_distance(t.translation, p);
        let id = e.to_bits().get();
        if best.is_none_or(|(bd, bid)| d < bd || (d == bd && id < bid)) {
            best = Some((d, id));
        }
    }
    best.map(|(_, id)| id)
}

/// The distance between two points along the ground (X and Z only), metres.
pub fn ground_distance(a: Vec3, b: Vec3) -> f32 {
    libm::hypotf(a.x - b.x, a.z - b.z)
}
