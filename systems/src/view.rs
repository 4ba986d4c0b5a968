//! The typed read view of a [`Sim`]: what every reader outside the simulation (the renderer's
//! extract, the study and its reports, the video, the desktop, the benchmarks, plug-in
//! techniques' tests) reads, as plain values and plain-data view types. The world (hecs) and
//! the layout of [`crate::resources::Resources`] stay private to this crate; a reader that needs
//! something no getter gives gets a new getter here.
//!
//! Every getter only reads: a copy of a small value, a shared reference to a resource, or a
//! visit of the entities of one kind in the world's own order (the order a query of the same
//! components gives, so that what readers build from it is unchanged).

use glam::Vec3;
use hecs::Entity;

use crate::aerial::AerialCrown;
use crate::catalogue::{Catalogue, ModelId};
use crate::components::{Controller, Grounded, Plane, Scale, Transform, Tree, WindState};
use crate::events::EventLog;
use crate::grass::Grass;
use crate::known_techniques::{Known, KnownTechniques};
use crate::mode::Mode;
use crate::resources::{Config, Interaction, MenuState};
use crate::sim::Sim;
use crate::spatial::{RayHit, SpatialIndex};
use crate::task::TaskState;
use crate::water::Water;

/// One tree as [`Sim::for_each_tree`] and [`Sim::tree_view`] read it: its entity's id bits and
/// components.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TreeView {
    /// The entity's id bits (what events and the log name a tree by).
    pub id: u64,
    /// Its catalogue model.
    pub model: ModelId,
    /// Its base position (metres) and yaw (radians).
    pub transform: Transform,
    /// Its uniform scale.
    pub scale: f32,
    /// Whether it stands on a plane.
    pub grounded: bool,
    /// Its wind state, if it sways.
    pub wind: Option<WindState>,
    /// The photographed crown it stands for, if any.
    pub crown: Option<AerialCrown>,
}

type TreeQuery<'a> =
    (Entity, &'a Tree, &'a Transform, &'a Scale, &'a Grounded, Option<&'a WindState>, Option<&'a AerialCrown>);

fn tree_view((e, tree, transform, scale, grounded, wind, crown): TreeQuery<'_>) -> TreeView {
    TreeView {
        id: e.to_bits().get(),
        model: tree.model,
        transform: *transform,
        scale: scale.0,
        grounded: grounded.0,
        wind: wind.copied(),
        crown: crown.copied(),
    }
}

impl Sim {
    /// Ticks completed since the start.
    pub fn tick(&self) -> u64 {
        self.res().tick
    }

    /// The fixed step, seconds.
    pub fn dt(&self) -> f32 {
        self.res().dt
    }

    /// Simulated time at the start of the current tick, seconds.
    pub fn time(&self) -> f64 {
        self.res().time()
    }

    /// The seed the simulation's RNG started from.
    pub fn seed(&self) -> u64 {
        self.res().seed
    }

    /// The tunable parameters in force.
    pub fn config(&self) -> &Config {
        &self.res().config
    }

    /// The model catalogue.
    pub fn catalogue(&self) -> &Catalogue {
        &self.res().catalogue
    }

    /// The interaction mode: the built-in behaviour of the active technique.
    pub fn mode(&self) -> Mode {
        self.res().mode
    }

    /// The registered techniques as the world knows them, built-in ones first.
    pub fn known_techniques(&self) -> &KnownTechniques {
        &self.res().techniques
    }

    /// The index of the active technique in [`Sim::known_techniques`].
    pub fn technique_index(&self) -> usize {
        self.res().technique
    }

    /// The active technique.
    pub fn active_technique(&self) -> &Known {
        self.res().techniques.at(self.res().technique)
    }

    /// The model menu: open or not, and the model Trigger plants.
    pub fn menu(&self) -> MenuState {
        self.res().menu
    }

    /// The ongoing trigger, drag, handle and touchpad interactions.
    pub fn interaction(&self) -> &Interaction {
        &self.res().interaction
    }

    /// Everything the interaction systems did, with ticks.
    pub fn log(&self) -> &EventLog {
        &self.res().log
    }

    /// The task being run, if any.
    pub fn task(&self) -> Option<&TaskState> {
        self.res().task.as_ref()
    }

    /// The spatial index the systems cast rays through (as of the last step).
    pub fn spatial(&self) -> &SpatialIndex {
        &self.res().spatial
    }

    /// The ground (the nearest plane) below `point` lifted by `lift` metres, if there is one.
    pub fn ground_below(&self, point: Vec3, lift: f32) -> Option<RayHit> {
        self.res().spatial.ground_below(point, lift)
    }

    /// A copy of the controller, if the world has one.
    pub fn controller(&self) -> Option<Controller> {
        self.world().query::<&Controller>().iter().next().copied()
    }

    /// One tree by entity id bits, with its wind state and crown; `None` if there is no such
    /// tree.
    pub fn tree_view(&self, id: u64) -> Option<TreeView> {
        let e = Entity::from_bits(id)?;
        let mut q = self.world().query_one::<TreeQuery<'_>>(e);
        q.get().ok().map(tree_view)
    }

    /// Calls `f` with every tree, in the world's order.
    pub fn for_each_tree(&self, mut f: impl FnMut(TreeView)) {
        for row in self.world().query::<TreeQuery<'_>>().iter() {
            f(tree_view(row));
        }
    }

    /// Calls `f` with every ground plane and its entity's id bits, in the world's order.
    pub fn for_each_plane(&self, mut f: impl FnMut(u64, &Plane)) {
        for (e, p) in self.world().query::<(Entity, &Plane)>().iter() {
            f(e.to_bits().get(), p);
        }
    }

    /// Copies of the water bodies with their entities' id bits, sorted by entity.
    pub fn water_bodies(&self) -> Vec<(u64, Water)> {
        crate::water::bodies(self.world()).into_iter().map(|(e, w)| (e.to_bits().get(), w)).collect()
    }

    /// Copies of the grass patches with their entities' id bits, sorted by entity.
    pub fn grass_patches(&self) -> Vec<(u64, Grass)> {
        let mut v: Vec<(u64, Grass)> =
            self.world().query::<(Entity, &Grass)>().iter().map(|(e, g)| (e.to_bits().get(), g.clone())).collect();
        v.sort_by_key(|(e, _)| *e);
        v
    }

    /// Copies of a plug-in technique's own component type `T` with their entities' id bits,
    /// sorted by entity: what the technique's tests read (the built-in components have the
    /// getters above).
    pub fn plug_in_components<T: hecs::Component + Clone>(&self) -> Vec<(u64, T)> {
        let mut v: Vec<(u64, T)> =
            self.world().query::<(Entity, &T)>().iter().map(|(e, c)| (e.to_bits().get(), c.clone())).collect();
        v.sort_by_key(|(e, _)| *e);
        v
    }
}
