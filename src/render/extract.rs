//! Extract: the first stage of a frame and the one file in `src/render` that reads simulation
//! components. [`FrameData::extract`] copies what the frame draws out of a [`Sim`] into plain
//! data (the camera, the sun, the wind, the trees, the planes, the interaction visuals); every
//! later stage works on that copy and never sees the world.

use glam::{Quat, Vec2, Vec3};
use grove_systems::components::{AnchorBall, Controller, Grass, HitMarker, HitTarget, Plane, Scale, Selection, Transform, Tree, WindState};
use grove_systems::aerial::AerialCrown;
use grove_systems::water::Water;
use grove_systems::wind_model::{Gust, Wind, WindModel, WindParams, WindResponse};
use grove_systems::Sim;

use grove_systems::grass::{patch_triangles, place_blades, GrassKind};

use super::grass::data::GrassPatch;
use super::overlay::geometry::{OverlayAnchor, OverlayController, OverlayHit, OverlayScene, OverlaySelection, OverlayTarget};
use super::view::Camera;

/// Identifies the planes' geometry: per plane, sorted by entity, its entity bits and its vertex
/// and triangle counts. The ground mesh is rebuilt only when this changes.
pub(crate) type GroundKey = Vec<(u64, usize, usize)>;

/// Identifies the grass: every plane's hash (`grove_systems::hash::plane_hash`: its name,
/// vertices and triangles) and every patch (entity bits and component), sorted by entity. The
/// grass buffers are rebuilt only when this changes.
pub(crate) type GrassKey = (Vec<(u64, u64)>, Vec<(u64, Grass)>);

/// One plane's mesh: world positions (metres) and counter-clockwise triangles.
pub(crate) struct PlaneMesh {
    /// Vertex positions, world metres.
    pub vertices: Vec<Vec3>,
    /// Triangles as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

/// One tree as the frame draws it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TreeDraw {
    /// The catalogue model's index.
    pub model: usize,
    /// Base position, world metres.
    pub origin: Vec3,
    /// Rotation about +Y, radians.
    pub yaw: f32,
    /// Uniform scale.
    pub scale: f32,
    /// The trunk's lean, metres per metre of height (world X and Z); zero without a wind state.
    pub bend: Vec2,
    /// The wind's gain at the tree; zero without a wind state (the tree stands still).
    pub gain: f32,
    /// The tree's wind phase, radians.
    pub phase: f32,
}

/// One water body as the frame draws it (a copy of its `Water` component).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct WaterDraw {
    /// The outline, (X, Z) metres.
    pub polygon: Vec<Vec2>,
    /// The surface height, metres.
    pub height: f32,
    /// The deepest point below the surface, metres.
    pub depth: f32,
    /// The deep colour, linear RGB.
    pub colour: [f32; 3],
    /// Ripple strength, 0 = still.
    pub ripples: f32,
    /// Ripple drift, metres per second.
    pub ripple_speed: f32,
}

/// A photographed crown's tree as the canopy draws it (from its `AerialCrown` component).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CrownDraw {
    /// The tree's foot: its current position, world metres.
    pub foot: Vec3,
    /// World (X, Z) of the crown's centre in the photograph, metres.
    pub photo_centre: Vec2,
    /// The crown's radius, metres.
    pub radius_m: f32,
    /// The crown's base over the foot, metres.
    pub base_m: f32,
    /// The crown's top over the foot, metres.
    pub top_m: f32,
}

/// Everything a frame draws, copied from the world.
pub(crate) struct FrameData {
    /// The head's camera.
    pub camera: Camera,
    /// Unit vector towards the sun.
    pub sun_dir: Vec3,
    /// The sun's true elevation, degrees.
    pub sun_elevation_deg: f64,
    /// Simulated time, seconds.
    pub time: f64,
    /// The per-vertex wind parameters of this frame.
    pub wind: WindParams,
    /// The global wind model (a pipeline choice).
    pub wind_model: WindModel,
    /// Every tree but the photographed crowns' (those are in `crown_trees`).
    pub trees: Vec<TreeDraw>,
    /// The photographed crowns, sorted by entity.
    pub crowns: Vec<CrownDraw>,
    /// The trees of `crowns`, in the same order: drawn as models only without a canopy.
    pub crown_trees: Vec<TreeDraw>,
    /// The planes' key.
    pub ground_key: GroundKey,
    /// The planes' meshes, sorted by entity; only when `ground_key` differs from the one the
    /// caller already has.
    pub planes: Option<Vec<PlaneMesh>>,
    /// The bounds of every plane vertex, metres.
    pub plane_bounds: Option<(Vec3, Vec3)>,
    /// The interaction visuals.
    pub overlay: OverlayScene,
    /// The water bodies, sorted by entity.
    pub water: Vec<WaterDraw>,
    /// The grass patches' key (see [`FrameData::extract_grass`]).
    pub grass_key: GrassKey,
    /// The grass patches with their triangles and blades; only when `grass_key` differs from
    /// the one the caller already has.
    pub grass: Option<Vec<GrassPatch>>,
}

impl FrameData {
    /// Copies what a frame draws from `sim`. `have_ground` is the key of the ground mesh the
    /// renderer already has; the planes are copied only when the world's differ.
    pub fn extract(sim: &Sim, have_ground: &GroundKey) -> FrameData {
        let head = sim.head();
        let camera = Camera { position: head.pose.position, rotation: head.pose.rotation, fov_y: head.fov_y };
        // Without a sun, light comes from high in the south-east.
        let (sun_dir, sun_elevation_deg) = sim
            .sun()
            .map_or((Vec3::new(0.3, 0.8, 0.2).normalize(), 45.0), |s| (s.direction.normalize_or(Vec3::Y), s.elevation_deg));
        let time = sim.res().time();
        let wind = sim.wind().unwrap_or_else(calm);

        let mut trees = Vec::new();
        let mut crowns = Vec::new();
        for (e, tree, t, s, w, crown) in sim.world().query::<(hecs::Entity, &Tree, &Transform, Option<&Scale>, Option<&WindState>, Option<&AerialCrown>)>().iter() {
            // A tree without a wind state stands still: no bend and zero gain.
            let (bend, gain, phase) = w.map_or((Vec2::ZERO, 0.0, 0.0), |w| (w.bend, w.gain, w.phase));
            let draw = TreeDraw {
                model: usize::from(tree.model.0),
                origin: t.translation,
                yaw: t.yaw,
                scale: s.map_or(1.0, |s| s.0),
                bend,
                gain,
                phase,
            };
            match crown {
                Some(c) => {
                    let foot = t.translation;
                    let cd = CrownDraw { foot, photo_centre: c.photo_centre, radius_m: c.radius_m, base_m: c.base_m, top_m: c.top_m };
                    crowns.push((e.to_bits().get(), cd, draw));
                }
                None => trees.push(draw),
            }
        }
        crowns.sort_by_key(|c| c.0);
        let crown_trees = crowns.iter().map(|c| c.2.clone()).collect();
        let crowns = crowns.into_iter().map(|c| c.1).collect();

        let mut ground_key: GroundKey = sim
            .world()
            .query::<(hecs::Entity, &Plane)>()
            .iter()
            .map(|(e, p)| (e.to_bits().get(), p.vertices.len(), p.triangles.len()))
            .collect();
        ground_key.sort_unstable();
        let planes = (&ground_key != have_ground).then(|| {
            let mut planes: Vec<(u64, PlaneMesh)> = sim
                .world()
                .query::<(hecs::Entity, &Plane)>()
                .iter()
                .map(|(e, p)| (e.to_bits().get(), PlaneMesh { vertices: p.vertices.clone(), triangles: p.triangles.clone() }))
                .collect();
            planes.sort_by_key(|(e, _)| *e);
            planes.into_iter().map(|(_, p)| p).collect()
        });
        let mut plane_bounds: Option<(Vec3, Vec3)> = None;
        for p in sim.world().query::<&Plane>().iter() {
            for v in &p.vertices {
                plane_bounds = Some(plane_bounds.map_or((*v, *v), |(a, b)| (a.min(*v), b.max(*v))));
            }
        }

        FrameData {
            camera,
            sun_dir,
            sun_elevation_deg,
            time,
            wind: WindParams::from_wind(&wind, time),
            wind_model: wind.model,
            trees,
            crowns,
            crown_trees,
            ground_key,
            planes,
            plane_bounds,
            overlay: overlay_scene(sim),
            water: water_bodies(sim),
            grass_key: GrassKey::default(),
            grass: None,
        }
    }

    /// Copies the grass patches from `sim` when the world's key differs from `have` (the key
    /// of the grass buffers the renderer already has): each patch's ground triangles and its
    /// blades, placed by the simulation's pure placement function.
    pub fn extract_grass(&mut self, sim: &Sim, have: &GrassKey) {
        let mut patches: Vec<(u64, Grass)> = sim.world().query::<(hecs::Entity, &Grass)>().iter().map(|(e, g)| (e.to_bits().get(), g.clone())).collect();
        patches.sort_by_key(|(e, _)| *e);
        // Without patches the planes do not matter (and are not hashed every frame).
        let mut planes: Vec<(u64, u64)> = if patches.is_empty() {
            Vec::new()
        } else {
            sim.world().query::<(hecs::Entity, &Plane)>().iter().map(|(e, p)| (e.to_bits().get(), grove_systems::hash::plane_hash(p))).collect()
        };
        planes.sort_unstable();
        self.grass_key = (planes, patches);
        if &self.grass_key == have {
            return;
        }
        let mut query = sim.world().query::<(hecs::Entity, &Plane)>();
        let mut planes: Vec<(u64, &str, &[Vec3], &[[u32; 3]])> =
            query.iter().map(|(e, p)| (e.to_bits().get(), p.name.as_str(), p.vertices.as_slice(), p.triangles.as_slice())).collect();
        planes.sort_by_key(|p| p.0);
        let views: Vec<(&str, &[Vec3], &[[u32; 3]])> = planes.iter().map(|p| (p.1, p.2, p.3)).collect();
        let out = self.grass_key.1.iter().map(|(_, g)| {
            let shells = g.def.kind == GrassKind::Shells;
            GrassPatch {
                shells,
                triangles: if shells { patch_triangles(g, &views) } else { Vec::new() },
                blades: place_blades(g, &views),
                root: g.def.base_color,
                tip: g.def.tip_color,
                height: g.def.height,
                density: g.def.density,
                layers: g.def.shells,
            }
        });
        self.grass = Some(out.collect());
    }
}

/// The world's water bodies, sorted by entity.
fn water_bodies(sim: &Sim) -> Vec<WaterDraw> {
    let mut w: Vec<(u64, WaterDraw)> = sim
        .world()
        .query::<(hecs::Entity, &Water)>()
        .iter()
        .map(|(e, w)| {
            let draw = WaterDraw { polygon: w.polygon.clone(), height: w.height, depth: w.depth, colour: w.colour, ripples: w.ripples, ripple_speed: w.ripple_speed };
            (e.to_bits().get(), draw)
        })
        .collect();
    w.sort_by_key(|(e, _)| *e);
    w.into_iter().map(|(_, d)| d).collect()
}

/// The wind of a world without a `Wind` entity: strength and gust 0, the default response, so
/// only the trees' own `WindState::bend` moves them.
fn calm() -> Wind {
    Wind {
        direction: Vec3::X,
        strength: 0.0,
        density: 0.0,
        gust: Gust { average: 0.0, strength: 0.0, frequency: 0.0 },
        current: 0.0,
        model: WindModel::Hierarchical,
        response: WindResponse::default(),
    }
}

/// The interaction visuals' inputs: the controller, the hit marker, the anchor ball, the
/// selection and the running task's targets.
pub fn overlay_scene(sim: &Sim) -> OverlayScene {
    let world = sim.world();
    let hit = world.query::<&HitMarker>().iter().next().map(|h| OverlayHit {
        visible: h.visible,
        distance: h.distance,
        position: h.position,
        normal: h.normal,
        on_water: matches!(h.target, HitTarget::Water(_)),
    });
    let controllers = world
        .query::<&Controller>()
        .iter()
        .map(|c| OverlayController {
            origin: c.ray_origin(),
            dir: c.ray_dir(),
            rotation: c.pose.rotation,
            trigger: c.buttons.trigger,
            bumper: c.buttons.bumper,
            touchpad_pressed: c.buttons.touchpad,
            touchpad: c.touchpad,
        })
        .collect();
    let anchors = world
        .query::<&AnchorBall>()
        .iter()
        .map(|a| OverlayAnchor { visible: a.visible, armed: a.armed, position: a.position, distance: a.distance })
        .collect();
    let selections = world
        .query::<&Selection>()
        .iter()
        .filter(|s| s.tree.is_some())
        .map(|s| OverlaySelection { center: s.center, rotation: Quat::from_rotation_y(s.yaw), half_extents: s.half_extents })
        .collect();
    let (targets, tolerance) = match &sim.res().task {
        Some(task) => (
            task.def
                .targets
                .iter()
                .enumerate()
                .map(|(i, t)| OverlayTarget { position: t.position, done: task.satisfied.get(i).is_some_and(|s| s.is_some()) })
                .collect(),
            task.def.tolerance,
        ),
        None => (Vec::new(), 0.0),
    };
    OverlayScene {
        controllers,
        hit,
        anchors,
        selections,
        targets,
        target_tolerance: tolerance,
        max_ray_length: sim.res().config.max_ray_length,
        handle_radius: sim.res().config.handle_radius,
        eye: sim.head().pose.position,
        ghosts: Vec::new(),
    }
}
