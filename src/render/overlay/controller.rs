//! The hand controller's model: a WebXR Input Profiles asset (a `profile.json` and the glb it
//! names; grove ships the Magic Leap One's in `assets/controllers/magicleap-one/`), posed by the
//! recorded buttons and touchpad the way the registry's motion-controllers library does it.
//!
//! Each visual response of the profile's layout names a value node and, for a `transform`
//! response, a min and a max node. Nodes are looked up by those names anywhere in the glb, not
//! under the layout's `rootNodeName` (the Magic Leap One's profile says `magicleap-one-none`,
//! its glb's root is `magic_leap_one_none`). Per response, the component's state (default,
//! touched, pressed) and a value: a button's value (0 or 1), or `(axis + 1) / 2` for an axis;
//! a state the response does not list gives the default (0 for a button, 0.5 for an axis,
//! hidden for a visibility). A `transform` response sets the value node's local transform to
//! the interpolation between the min and the max node's (translation and scale lerp, rotation
//! slerp); a `visibility` response hides the value node and its children.
//!
//! The mesh data stays in node-local space; [`ControllerModel::pose`] emits the posed
//! triangles in world space every frame. It does not know the overlay's vertex type (the
//! overlay's `geometry` calls it), so that the two modules do not import each other.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{Mat3, Mat4, Quat, Vec2, Vec3};
use grove_systems::files::{self, FileError, Kind};
use serde::Deserialize;

/// The model's folder under the assets folder.
pub const MODEL_DIR: &str = "controllers/magicleap-one";
/// The layout drawn: the registry's layout for a controller held in neither hand in particular.
pub const LAYOUT: &str = "none";
/// The smallest linear value of each colour channel: the registry's material is nearly black
/// (0.027), which reads as a hole against a dark scene; lifted, its shading shows.
pub const MIN_CHANNEL: f32 = 0.09;
/// Colour of the touch dot (linear RGBA).
pub const TOUCH_DOT: [f32; 4] = [0.3, 0.8, 1.0, 1.0];
/// Radius of the touch dot, metres.
pub const TOUCH_DOT_RADIUS: f32 = 0.003;
/// How deep, metres, the front face is taken to be when placing the tip on the ray.
const FRONT_DEPTH: f32 = 0.005;

/// Why the controller's model did not load. `Display` is one line.
#[derive(Debug, thiserror::Error)]
pub enum ControllerError {
    /// A file could not be read.
    #[error(transparent)]
    File(#[from] FileError),
    /// The profile is not a WebXR input profile.
    #[error("{path}: not a WebXR input profile: {message}")]
    Profile {
        /// The profile's path (or `profile.json`).
        path: String,
        /// What is wrong.
        message: String,
    },
    /// The glb could not be parsed.
    #[error("{path}: {message}")]
    Gltf {
        /// The glb's path (or its name in the profile).
        path: String,
        /// What is wrong.
        message: String,
    },
    /// A node a visual response names is not in the glb.
    #[error("the controller model has no node named {0:?}")]
    MissingNode(String),
}

#[derive(Deserialize)]
struct Profile {
    layouts: BTreeMap<String, Layout>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct Layout {
    components: BTreeMap<String, ProfileComponent>,
    asset_path: String,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct ProfileComponent {
    #[serde(rename = "type")]
    kind: String,
    #[serde(default)]
    visual_responses: BTreeMap<String, VisualResponse>,
    touch_point_node_name: Option<String>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct VisualResponse {
    component_property: String,
    states: Vec<String>,
    value_node_property: String,
    value_node_name: String,
    min_node_name: Option<String>,
    max_node_name: Option<String>,
}

/// What the controller's buttons and touchpad do this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ControllerInput {
    /// The trigger is held.
    pub trigger: bool,
    /// The bumper (WebXR's squeeze) is held.
    pub squeeze: bool,
    /// The touchpad is pressed.
    pub touchpad_pressed: bool,
    /// The touch point, each axis in [−1, 1]: +X right, +Y front (away from the user); zero
    /// when the touchpad is not touched.
    pub touchpad: Vec2,
}

/// A component grove has input for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Part {
    Trigger,
    Squeeze,
    Touchpad,
}

/// A component's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    Default = 0,
    Touched = 1,
    Pressed = 2,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Property {
    Button,
    XAxis,
    YAxis,
    State,
}

#[derive(Clone, Copy, Debug)]
enum Effect {
    Transform { min: usize, max: usize },
    Visibility,
}

/// One visual response, its nodes resolved.
#[derive(Clone, Debug)]
struct Response {
    part: Part,
    property: Property,
    /// The states it responds in, indexed by [`State`].
    states: [bool; 3],
    node: usize,
    effect: Effect,
}

/// A node's local transform.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Trs {
    t: Vec3,
    r: Quat,
    s: Vec3,
}

impl Trs {
    fn matrix(self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.s, self.r, self.t)
    }

    fn lerp(a: Trs, b: Trs, v: f32) -> Trs {
        Trs { t: a.t.lerp(b.t, v), r: a.r.slerp(b.r, v), s: a.s.lerp(b.s, v) }
    }
}

#[derive(Clone, Debug)]
struct Node {
    name: String,
    local: Trs,
    children: Vec<usize>,
    mesh: Option<usize>,
}

/// A mesh's triangles in its node's space.
#[derive(Clone, Debug, Default)]
struct Mesh {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    /// Triangle list.
    indices: Vec<u32>,
}

/// A loaded controller model.
#[derive(Clone, Debug)]
pub struct ControllerModel {
    nodes: Vec<Node>,
    roots: Vec<usize>,
    meshes: Vec<Mesh>,
    color: [f32; 4],
    responses: Vec<Response>,
    touch_point: Option<usize>,
    /// Added to the model (grip space) so that the centre of its front face sits at the
    /// origin, where the ray starts.
    offset: Vec3,
}

/// Each component's state and its button value and axes in the registry's terms.
fn component_values(input: &ControllerInput, part: Part) -> (State, f32, Vec2) {
    let pressed = |b: bool| {
        if b { (State::Pressed, 1.0) } else { (State::Default, 0.0) }
    };
    match part {
        Part::Trigger => {
            let (s, v) = pressed(input.trigger);
            (s, v, Vec2::ZERO)
        }
        Part::Squeeze => {
            let (s, v) = pressed(input.squeeze);
            (s, v, Vec2::ZERO)
        }
        Part::Touchpad => {
            let state = if input.touchpad_pressed {
                State::Pressed
            } else if input.touchpad != Vec2::ZERO {
                State::Touched
            } else {
                State::Default
            };
            // WebXR's yAxis grows towards the user; grove's touchpad +Y is away from them.
            let mut axes = Vec2::new(input.touchpad.x, -input.touchpad.y);
            if axes.length() > 1.0 {
                axes = axes.normalize();
            }
            (state, if input.touchpad_pressed { 1.0 } else { 0.0 }, axes)
        }
    }
}

impl Response {
    /// The response's value: a transform's interpolation parameter, or 1 (shown) / 0 (hidden).
    fn value(&self, input: &ControllerInput) -> f32 {
        let (state, button, axes) = component_values(input, self.part);
        let active = self.states[state as usize];
        match (self.property, active) {
            (Property::Button, true) => button,
            (Property::XAxis, true) => (axes.x + 1.0) / 2.0,
            (Property::YAxis, true) => (axes.y + 1.0) / 2.0,
            (Property::State, true) => 1.0,
            (Property::Button | Property::State, false) => 0.0,
            (Property::XAxis | Property::YAxis, false) => 0.5,
        }
    }
}

impl ControllerModel {
    /// Loads `profile.json` and the glb its [`LAYOUT`] names from `dir`, through
    /// `grove_systems::files` (the glb must lie inside `dir`).
    pub fn load(dir: &Path) -> Result<ControllerModel, ControllerError> {
        let profile_path = dir.join("profile.json");
        let text = files::read_text(&profile_path, Kind::Index)?;
        let asset = Self::asset_path(&text)
            .map_err(|message| ControllerError::Profile { path: profile_path.display().to_string(), message })?;
        let glb_path: PathBuf = files::within(&dir.join(&asset), dir)?;
        let glb = files::read(&glb_path, Kind::Gltf)?;
        Self::from_bytes(&text, &glb).map_err(|e| match e {
            ControllerError::Profile { message, .. } => {
                ControllerError::Profile { path: profile_path.display().to_string(), message }
            }
            ControllerError::Gltf { message, .. } => {
                ControllerError::Gltf { path: glb_path.display().to_string(), message }
            }
            other => other,
        })
    }

    fn layout(profile: &Profile) -> Result<&Layout, String> {
        profile
            .layouts
            .get(LAYOUT)
            .or_else(|| profile.layouts.values().next())
            .ok_or_else(|| "it has no layouts".to_string())
    }

    fn asset_path(profile_json: &str) -> Result<String, String> {
        let profile: Profile = serde_json::from_str(profile_json).map_err(|e| e.to_string())?;
        Ok(Self::layout(&profile)?.asset_path.clone())
    }

    /// The model from a profile's text and its glb's bytes.
    pub fn from_bytes(profile_json: &str, glb: &[u8]) -> Result<ControllerModel, ControllerError> {
        let profile_err = |message: String| ControllerError::Profile { path: "profile.json".into(), message };
        let profile: Profile = serde_json::from_str(profile_json).map_err(|e| profile_err(e.to_string()))?;
        let layout = Self::layout(&profile).map_err(profile_err)?;
        let gltf_err = |message: String| ControllerError::Gltf { path: layout.asset_path.clone(), message };
        let gltf = gltf::Gltf::from_slice(glb).map_err(|e| gltf_err(e.to_string()))?;
        let blob = gltf.blob.as_deref();
        let doc = &gltf.document;
        let nodes: Vec<Node> = doc
            .nodes()
            .map(|n| {
                let (t, r, s) = n.transform().decomposed();
                Node {
                    name: n.name().unwrap_or_default().to_string(),
                    local: Trs { t: Vec3::from(t), r: Quat::from_array(r).normalize(), s: Vec3::from(s) },
                    children: n.children().map(|c| c.index()).collect(),
                    mesh: n.mesh().map(|m| m.index()),
                }
            })
            .collect();
        let scene =
            doc.default_scene().or_else(|| doc.scenes().next()).ok_or_else(|| gltf_err("it has no scene".into()))?;
        let roots: Vec<usize> = scene.nodes().map(|n| n.index()).collect();
        let mut color = None;
        let mut meshes = Vec::new();
        for mesh in doc.meshes() {
            let mut m = Mesh::default();
            for prim in mesh.primitives() {
                if prim.mode() != gltf::mesh::Mode::Triangles {
                    continue;
                }
                color.get_or_insert(prim.material().pbr_metallic_roughness().base_color_factor());
                let reader = prim.reader(|b| match b.source() {
                    gltf::buffer::Source::Bin => blob,
                    gltf::buffer::Source::Uri(_) => None,
                });
                let Some(positions) = reader.read_positions() else {
                    continue;
                };
                let base = m.positions.len() as u32;
                let positions: Vec<Vec3> = positions.map(Vec3::from).collect();
                let normals: Vec<Vec3> = match reader.read_normals() {
                    Some(n) => n.map(Vec3::from).collect(),
                    None => vec![Vec3::ZERO; positions.len()],
                };
                if normals.len() != positions.len() {
                    return Err(gltf_err(format!(
                        "mesh {}: {} normals for {} positions",
                        mesh.index(),
                        normals.len(),
                        positions.len()
                    )));
                }
                let indices: Vec<u32> = match reader.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..positions.len() as u32).collect(),
                };
                if let Some(bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
                    return Err(gltf_err(format!(
                        "mesh {}: index {bad} past its {} vertices",
                        mesh.index(),
                        positions.len()
                    )));
                }
                m.indices.extend(indices[..indices.len() / 3 * 3].iter().map(|i| i + base));
                m.positions.extend(positions);
                m.normals.extend(normals);
            }
            meshes.push(m);
        }
        let find = |name: &str| {
            nodes.iter().position(|n| n.name == name).ok_or_else(|| ControllerError::MissingNode(name.to_string()))
        };
        let mut responses = Vec::new();
        let mut touch_point = None;
        for component in layout.components.values() {
            let part = match component.kind.as_str() {
                "trigger" => Part::Trigger,
                "squeeze" => Part::Squeeze,
                "touchpad" => Part::Touchpad,
                // Grove records no other control (the menu button has no component here).
                _ => continue,
            };
            if part == Part::Touchpad
                && let Some(name) = &component.touch_point_node_name
            {
                touch_point = Some(find(name)?);
            }
            for r in component.visual_responses.values() {
                let property = match r.component_property.as_str() {
                    "button" => Property::Button,
                    "xAxis" => Property::XAxis,
                    "yAxis" => Property::YAxis,
                    "state" => Property::State,
                    other => {
                        return Err(profile_err(format!("unknown componentProperty {other:?}")));
                    }
                };
                let mut states = [false; 3];
                for s in &r.states {
                    match s.as_str() {
                        "default" => states[State::Default as usize] = true,
                        "touched" => states[State::Touched as usize] = true,
                        "pressed" => states[State::Pressed as usize] = true,
                        other => return Err(profile_err(format!("unknown state {other:?}"))),
                    }
                }
                let effect = match r.value_node_property.as_str() {
                    "transform" => {
                        let name = |n: &Option<String>, what: &str| {
                            n.clone().ok_or_else(|| profile_err(format!("{} has no {what}", r.value_node_name)))
                        };
                        Effect::Transform {
                            min: find(&name(&r.min_node_name, "minNodeName")?)?,
                            max: find(&name(&r.max_node_name, "maxNodeName")?)?,
                        }
                    }
                    "visibility" => Effect::Visibility,
                    other => {
                        return Err(profile_err(format!("unknown valueNodeProperty {other:?}")));
                    }
                };
                responses.push(Response { part, property, states, node: find(&r.value_node_name)?, effect });
            }
        }
        let c = color.unwrap_or([0.15, 0.15, 0.17, 1.0]);
        let color = [c[0].max(MIN_CHANNEL), c[1].max(MIN_CHANNEL), c[2].max(MIN_CHANNEL), 1.0];
        let mut model = ControllerModel { nodes, roots, meshes, color, responses, touch_point, offset: Vec3::ZERO };
        model.offset = model.front_offset();
        Ok(model)
    }

    /// The offset that puts the centre of the model's front face (the vertices within
    /// [`FRONT_DEPTH`] of its most forward one, at rest) on the origin.
    fn front_offset(&self) -> Vec3 {
        let mut points = Vec::new();
        self.pose(&ControllerInput::default(), Mat4::IDENTITY, &mut |p, _, _| points.push(p));
        let front = points.iter().map(|p| p.z).fold(f32::INFINITY, f32::min);
        if !front.is_finite() {
            return Vec3::ZERO;
        }
        let near: Vec<&Vec3> = points.iter().filter(|p| p.z <= front + FRONT_DEPTH).collect();
        let y = near.iter().map(|p| p.y).sum::<f32>() / near.len() as f32;
        -Vec3::new(0.0, y, front)
    }

    /// Every node's transform in model space for `input`, and whether it is drawn.
    fn world(&self, input: &ControllerInput) -> (Vec<Mat4>, Vec<bool>) {
        let mut local: Vec<Trs> = self.nodes.iter().map(|n| n.local).collect();
        let mut visible = vec![true; self.nodes.len()];
        for r in &self.responses {
            let v = r.value(input);
            match r.effect {
                Effect::Transform { min, max } => {
                    local[r.node] = Trs::lerp(self.nodes[min].local, self.nodes[max].local, v)
                }
                Effect::Visibility => visible[r.node] = v > 0.5,
            }
        }
        let mut world = vec![Mat4::IDENTITY; self.nodes.len()];
        let mut drawn = vec![false; self.nodes.len()];
        let mut stack: Vec<(usize, Mat4, bool)> = self.roots.iter().map(|&r| (r, Mat4::IDENTITY, true)).collect();
        let mut seen = vec![false; self.nodes.len()];
        while let Some((i, parent, shown)) = stack.pop() {
            if i >= self.nodes.len() || std::mem::replace(&mut seen[i], true) {
                continue;
            }
            world[i] = parent * local[i].matrix();
            drawn[i] = shown && visible[i];
            stack.extend(self.nodes[i].children.iter().map(|&c| (c, world[i], drawn[i])));
        }
        (world, drawn)
    }

    /// The placement of the model at a controller pose: grip space (−Z forward, +Y up) turned
    /// by `rotation` and moved so that its front face sits at `origin`, where the ray starts.
    pub fn placement(&self, origin: Vec3, rotation: Quat) -> Mat4 {
        Mat4::from_rotation_translation(rotation, origin) * Mat4::from_translation(self.offset)
    }

    /// The model posed by `input` at `place` (see [`ControllerModel::placement`]): emits each
    /// triangle's three vertices (world position, unit normal, colour) in order, and returns
    /// the touch dot's centre when the touchpad is touched.
    pub fn pose(
        &self,
        input: &ControllerInput,
        place: Mat4,
        out: &mut dyn FnMut(Vec3, Vec3, [f32; 4]),
    ) -> Option<Vec3> {
        let (world, drawn) = self.world(input);
        for (i, node) in self.nodes.iter().enumerate() {
            let Some(mesh) = node.mesh.and_then(|m| self.meshes.get(m)) else {
                continue;
            };
            if !drawn[i] {
                continue;
            }
            let m = place * world[i];
            let n = Mat3::from_mat4(m).inverse().transpose();
            for &k in &mesh.indices {
                let k = k as usize;
                out(m.transform_point3(mesh.positions[k]), (n * mesh.normals[k]).normalize_or_zero(), self.color);
            }
        }
        let t = self.touch_point?;
        drawn[t].then(|| (place * world[t]).transform_point3(Vec3::ZERO))
    }

    /// The model-space transform of the node called `name` for `input`, if there is one.
    pub fn node_transform(&self, input: &ControllerInput, name: &str) -> Option<Mat4> {
        let i = self.nodes.iter().position(|n| n.name == name)?;
        Some(self.world(input).0[i])
    }

    /// Whether the node called `name` is drawn for `input`.
    pub fn node_drawn(&self, input: &ControllerInput, name: &str) -> Option<bool> {
        let i = self.nodes.iter().position(|n| n.name == name)?;
        Some(self.world(input).1[i])
    }

    /// The mean model-space position of the vertices under the node called `name`, for
    /// `input` (the centre of a moving part), if it holds any.
    pub fn mesh_centre(&self, input: &ControllerInput, name: &str) -> Option<Vec3> {
        let root = self.nodes.iter().position(|n| n.name == name)?;
        let (world, drawn) = self.world(input);
        let mut stack = vec![root];
        let mut seen = vec![false; self.nodes.len()];
        let (mut sum, mut count) = (Vec3::ZERO, 0usize);
        while let Some(i) = stack.pop() {
            if i >= self.nodes.len() || std::mem::replace(&mut seen[i], true) {
                continue;
            }
            stack.extend(&self.nodes[i].children);
            if let Some(mesh) = self.nodes[i].mesh.and_then(|m| self.meshes.get(m))
                && drawn[i]
            {
                sum += mesh.positions.iter().map(|&p| world[i].transform_point3(p)).sum::<Vec3>();
                count += mesh.positions.len();
            }
        }
        (count > 0).then(|| sum / count as f32)
    }

    /// The number of triangles drawn at rest.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.indices.len() / 3).sum()
    }
}

/// The model's folder under `assets`.
pub fn model_dir(assets: &Path) -> PathBuf {
    assets.join(MODEL_DIR)
}

#[cfg(test)]
#[path = "controller_tests.rs"]
mod tests;
