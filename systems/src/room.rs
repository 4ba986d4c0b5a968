//! The scene of a session in a room a headset found (AR, `docs/headset.md`): the floor as a flat
//! ground wide enough for the task (40 × 40 m around the start, at y = 0 of the simulation's
//! frame), the other horizontal planes found between [`PLANE_BAND_M`] (tables, shelves) as
//! meshes, and the study scene's step, seed, sun, wind and camera. Comments say how the floor was
//! found and which of the task's targets the room moves ([`crate::task_layout`]).
//!
//! The WebAssembly module builds it for the page in one call (`grove_room_scene`, `web/sim`);
//! the text it gives is self-contained ([`crate::scene_text`]), so `grove serve` takes every room
//! built here.

use glam::{Vec2, Vec3};
use serde::Deserialize;

use crate::input::InputEvent;
use crate::scene::{PlaneDef, PlaneShape, Scene};
use crate::sim::Sim;
use crate::task::TaskDef;

/// The most planes besides the floor a room keeps (the first ones found within the band).
pub const MAX_ROOM_PLANES: usize = 16;
/// The heights above the floor (exclusive, metres) between which a plane is kept: a tabletop or
/// a shelf within reach, not the floor again nor the ceiling.
pub const PLANE_BAND_M: (f64, f64) = (0.3, 2.2);
/// The most points a plane's outline may have to be kept.
pub const MAX_PLANE_POINTS: usize = 128;
/// The most characters of the floor's source kept in the comment.
const MAX_SOURCE_CHARS: usize = 120;

/// What the page found: how it found the floor, the floor's height in the session's reference
/// space, the horizontal planes in the simulation's frame (whose y = 0 is the floor), and the
/// task the session runs.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoomInput {
    /// How the floor was found ("plane detection (floor)", "hit test", …).
    pub source: String,
    /// The floor's height from the session's `local-floor` origin, metres.
    pub floor_y: f64,
    /// The horizontal planes found, in the simulation's frame.
    #[serde(default)]
    pub planes: Vec<FoundPlane>,
    /// The task the session runs, whose targets the room may move.
    #[serde(default)]
    pub task: Option<String>,
    /// How the task's targets are laid out (`crate::room_layout`), when not as its file puts them.
    #[serde(default)]
    pub layout: Option<crate::room_layout::TaskLayout>,
}

/// A horizontal plane the headset found.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FoundPlane {
    /// Its semantic label ("table", "shelf"), if the headset gave one.
    #[serde(default)]
    pub label: Option<String>,
    /// Its outline, in order, metres.
    pub points: Vec<Point>,
}

/// A point of a plane's outline, metres.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Point {
    /// East.
    pub x: f64,
    /// Up.
    pub y: f64,
    /// South.
    pub z: f64,
}

/// Why a room's scene could not be built.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RoomError {
    /// The task is not a built-in one.
    #[error("task '{0}' is not a built-in task")]
    UnknownTask(String),
    /// The scene built breaks a scene rule (a point beyond the limits of `limits.rs`).
    #[error("the room's scene: {0}")]
    Scene(String),
}

/// A number as the scene's text gives it: rounded to 0.1 mm.
fn round(v: f64) -> f32 {
    ((v * 1e4).round() / 1e4) as f32
}

/// A number in a comment: rounded to 0.1 mm, whole numbers with one decimal.
fn num(v: f64) -> String {
    let t = (v * 1e4).round() / 1e4 + 0.0; // no "-0.0"
    if t.fract() == 0.0 && t.abs() < 1e15 { format!("{t:.1}") } else { format!("{t}") }
}

/// A plane's outline as a mesh: a fan of triangles, counter-clockwise seen from above.
fn mesh(points: &[Point]) -> PlaneShape {
    let mut vertices: Vec<Vec3> = points.iter().map(|p| Vec3::new(round(p.x), round(p.y), round(p.z))).collect();
    let area: f64 = (0..points.len()).map(|i| {
        let (a, b) = (points[i], points[(i + 1) % points.len()]);
        a.x * b.z - b.x * a.z
    }).sum();
    // Seen from above (+X right, −Z up the page), counter-clockwise is a negative signed area
    // in (x, z).
    if area > 0.0 {
        vertices.reverse();
    }
    let triangles = (1..vertices.len() as u32 - 1).map(|i| [0, i, i + 1]).collect();
    PlaneShape::Mesh { vertices, triangles }
}

/// A plane's name in the scene: its label's letters and underscores, lowercase, and its number.
fn plane_name(label: Option<&str>, n: usize) -> String {
    let word: String = label.unwrap_or_default().chars().filter(|c| c.is_ascii_alphabetic() || *c == '_').map(|c| c.to_ascii_lowercase()).collect();
    format!("{}-{n}", if word.is_empty() { "plane" } else { &word })
}

/// The planes a room keeps, named: those with 3 to [`MAX_PLANE_POINTS`] points whose mean height
/// lies in [`PLANE_BAND_M`], the first [`MAX_ROOM_PLANES`] of them.
fn kept(planes: &[FoundPlane]) -> Vec<PlaneDef> {
    planes
        .iter()
        .filter(|p| (3..=MAX_PLANE_POINTS).contains(&p.points.len()))
        .filter(|p| {
            let y = p.points.iter().map(|q| q.y).sum::<f64>() / p.points.len() as f64;
            y > PLANE_BAND_M.0 && y < PLANE_BAND_M.1
        })
        .take(MAX_ROOM_PLANES)
        .enumerate()
        .map(|(i, p)| PlaneDef { name: plane_name(p.label.as_deref(), i + 1), shape: mesh(&p.points) })
        .collect()
}

/// The room's scene as text (a RON scene file with its comments).
pub fn room_scene(input: &RoomInput) -> Result<String, RoomError> {
    let study = Scene::builtin("study").ok_or_else(|| RoomError::Scene("the built-in study scene is missing".into()))?;
    let floor = PlaneShape::Grid { min: Vec2::new(-20.0, -14.0), size: Vec2::new(40.0, 40.0), cell: 2.0, elevation: 0.0, unevenness: 0.0, noise_seed: 0, holes: Vec::new() };
    let mut planes = vec![PlaneDef { name: "floor".into(), shape: floor }];
    planes.extend(kept(&input.planes));
    let scene = Scene { name: "room".into(), dt: study.dt, seed: study.seed, planes, sun: study.sun, wind: study.wind, camera: study.camera, ..Scene::default() };
    scene.validate().map_err(|e| RoomError::Scene(e.0))?;

    let source: String = input.source.chars().filter(|c| !c.is_control()).take(MAX_SOURCE_CHARS).collect();
    let mut text = String::from("// A room found by a headset in AR: its floor is the ground (docs/headset.md).\n");
    text += &format!("// The floor was found by {source}, {} m from the session's local-floor origin; the simulation's\n", num(input.floor_y));
    text += "// frame puts the participant's start at (0, 6), looking towards -Z, and the floor at y = 0.\n";
    // The simulation of the room, built here so that a room that cannot be simulated is refused
    // here, and stepped once with the task to find the targets the room moves.
    let mut sim = Sim::from_scene(&scene, scene.seed).map_err(|e| RoomError::Scene(e.to_string()))?;
    if let Some(task) = &input.task {
        let def = TaskDef::builtin(task).ok_or_else(|| RoomError::UnknownTask(task.chars().take(64).collect()))?;
        sim.step_with([InputEvent::StartTask { task: task.clone(), layout: input.layout.clone() }]).map_err(|e| RoomError::Scene(e.to_string()))?;
        for m in sim.moved_targets() {
            let model = def.targets.get(m.target).map_or("?", |t| t.model.as_str());
            let to: Vec<String> = m.to.iter().map(|v| num(*v as f64)).collect();
            text += &format!("// Target {} ({model}) has no plane at {} m in this room: it lies on the floor at ({}).\n", m.target, num(m.from[1] as f64), to.join(", "));
        }
    }
    let pretty = ron::ser::PrettyConfig::new().depth_limit(3);
    text += &ron::ser::to_string_pretty(&scene, pretty).map_err(|e| RoomError::Scene(e.to_string()))?;
    text.push('\n');
    // What is built here is taken wherever a scene's text is (the module, the server).
    crate::scene_text::self_contained(&text).map_err(|e| RoomError::Scene(e.to_string()))?;
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(y: f64, side: f64, clockwise: bool) -> FoundPlane {
        let mut points: Vec<Point> = [(0.0, 0.0), (side, 0.0), (side, side), (0.0, side)].iter().map(|&(x, z)| Point { x: x + 1.0, y, z: z - 3.0 }).collect();
        if clockwise {
            points.reverse();
        }
        FoundPlane { label: Some("Table!".into()), points }
    }

    fn room(planes: Vec<FoundPlane>, task: Option<&str>) -> RoomInput {
        RoomInput { source: "plane detection (floor)\nScene(".into(), floor_y: -0.0312, planes, task: task.map(str::to_string), layout: None }
    }

    #[test]
    fn a_floor_alone_is_the_study_s_ground_and_moves_the_terrace_target() {
        let text = room_scene(&room(Vec::new(), Some("ray-casting-7"))).unwrap();
        let scene = crate::scene_text::self_contained(&text).unwrap();
        let study = Scene::builtin("study").unwrap();
        assert_eq!((scene.dt, scene.seed, &scene.sun, &scene.camera), (study.dt, study.seed, &study.sun, &study.camera));
        assert_eq!(scene.planes.len(), 1);
        assert!(text.contains("found by plane detection (floor)Scene(, -0.0312 m"), "no line break from the source: {text}");
        assert!(text.contains("// Target 6 (birch-billboard) has no plane at 0.8 m in this room: it lies on the floor at (10.0, 0.0, -11.0).\n"), "{text}");
        assert_eq!(text.lines().filter(|l| l.starts_with("// Target")).count(), 1);
    }

    #[test]
    fn planes_within_the_band_become_meshes_counter_clockwise_seen_from_above() {
        let planes = vec![square(0.75, 1.2, false), square(0.75, 1.2, true), square(0.1, 1.0, false), square(2.5, 1.0, false), FoundPlane { label: None, points: vec![Point { x: 0.0, y: 1.0, z: 0.0 }; 2] }, FoundPlane { label: None, points: square(1.0, 1.0, false).points }];
        let scene = crate::scene_text::self_contained(&room_scene(&room(planes, None)).unwrap()).unwrap();
        let names: Vec<&str> = scene.planes.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["floor", "table-1", "table-2", "plane-3"], "the floor, the band's planes, unlabelled ones as plane");
        for p in &scene.planes[1..] {
            let PlaneShape::Mesh { vertices, triangles } = &p.shape else { panic!("{p:?}") };
            assert_eq!(triangles, &vec![[0, 1, 2], [0, 2, 3]]);
            for t in triangles {
                let [a, b, c] = t.map(|i| vertices[i as usize]);
                let up = (b - a).cross(c - a).y;
                assert!(up > 0.0, "{}: a triangle faces down", p.name);
            }
        }
    }

    #[test]
    fn many_planes_keep_the_first_sixteen_and_planes_at_the_limits_are_refused_or_dropped() {
        let many: Vec<FoundPlane> = (0..40).map(|i| square(0.5 + i as f64 * 0.01, 0.5, i % 2 == 0)).collect();
        let scene = crate::scene_text::self_contained(&room_scene(&room(many, Some("manual-7"))).unwrap()).unwrap();
        assert_eq!(scene.planes.len(), 1 + MAX_ROOM_PLANES);
        let far = FoundPlane { label: None, points: vec![Point { x: 2.0e6, y: 1.0, z: 0.0 }, Point { x: 2.0e6 + 1.0, y: 1.0, z: 0.0 }, Point { x: 2.0e6, y: 1.0, z: 1.0 }] };
        assert!(matches!(room_scene(&room(vec![far], None)), Err(RoomError::Scene(m)) if m.contains("beyond the limit")));
        let dense = FoundPlane { label: None, points: (0..=MAX_PLANE_POINTS).map(|i| Point { x: (i as f64).cos(), y: 1.0, z: (i as f64).sin() }).collect() };
        assert_eq!(crate::scene_text::self_contained(&room_scene(&room(vec![dense], None)).unwrap()).unwrap().planes.len(), 1, "a plane with too many points is left out");
        assert_eq!(room_scene(&room(Vec::new(), Some("knitting"))).unwrap_err(), RoomError::UnknownTask("knitting".into()));
    }
}
