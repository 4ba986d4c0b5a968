//! [`Sim`]: a world, its resources and the fixed-step driver.

use glam::Vec3;
use hecs::World;
use rand::RngExt;

use crate::catalogue::{Catalogue, ModelId};
use crate::components::*;
use crate::hash::{WorldHash, world_hash};
use crate::input::{InputEvent, InvalidEvent};
use crate::limits::InvalidScene;
use crate::resources::Resources;
use crate::scene::{Scene, TimeError, parse_utc_ms};
use crate::systems::sun::SunError;
use crate::water::Water;

pub use crate::components::{TreeComponents, tree_components};

/// Why a simulation could not be built from a scene, or an input event was refused.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The scene's model banks could not be opened.
    #[error("{0}")]
    Banks(String),
    /// The scene is invalid.
    #[error("{0}")]
    Scene(#[from] InvalidScene),
    /// The sun's time does not parse.
    #[error("{0}")]
    Time(#[from] TimeError),
    /// The sun's position could not be computed.
    #[error("{0}")]
    Sun(#[from] SunError),
    /// A part of the scene (`tree 3`, `scatter 0`, `aerial`) names a model the catalogue lacks,
    /// or could not be built.
    #[error("{part}: {message}")]
    Part {
        /// The part, as the scene's messages name it.
        part: String,
        /// What is wrong.
        message: String,
    },
    /// An input event with invalid numbers or names.
    #[error("{0}")]
    Event(#[from] InvalidEvent),
}

/// A running simulation: the hecs world and its resources.
pub struct Sim {
    /// The entities: read outside the crate through the getters of [`crate::view`], changed by the schedule,
    /// input events, the scene and [`Sim::set_up`].
    pub(crate) world: World,
    /// Everything that belongs to no entity (read outside the crate through [`crate::view`]).
    pub(crate) res: Resources,
    /// The registered techniques, whose systems the schedule runs ([`crate::technique`]).
    pub techniques: crate::technique::Techniques,
}

impl Sim {
    /// Builds the world a scene describes, with the embedded model catalogue and the models of
    /// the scene's own banks ([`Scene::banks`]), if it names any.
    pub fn from_scene(scene: &Scene, seed: u64) -> Result<Sim, SimError> {
        if scene.banks.is_empty() {
            return Sim::from_scene_with(scene, seed, Catalogue::builtin());
        }
        let banks = crate::bank::Banks::open(&scene.bank_dirs()).map_err(|e| SimError::Banks(e.to_string()))?;
        let (catalogue, _) = banks.session_catalogue().map_err(|e| SimError::Banks(e.to_string()))?;
        Sim::from_scene_with(scene, seed, catalogue)
    }

    /// Builds the world a scene describes, with a given catalogue.
    pub fn from_scene_with(scene: &Scene, seed: u64, catalogue: Catalogue) -> Result<Sim, SimError> {
        scene.validate()?;
        let mut world = World::new();
        let mut res = Resources::new(scene.dt, seed, catalogue);

        for p in &scene.planes {
            let (vertices, triangles) = crate::plane_geometry::plane_geometry_cut(&p.shape, scene.exact_holes);
            let plane = Plane { name: p.name.clone(), vertices, triangles };
            let hash = plane_hash(&plane);
            res.plane_hashes.push((world.spawn((plane,)), hash));
        }

        for w in &scene.water {
            world.spawn((Water::from(w),));
        }

        let utc_ms = parse_utc_ms(&scene.sun.utc)?;
        let mut sun = Sun {
            latitude_deg: scene.sun.latitude_deg,
            longitude_deg: scene.sun.longitude_deg,
            utc_ms,
            time_rate: scene.sun.time_rate,
            elevation_deg: 0.0,
            azimuth_deg: 0.0,
            direction: Vec3::Y,
        };
        crate::systems::sun::update_sun(&mut sun)?;
        world.spawn((sun,));

        let w = &scene.wind;
        let dir = Vec3::new(w.direction.x, 0.0, w.direction.z).normalize_or(Vec3::X);
        world.spawn((Wind {
            direction: dir,
            strength: w.strength,
            density: w.density,
            gust: Gust { average: w.gust_average, strength: w.gust_strength, frequency: w.gust_frequency },
            current: w.gust_average,
            model: w.model,
            response: w.response,
        },));

        let head = Pose::looking_at(scene.camera.position, scene.camera.look_at);
        world.spawn((Head { pose: head, fov_y: scene.camera.fov_y_deg.to_radians() },));
        let hand =
            Pose { position: head.position + head.rotation * Vec3::new(0.25, -0.35, -0.3), rotation: head.rotation };
        world.spawn((Controller { pose: hand, ..Default::default() },));
        world.spawn((HitMarker::default(),));
        world.spawn((AnchorBall::default(),));
        world.spawn((Selection::default(),));

        res.singles = crate::single::Singles::find(&world);
        res.spatial.refresh(&world, &res.catalogue);
        let mut sim = Sim { world, res, techniques: crate::technique::Techniques::builtin() };
        sim.set_techniques(crate::technique::installed());
        for (i, t) in scene.trees.iter().enumerate() {
            let model = sim.res.catalogue.by_name(&t.model).map(|m| m.id).ok_or_else(|| SimError::Part {
                part: format!("tree {i}"),
                message: sim.res.catalogue.unknown_name(&t.model),
            })?;
            sim.spawn_tree(model, t.position, t.yaw_deg.to_radians(), t.scale, t.on_ground);
        }
        let water = crate::water::bodies(&sim.world);
        for (k, sc) in scene.scatter.iter().enumerate() {
            for t in sc.trees().map_err(|e| SimError::Part { part: format!("scatter {k}"), message: e.0 })? {
                // A scattered position with no ground below (a hole), or only a pond's bed,
                // gets no tree.
                if crate::water::dry_ground(&water, sim.res.spatial.ground_below(t.position, 1.0e3)).is_none() {
                    continue;
                }
                let model = sim.res.catalogue.by_name(&t.model).map(|m| m.id).ok_or_else(|| SimError::Part {
                    part: format!("scatter {k}"),
                    message: sim.res.catalogue.unknown_name(&t.model),
                })?;
                sim.spawn_tree(model, t.position, t.yaw_deg.to_radians(), t.scale, t.on_ground);
            }
        }
        // Grass patches last, so that a scene without grass has the same entities as before.
        // Their placement seed is the scene's, never the simulation's RNG.
        let outlines = scene.plane_outlines();
        for (i, g) in scene.grass.iter().enumerate() {
            sim.world.spawn((Grass::new(g, i, scene.seed, &outlines),));
        }
        // The photographed crowns after everything else, so a scene without them builds the
        // same entities as before: a tree of the aerial model at each crown, scaled to its
        // radius, tied to its crown by an `AerialCrown` component.
        if let Some(a) = &scene.aerial {
            let model = sim.res.catalogue.by_name(&a.model).ok_or_else(|| SimError::Part {
                part: "aerial".into(),
                message: sim.res.catalogue.unknown_name(&a.model),
            })?;
            let (id, crown_radius) = (model.id, model.crown_radius.max(0.01));
            for c in a.crown_list.iter().filter(|c| c.radius_m >= a.min_radius_m) {
                let crown = a.crown(c);
                let pos = Vec3::new(crown.photo_centre.x, a.elevation, crown.photo_centre.y);
                let yaw = (c.id as f32 * 137.507_76).rem_euclid(360.0).to_radians();
                let e = sim.spawn_tree(id, pos, yaw, (c.radius_m / crown_radius).clamp(0.3, 3.0), true);
                sim.world
                    .insert_one(e, crown)
                    .map_err(|e| SimError::Part { part: "aerial".into(), message: e.to_string() })?;
            }
        }
        Ok(sim)
    }

    /// Spawns a tree directly (for scenes and scale tests), drawing its wind phase from the RNG.
    /// With `on_ground`, its lowest point is put on the plane below `position`, if there is one.
    pub fn spawn_tree(
        &mut self,
        model: ModelId,
        position: Vec3,
        yaw: f32,
        scale: f32,
        on_ground: bool,
    ) -> hecs::Entity {
        let lowest = self.res.catalogue.get(model).map_or(0.0, |m| m.lowest_point());
        let mut pos = position;
        let mut grounded = false;
        if on_ground {
            if let Some(hit) = self.res.spatial.ground_below(Vec3::new(pos.x, pos.y.max(-1.0e3), pos.z), 1.0e3) {
                pos.y = hit.point.y - lowest * scale;
                grounded = true;
            }
        }
        let wind = self.wind();
        let bundle = tree_components(&mut self.res.rng, wind.as_ref(), model, pos, yaw, scale, grounded);
        self.res.spatial.mark_trees_dirty();
        self.world.spawn(bundle)
    }

    /// Scatters `n` extra trees uniformly over the planes' bounding rectangle, cycling through
    /// the catalogue's models, each grounded where there is a plane below it.
    pub fn scatter_trees(&mut self, n: usize) {
        let (mut min, mut max) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for p in self.world.query::<&Plane>().iter() {
            for v in &p.vertices {
                min = min.min(*v);
                max = max.max(*v);
            }
        }
        let models = self.res.catalogue.len().max(1);
        for i in 0..n {
            let x = min.x + (max.x - min.x) * self.res.rng.random::<f32>();
            let z = min.z + (max.z - min.z) * self.res.rng.random::<f32>();
            let yaw = self.res.rng.random::<f32>() * std::f32::consts::TAU;
            self.spawn_tree(ModelId((i % models) as u8), Vec3::new(x, max.y, z), yaw, 1.0, true);
        }
        self.res.spatial.refresh(&self.world, &self.res.catalogue);
    }

    /// Queues an input event for the next tick. Invalid numbers are rejected.
    pub fn push_input(&mut self, event: InputEvent) -> Result<(), InvalidEvent> {
        event.validate()?;
        self.res.input.push(event);
        Ok(())
    }

    /// Applies this tick's input events and runs one fixed step: the one way every driver (the
    /// live session, the replay viewer, scripts, the recorder) advances the world. Stops at the
    /// first invalid event, before stepping.
    pub fn step_with<I: IntoIterator<Item = InputEvent>>(&mut self, events: I) -> Result<(), InvalidEvent> {
        for event in events {
            self.push_input(event)?;
        }
        self.step();
        Ok(())
    }

    /// Runs one fixed step of the schedule.
    pub fn step(&mut self) {
        crate::schedule::step(&mut self.world, &mut self.res, &self.techniques);
    }

    /// Registers these techniques on this simulation (a plug-in's tests do this; the app
    /// installs its list once, [`crate::technique::install`]). The built-in technique of the
    /// current mode becomes the active one.
    pub fn set_techniques(&mut self, techniques: crate::technique::Techniques) {
        self.res.techniques = techniques.known();
        self.res.technique = crate::technique::Techniques::of_mode(self.res.mode);
        self.techniques = techniques;
    }

    /// The entities, read-only, inside the crate. Readers outside it read the typed getters of
    /// [`crate::view`]; changes go through input events ([`Sim::step_with`]) or the scene before
    /// [`Sim::from_scene`].
    pub(crate) fn world(&self) -> &World {
        &self.world
    }

    /// The resources, read-only, inside the crate (see [`Sim::world`]).
    pub(crate) fn res(&self) -> &Resources {
        &self.res
    }

    /// Runs `n` steps.
    pub fn run(&mut self, n: u64) {
        for _ in 0..n {
            self.step();
        }
    }

    /// The checkpoint hash of the current state.
    pub fn hash(&self) -> WorldHash {
        world_hash(&self.world, &self.res)
    }

    /// A copy of the wind component, if the world has one.
    pub fn wind(&self) -> Option<Wind> {
        self.world.query::<&Wind>().iter().next().copied()
    }

    /// A copy of the hit marker (default if the world has none).
    pub fn hit_marker(&self) -> HitMarker {
        self.world.query::<&HitMarker>().iter().next().copied().unwrap_or_default()
    }

    /// A copy of the anchor ball (default if the world has none).
    pub fn anchor_ball(&self) -> AnchorBall {
        self.world.query::<&AnchorBall>().iter().next().copied().unwrap_or_default()
    }

    /// A copy of the selection (default if the world has none).
    pub fn selection(&self) -> Selection {
        self.world.query::<&Selection>().iter().next().copied().unwrap_or_default()
    }

    /// The state of a tree by entity id bits; `None` if there is no such tree.
    pub fn tree(&self, id: u64) -> Option<TreeState> {
        let e = hecs::Entity::from_bits(id)?;
        let mut q = self.world.query_one::<(&Tree, &Transform, &Scale, &Grounded)>(e);
        q.get().ok().map(|(tree, transform, scale, grounded)| TreeState {
            tree: *tree,
            transform: *transform,
            scale: *scale,
            grounded: *grounded,
        })
    }

    /// The head (the camera): the world's `Head`, or [`Sim::fallback_head`] when it has
    /// none. Every reader of the camera goes through here, so there is one fallback.
    pub fn head(&self) -> Head {
        self.world.query::<&Head>().iter().next().copied().unwrap_or_else(Sim::fallback_head)
    }

    /// The camera of a world without a `Head`: 1.7 m up, 6 m south of the origin, looking at it,
    /// with a 60° vertical field of view.
    pub fn fallback_head() -> Head {
        Head { pose: Pose::looking_at(Vec3::new(0.0, 1.7, 6.0), Vec3::ZERO), fov_y: 60f32.to_radians() }
    }

    /// A copy of the sun component, if the world has one.
    pub fn sun(&self) -> Option<Sun> {
        self.world.query::<&Sun>().iter().next().copied()
    }

    /// The id bits of every tree, in ascending order.
    pub fn tree_ids(&self) -> Vec<u64> {
        let mut ids: Vec<u64> =
            self.world.query::<(hecs::Entity, &Tree)>().iter().map(|(e, _)| e.to_bits().get()).collect();
        ids.sort_unstable();
        ids
    }

    /// Counts of entities by role, for summaries.
    pub fn counts(&self) -> EntityCounts {
        EntityCounts {
            trees: self.world.query::<&Tree>().iter().count(),
            planes: self.world.query::<&Plane>().iter().count(),
            suns: self.world.query::<&Sun>().iter().count(),
            winds: self.world.query::<&Wind>().iter().count(),
            controllers: self.world.query::<&Controller>().iter().count(),
            heads: self.world.query::<&Head>().iter().count(),
            total: self.world.len() as usize,
        }
    }
}

/// The state of one tree as [`Sim::tree`] reads it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TreeState {
    /// Its model.
    pub tree: Tree,
    /// Its base position (metres) and yaw (radians).
    pub transform: Transform,
    /// Its uniform scale.
    pub scale: Scale,
    /// Whether it stands on a plane.
    pub grounded: Grounded,
}

/// Numbers of entities by role.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct EntityCounts {
    /// Trees.
    pub trees: usize,
    /// Ground planes.
    pub planes: usize,
    /// Suns.
    pub suns: usize,
    /// Winds.
    pub winds: usize,
    /// Controllers.
    pub controllers: usize,
    /// Heads (cameras).
    pub heads: usize,
    /// All entities, including markers and the selection.
    pub total: usize,
}
