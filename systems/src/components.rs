//! Components of the simulation's entities.
//!
//! Units and axes, stated once for the whole crate: lengths are in metres, angles in radians
//! (unless a field name ends in `_deg`), time in seconds. The world is right-handed with +Y up,
//! −Z north and +X east. Azimuths are measured clockwise from north.
//!
//! Every component that takes part in the simulation implements [`crate::hash::StableHash`] and is
//! listed in [`crate::hash::HASHED`], so that the world hash covers it.

use glam::{Quat, Vec2, Vec3};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::catalogue::ModelId;

/// The wind component and its gust function live with the pure wind maths
/// ([`crate::wind_model`]), which the rest of the crate builds on.
pub use crate::wind_model::{Gust, Wind};

/// A grass patch's component lives with the grass section of scenes ([`crate::grass`]).
pub use crate::grass::Grass;

/// A rigid pose: a position and an orientation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position in world space, metres.
    pub position: Vec3,
    /// Orientation; the local −Z axis is "forward".
    pub rotation: Quat,
}

impl Default for Pose {
    fn default() -> Self {
        Pose { position: Vec3::ZERO, rotation: Quat::IDENTITY }
    }
}

impl Pose {
    /// The forward direction (local −Z) in world space, unit length.
    pub fn forward(&self) -> Vec3 {
        (self.rotation * Vec3::NEG_Z).normalize_or(Vec3::NEG_Z)
    }

    /// A pose at `position` looking towards `target`, with +Y up.
    pub fn looking_at(position: Vec3, target: Vec3) -> Pose {
        let dir = (target - position).normalize_or(Vec3::NEG_Z);
        Pose { position, rotation: rotation_towards(dir) }
    }

    /// Whether every number in the pose is finite.
    pub fn is_finite(&self) -> bool {
        self.position.is_finite() && self.rotation.is_finite()
    }
}

/// The rotation that turns local −Z into `dir` while keeping local +X horizontal (no roll).
pub fn rotation_towards(dir: Vec3) -> Quat {
    let dir = dir.normalize_or(Vec3::NEG_Z);
    let yaw = libm::atan2f(-dir.x, -dir.z);
    let pitch = libm::asinf(dir.y.clamp(-1.0, 1.0));
    Quat::from_rotation_y(yaw) * Quat::from_rotation_x(pitch)
}

/// Where a tree stands: the position of its base (its model origin) and its heading.
///
/// Trees stay upright, so their orientation is a single yaw about +Y, counter-clockwise seen
/// from above.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Transform {
    /// Position of the model origin (the base of the trunk), metres.
    pub translation: Vec3,
    /// Rotation about +Y, radians, counter-clockwise seen from above.
    pub yaw: f32,
}

impl Transform {
    /// The rotation as a quaternion.
    pub fn rotation(&self) -> Quat {
        Quat::from_rotation_y(self.yaw)
    }
}

/// Uniform scale of a tree relative to its catalogue model (1.0 = as modelled).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Scale(pub f32);

/// Marks an entity as a tree and names its model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Tree {
    /// Which of the catalogue's models this tree shows.
    pub model: ModelId,
}

/// Whether a tree stands on a plane: its lowest point touches the plane below it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Grounded(pub bool);

/// The per-tree state of the wind animation, advanced every tick by the wind system.
///
/// The renderer reads `bend` (the trunk's lean), `gain` and `phase` and passes them to the
/// per-vertex wind functions (`src/render/trees/wind.wgsl`, CPU reference in [`crate::wind_model`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WindState {
    /// A random phase in radians, drawn from the seeded RNG when the tree is spawned.
    pub phase: f32,
    /// Gain of the wind at this tree's position, 0.5..1.5 ([`crate::wind_model::position_gain`]),
    /// so that trees do not sway in lockstep.
    pub gain: f32,
    /// The current lean of the trunk: horizontal displacement per metre of height, world X and Z.
    pub bend: Vec2,
    /// The horizontal position (X, Z) and the wind density for which `gain` was computed; the
    /// wind system recomputes `gain` when the tree moves or the density changes.
    pub gain_at: Vec3,
}

impl WindState {
    /// A tree's initial wind state at `position` for a wind of spatial `density`.
    pub fn new(phase: f32, position: Vec3, density: f32) -> WindState {
        WindState {
            phase,
            gain: crate::wind_model::position_gain(position, density),
            bend: Vec2::ZERO,
            gain_at: Vec3::new(position.x, position.z, density),
        }
    }
}

/// A reconstructed ground surface: a triangle mesh that may have holes and unevenness.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plane {
    /// A name from the scene, e.g. "ground" or "terrace".
    pub name: String,
    /// Vertex positions in world space, metres.
    pub vertices: Vec<Vec3>,
    /// Triangles as indices into `vertices`, counter-clockwise seen from above.
    pub triangles: Vec<[u32; 3]>,
}

/// The hash of a plane: its name, then its vertices' and triangles' bytes, little-endian.
pub fn plane_hash(p: &Plane) -> u64 {
    let mut h = xxhash_rust::xxh3::Xxh3::new();
    h.update(p.name.as_bytes());
    h.update(&(p.vertices.len() as u64).to_le_bytes());
    if cfg!(target_endian = "little") {
        h.update(bytemuck::cast_slice(&p.vertices));
        h.update(bytemuck::cast_slice(&p.triangles));
    } else {
        for v in &p.vertices {
            for x in v.to_array() {
                h.update(&x.to_le_bytes());
            }
        }
        for t in &p.triangles {
            for i in t {
                h.update(&i.to_le_bytes());
            }
        }
    }
    h.digest()
}

/// The sun: where on Earth and when the scene is, and the resulting direction of sunlight.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sun {
    /// Latitude, degrees north.
    pub latitude_deg: f64,
    /// Longitude, degrees east.
    pub longitude_deg: f64,
    /// The current UTC time, milliseconds since the Unix epoch.
    pub utc_ms: i64,
    /// Simulated seconds of sun time per simulated second (0 = fixed, 60 = a minute per second).
    pub time_rate: f64,
    /// True geometric elevation above the horizon, degrees (no refraction).
    pub elevation_deg: f64,
    /// Azimuth, degrees clockwise from north.
    pub azimuth_deg: f64,
    /// Unit vector in world space pointing from the ground towards the sun.
    pub direction: Vec3,
}

/// The controller buttons, named after the Magic Leap One controller.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Buttons {
    /// The trigger (WebXR "trigger").
    pub trigger: bool,
    /// The bumper (WebXR "squeeze").
    pub bumper: bool,
    /// The touchpad press.
    pub touchpad: bool,
    /// The menu button.
    pub menu: bool,
}

/// The hand controller: a pose that defines a ray, and its buttons.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Controller {
    /// The controller pose; the ray starts at `pose.position` along `pose.forward()`.
    pub pose: Pose,
    /// Which buttons are held.
    pub buttons: Buttons,
    /// The touchpad position, each axis in [−1, 1]; +Y is front (away from the user), +X right.
    pub touchpad: Vec2,
}

impl Controller {
    /// The ray origin, metres.
    pub fn ray_origin(&self) -> Vec3 {
        self.pose.position
    }

    /// The unit ray direction.
    pub fn ray_dir(&self) -> Vec3 {
        self.pose.forward()
    }
}

/// The Scale pad of the controller's entity ([`crate::input::InputEvent::ScaleAxis`]), added by
/// the first such event: a world that never had one hashes as before it existed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ScalePad {
    /// The pad's value in [−1, 1]; 0 at rest.
    pub value: f32,
    /// The gesture in progress: the tree being scaled (its id bits) and its scale when it began.
    pub gesture: Option<(u64, f32)>,
}

/// The user's head, which is also the camera.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Head {
    /// The head pose; the camera looks along `pose.forward()`.
    pub pose: Pose,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

/// What the controller ray hits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum HitTarget {
    /// Nothing within range.
    #[default]
    None,
    /// A ground plane, by entity id bits.
    Plane(u64),
    /// A tree, by entity id bits.
    Tree(u64),
    /// A bounding-box handle of the selected tree.
    Handle(crate::components::Handle),
    /// A water surface, by entity id bits: not ground, nothing is planted there.
    Water(u64),
}

/// A bounding-box handle: corners scale uniformly, vertical edges rotate about +Y.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Handle {
    /// One of the 8 corners, index 0..8 (bit 0: +X, bit 1: +Y, bit 2: +Z).
    Corner(u8),
    /// One of the 4 vertical edges, index 0..4 (bit 0: +X, bit 1: +Z).
    Edge(u8),
}

/// The marker at the nearest hit of the controller ray.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HitMarker {
    /// Whether the ray hits anything.
    pub visible: bool,
    /// The hit point, metres.
    pub position: Vec3,
    /// The surface normal at the hit point.
    pub normal: Vec3,
    /// Distance from the ray origin, metres.
    pub distance: f32,
    /// What was hit.
    pub target: HitTarget,
}

/// The ball that shows where a dragged tree would attach to the ground.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AnchorBall {
    /// Shown only while a tree is being dragged over a plane.
    pub visible: bool,
    /// Where the ball sits on the plane, under the tree, metres.
    pub position: Vec3,
    /// Distance from the tree's lowest point down to the plane, metres (negative if below it).
    pub distance: f32,
    /// White (true) when `distance` is below the snap threshold, green (false) otherwise.
    pub armed: bool,
}

/// The selection and its oriented bounding box.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Selection {
    /// The selected tree, by entity id bits, if any.
    pub tree: Option<u64>,
    /// Centre of the oriented bounding box, metres.
    pub center: Vec3,
    /// Half extents of the box along its own axes, metres.
    pub half_extents: Vec3,
    /// Rotation of the box about +Y, radians.
    pub yaw: f32,
}

/// The components every tree entity carries.
pub type TreeComponents = (Tree, Transform, Scale, Grounded, WindState);

/// The components of a new tree: its model, base position, yaw, scale and grounded flag, and a
/// wind state whose phase is drawn from `rng` (one draw) and whose gain comes from `wind` at
/// `position`. [`Sim::spawn_tree`] and the interaction systems (through a command buffer) both
/// spawn trees with this.
pub fn tree_components(
    rng: &mut ChaCha8Rng,
    wind: Option<&Wind>,
    model: ModelId,
    position: Vec3,
    yaw: f32,
    scale: f32,
    grounded: bool,
) -> TreeComponents {
    let phase = rng.random::<f32>() * std::f32::consts::TAU;
    let density = wind.map_or(0.0, |w| w.density);
    (
        Tree { model },
        Transform { translation: position, yaw },
        Scale(scale),
        Grounded(grounded),
        WindState::new(phase, position, density),
    )
}
