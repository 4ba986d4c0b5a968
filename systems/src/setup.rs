//! [`SetUp`]: the typed changes a test, a benchmark or a renderer's fixture makes to a
//! [`Sim`] outside the schedule.
//!
//! Outside grove-systems the world is read through [`Sim::world`] and [`Sim::res`] and changed
//! only by input events ([`Sim::step_with`]) or by the [`crate::scene::Scene`] it is built from.
//! What neither can express — a camera placed for a still, the sun fixed at an angle, a tree
//! removed to isolate another, the overlay's state posed for a golden image, a config knob a
//! test turns — goes through [`Sim::set_up`]: set-up before the first step, or a render-only
//! change between frames. None of it is recorded, so a session that uses it is not a replay.

use hecs::Entity;

use crate::components::{AnchorBall, Controller, Head, HitMarker, Pose, Selection, Sun, Transform, Tree, Wind};
use crate::resources::Config;
use crate::sim::Sim;
use crate::task::TaskState;

/// Why a set-up change failed.
#[derive(Debug, thiserror::Error)]
pub enum SetUpError {
    /// The entity is not in the world.
    #[error("no such entity: {0:?}")]
    NoEntity(Entity),
    /// The entity has no component of the kind to change.
    #[error("entity {0:?} has no {1} component")]
    NoComponent(Entity, &'static str),
    /// A time of day that does not parse.
    #[error("sun time: {0}")]
    Utc(crate::scene::TimeError),
    /// The sun's position could not be computed.
    #[error("sun position: {0}")]
    Sun(crate::systems::sun::SunError),
}

/// Typed set-up changes to a simulation: see the module documentation.
pub struct SetUp<'a> {
    sim: &'a mut Sim,
}

impl Sim {
    /// Set-up changes outside the schedule (before the first step, or render-only): see
    /// [`crate::setup`]. A live change is an input event instead.
    pub fn set_up(&mut self) -> SetUp<'_> {
        SetUp { sim: self }
    }
}

impl SetUp<'_> {
    /// Replaces the head (the camera): its pose and vertical field of view.
    pub fn camera(&mut self, head: Head) -> &mut Self {
        for h in self.sim.world.query_mut::<&mut Head>() {
            *h = head;
        }
        self
    }

    /// Moves the head (the camera), keeping its field of view.
    pub fn camera_pose(&mut self, pose: Pose) -> &mut Self {
        for h in self.sim.world.query_mut::<&mut Head>() {
            h.pose = pose;
        }
        self
    }

    /// Fixes the sun at these angles (degrees), its direction to match; with a time rate of 0
    /// the sun system leaves them.
    pub fn sun_angles(&mut self, elevation_deg: f64, azimuth_deg: f64) -> &mut Self {
        for s in self.sim.world.query_mut::<&mut Sun>() {
            s.elevation_deg = elevation_deg;
            s.azimuth_deg = azimuth_deg;
            s.direction = crate::systems::sun::direction_from_angles(azimuth_deg, elevation_deg);
        }
        self
    }

    /// Sets the sun's clock to an ISO 8601 UTC time and recomputes its position.
    pub fn sun_utc(&mut self, utc: &str) -> Result<&mut Self, SetUpError> {
        let ms = crate::scene::parse_utc_ms(utc).map_err(SetUpError::Utc)?;
        for sun in self.sim.world.query_mut::<&mut Sun>() {
            sun.utc_ms = ms;
            crate::systems::sun::update_sun(sun).map_err(SetUpError::Sun)?;
        }
        Ok(self)
    }

    /// Replaces the wind (read it with [`Sim::wind`], change what the fixture needs).
    pub fn wind(&mut self, wind: Wind) -> &mut Self {
        for w in self.sim.world.query_mut::<&mut Wind>() {
            *w = wind;
        }
        self
    }

    /// Sets the controller's pose directly, without the tick an
    /// [`crate::input::InputEvent::ControllerPose`] takes.
    pub fn controller_pose(&mut self, pose: Pose) -> &mut Self {
        for c in self.sim.world.query_mut::<&mut Controller>() {
            c.pose = pose;
        }
        self
    }

    /// Replaces the hit marker (the overlay's state, for a still).
    pub fn hit_marker(&mut self, marker: HitMarker) -> &mut Self {
        for h in self.sim.world.query_mut::<&mut HitMarker>() {
            *h = marker;
        }
        self
    }

    /// Replaces the anchor ball (the overlay's state, for a still).
    pub fn anchor_ball(&mut self, ball: AnchorBall) -> &mut Self {
        for a in self.sim.world.query_mut::<&mut AnchorBall>() {
            *a = ball;
        }
        self
    }

    /// Replaces the selection (the overlay's state, for a still).
    pub fn selection(&mut self, selection: Selection) -> &mut Self {
        for s in self.sim.world.query_mut::<&mut Selection>() {
            *s = selection;
        }
        self
    }

    /// Sets the running study task (or none).
    pub fn task(&mut self, task: Option<TaskState>) -> &mut Self {
        self.sim.res.task = task;
        self
    }

    /// Replaces the configuration.
    pub fn config(&mut self, config: Config) -> &mut Self {
        self.sim.res.config = config;
        self
    }

    /// Replaces an entity's transform (a tree moved or turned in place).
    pub fn transform(&mut self, entity: Entity, transform: Transform) -> Result<&mut Self, SetUpError> {
        let mut t = self.sim.world.get::<&mut Transform>(entity).map_err(|e| match e {
            hecs::ComponentError::NoSuchEntity => SetUpError::NoEntity(entity),
            hecs::ComponentError::MissingComponent(_) => SetUpError::NoComponent(entity, "Transform"),
        })?;
        *t = transform;
        drop(t);
        self.sim.res.spatial.mark_trees_dirty();
        Ok(self)
    }

    /// Removes an entity (a tree, a plane). Removing a tree marks the spatial index's trees
    /// stale; the next step, or [`SetUp::refresh_spatial`], rebuilds them.
    pub fn despawn(&mut self, entity: Entity) -> Result<&mut Self, SetUpError> {
        let tree = self.sim.world.get::<&Tree>(entity).is_ok();
        self.sim.world.despawn(entity).map_err(|_| SetUpError::NoEntity(entity))?;
        if tree {
            self.sim.res.spatial.mark_trees_dirty();
        }
        Ok(self)
    }

    /// Rebuilds the spatial index now, as a step would before its first ray.
    pub fn refresh_spatial(&mut self) -> &mut Self {
        let sim = &mut *self.sim;
        sim.res.spatial.refresh(&sim.world, &sim.res.catalogue);
        self
    }

    /// Runs the wind system, the sun system or both, alone, and advances the tick as the
    /// schedule would: the wind benchmark's timing loop (`grove bench wind`).
    pub fn run_wind_and_sun(&mut self, wind: bool, sun: bool) -> &mut Self {
        let sim = &mut *self.sim;
        if wind {
            crate::systems::wind::run(&mut sim.world, &mut sim.res);
        }
        if sun {
            crate::systems::sun::run(&mut sim.world, &mut sim.res);
        }
        sim.res.tick += 1;
        self
    }
}
