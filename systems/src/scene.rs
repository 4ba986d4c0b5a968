//! Scenes: the starting state of a simulation, read from RON files in `assets/scenes/`.
//!
//! The fields are documented on the types below and in `docs/scenes.md`. Loading checks every
//! number (finite, positive where it must be) and every plane (at least 3 vertices, valid
//! triangles), and reports the first problem as one line naming the file and, where RON says,
//! the line and column.

use std::path::Path;

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::limits::{self, MAX_COORD, RAISE};
pub use crate::limits::InvalidScene;
pub use crate::plane_geometry::{plane_geometry, plane_geometry_cut};

/// Scenes that ship with grove, embedded at compile time: `(name, RON text)`. A replay header
/// may name one of these instead of a path.
pub const BUILTIN_SCENES: &[(&str, &str)] = &[("study", include_str!("../../assets/scenes/study.ron"))];

/// A scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// A human-readable name.
    pub name: String,
    /// The fixed simulation step, seconds. Default 1/60.
    #[serde(default = "default_dt")]
    pub dt: f32,
    /// The seed of the simulation's RNG, unless a replay or the command line gives one.
    #[serde(default)]
    pub seed: u64,
    /// Ground surfaces.
    pub planes: Vec<PlaneDef>,
    /// Where and when the scene is, for the sun.
    pub sun: SunDef,
    /// The wind.
    pub wind: WindDef,
    /// Trees present at the start.
    #[serde(default)]
    pub trees: Vec<TreeDef>,
    /// Trees scattered over regions at the start (see `scatter.rs`), after `trees`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub scatter: Vec<crate::scatter::ScatterDef>,
    /// The initial head (camera) pose.
    pub camera: CameraDef,
    /// Model-bank folders whose models the scene's trees and scatters may name, relative to the
    /// scene file's folder (docs/model-bank.md); searched before any `--bank` folder.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub banks: Vec<String>,
    /// The folder of the file the scene was read from ([`Scene::load`]); not part of the file.
    #[serde(skip)]
    pub dir: Option<std::path::PathBuf>,
    /// Water bodies (ponds): outlines at a surface height (see `water.rs`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub water: Vec<crate::water::WaterDef>,
    /// Grass patches (see `grass.rs`); each becomes an entity with a `Grass` component.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub grass: Vec<crate::grass::GrassDef>,
    /// Aerial photographs draped on the ground, with a tree at each photographed crown (see
    /// `aerial.rs`); absent in scenes without photographs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub aerial: Option<crate::aerial::AerialDef>,
    /// Cut the grid planes' holes exactly: the vertices on a hole's rim are moved onto its circle
    /// ([`crate::holes::cut_rims`]), so a pit is round instead of following the grid's triangles
    /// with spikes along its diagonals. Off by default, so that the planes (and every world hash)
    /// of existing scenes stay as they are.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub exact_holes: bool,
}

fn default_dt() -> f32 {
    1.0 / 60.0
}

/// A scene built in code starts from this: `Scene { planes, ..Scene::default() }` names only
/// what differs, so a new section (a field with its own `Default`) edits this module and its
/// feature, never the scenes built elsewhere. An empty scene: no planes, trees or other
/// sections, the default step (1/60 s), seed 0, and the default sun ([`SunDef::default`]),
/// calm wind ([`WindDef::default`]) and camera ([`CameraDef::default`]). Scene files are read
/// as before: a file still names its sun, wind and camera, and a field it leaves out takes the
/// default its `serde` attribute names.
impl Default for Scene {
    fn default() -> Scene {
        Scene {
            name: "scene".into(),
            dt: default_dt(),
            seed: 0,
            planes: Vec::new(),
            sun: SunDef::default(),
            wind: WindDef::default(),
            trees: Vec::new(),
            scatter: Vec::new(),
            camera: CameraDef::default(),
            banks: Vec::new(),
            dir: None,
            water: Vec::new(),
            grass: Vec::new(),
            aerial: None,
            exact_holes: false,
        }
    }
}

/// A ground plane.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneDef {
    /// The plane's name, e.g. "ground".
    pub name: String,
    /// Its geometry.
    pub shape: PlaneShape,
}

/// The geometry of a plane.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum PlaneShape {
    /// An explicit triangle mesh, as a world reconstruction exports it.
    Mesh {
        /// Vertex positions, metres.
        vertices: Vec<Vec3>,
        /// Triangles as vertex indices, counter-clockwise seen from above.
        triangles: Vec<[u32; 3]>,
    },
    /// A generated reconstruction-like surface: a regular grid of `cell`-sized squares over the
    /// rectangle `min .. min + size` (X and Z), at height `elevation` plus Perlin unevenness of
    /// amplitude `unevenness`, with every triangle whose centre lies in a hole left out.
    Grid {
        /// Minimum corner (X, Z), metres.
        min: Vec2,
        /// Size along X and Z, metres.
        size: Vec2,
        /// Grid spacing, metres.
        cell: f32,
        /// Base height, metres.
        elevation: f32,
        /// Amplitude of the unevenness, metres.
        #[serde(default)]
        unevenness: f32,
        /// Seed of the unevenness noise.
        #[serde(default)]
        noise_seed: u32,
        /// Holes, as circles in the XZ plane.
        #[serde(default)]
        holes: Vec<Hole>,
    },
}

pub use crate::holes::Hole;

/// Where and when the scene is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SunDef {
    /// Latitude, degrees north, −90..=90.
    pub latitude_deg: f64,
    /// Longitude, degrees east, −180..=180.
    pub longitude_deg: f64,
    /// UTC date and time, RFC 3339, e.g. "2026-06-21T10:00:00Z".
    pub utc: String,
    /// Sun seconds per simulated second (0 = fixed).
    #[serde(default)]
    pub time_rate: f64,
}

/// Zürich at 10:00 UTC on the summer solstice, the sun fixed.
impl Default for SunDef {
    fn default() -> SunDef {
        SunDef { latitude_deg: 47.37, longitude_deg: 8.54, utc: "2026-06-21T10:00:00Z".into(), time_rate: 0.0 }
    }
}

/// The wind.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindDef {
    /// Direction the wind blows towards; only X and Z are used.
    pub direction: Vec3,
    /// Base strength (0 = calm).
    pub strength: f32,
    /// Spatial frequency, per metre.
    pub density: f32,
    /// Mean gust factor.
    pub gust_average: f32,
    /// Gust amplitude.
    pub gust_strength: f32,
    /// Gust frequency, hertz.
    pub gust_frequency: f32,
    /// The per-vertex wind model, `noise` or `hierarchical` (default).
    #[serde(default)]
    pub model: crate::wind_model::WindModel,
    /// Per-vertex response constants; every field has a default.
    #[serde(default)]
    pub response: crate::wind_model::WindResponse,
}

/// Calm: no strength and no gusts, blowing towards +X, with the default model and response.
impl Default for WindDef {
    fn default() -> WindDef {
        WindDef {
            direction: Vec3::X,
            strength: 0.0,
            density: 0.1,
            gust_average: 0.0,
            gust_strength: 0.0,
            gust_frequency: 0.0,
            model: Default::default(),
            response: Default::default(),
        }
    }
}

pub use crate::tree_def::TreeDef;

/// The initial camera.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDef {
    /// Eye position, metres.
    pub position: Vec3,
    /// A point the camera looks at.
    pub look_at: Vec3,
    /// Vertical field of view, degrees.
    #[serde(default = "default_fov")]
    pub fov_y_deg: f32,
}

fn default_fov() -> f32 {
    60.0
}

/// At eye height 6 m south of the origin, looking at it, with the default field of view.
impl Default for CameraDef {
    fn default() -> CameraDef {
        CameraDef { position: Vec3::new(0.0, 1.7, 6.0), look_at: Vec3::ZERO, fov_y_deg: default_fov() }
    }
}

/// A scene that could not be loaded. Its `Display` is one line that names the file.
#[derive(Debug, thiserror::Error)]
#[error("{file}: {message}")]
pub struct SceneError {
    /// The file (or "<text>").
    pub file: String,
    /// What is wrong, with line and column where known.
    pub message: String,
}

impl Scene {
    /// Reads and checks a scene file. Only a regular file of at most
    /// [`limits::MAX_SCENE_BYTES`] is read; a folder, a device, a pipe or a larger file is
    /// refused before anything is read from it.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = read_scene_text(path)?;
        let mut scene = Scene::parse(&text, &path.display().to_string())?;
        scene.dir = Some(path.parent().map(Path::to_path_buf).unwrap_or_default());
        // The crowns file an aerial section names, read with its limits.
        let dir = scene.dir.clone().unwrap_or_default();
        if let Some(a) = &mut scene.aerial {
            if let Some(c) = &a.crowns {
                a.crown_list = crate::aerial::read_crowns(&dir.join(c)).map_err(|message| SceneError { file: path.display().to_string(), message: format!("aerial crowns: {message}") })?;
            }
        }
        Ok(scene)
    }

    /// The scene's bank folders ([`Scene::banks`]) resolved against the scene file's folder.
    pub fn bank_dirs(&self) -> Vec<std::path::PathBuf> {
        self.banks.iter().map(|b| self.dir.as_deref().unwrap_or(Path::new("")).join(b)).collect()
    }

    /// A scene that ships with grove, by name (e.g. "study").
    pub fn builtin(name: &str) -> Option<Scene> {
        // Each built-in scene is parsed once per process: every replayed recording names one.
        static PARSED: std::sync::OnceLock<Vec<Option<Scene>>> = std::sync::OnceLock::new();
        let i = BUILTIN_SCENES.iter().position(|(n, _)| *n == name)?;
        let parsed = PARSED.get_or_init(|| BUILTIN_SCENES.iter().map(|(n, text)| Scene::parse(text, n).ok()).collect());
        parsed[i].clone()
    }

    /// Parses and checks scene text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Scene, SceneError> {
        let scene: Scene = ron::from_str(text).map_err(|e| SceneError {
            file: file.to_string(),
            message: format!("line {}, column {}: {}", e.span.start.line, e.span.start.col, e.code),
        })?;
        scene.validate().map_err(|e| SceneError { file: file.to_string(), message: e.0 })?;
        Ok(scene)
    }

    /// Checks the numbers and shapes against the limits of [`crate::limits`]; returns a
    /// one-line message for the first problem. Every coordinate, size, radius and elevation must
    /// be finite and within ±[`MAX_COORD`] metres, so no library ever sees a value it cannot
    /// handle, and the cells, holes, planes and trees are bounded, so building the scene takes
    /// bounded time and memory.
    pub fn validate(&self) -> Result<(), InvalidScene> {
        self.validate_message().map_err(InvalidScene)
    }

    fn validate_message(&self) -> Result<(), String> {
        let finite = |what: &str, ok: bool| if ok { Ok(()) } else { Err(format!("{what} has a NaN or infinite number")) };
        let near = |what: &str, v: &[f32]| {
            finite(what, v.iter().all(|x| x.is_finite()))?;
            if v.iter().any(|x| x.abs() > MAX_COORD) {
                return Err(format!("{what} has a number beyond the limit of ±{MAX_COORD:e} m"));
            }
            Ok(())
        };
        if !(self.dt.is_finite() && self.dt > 0.0 && self.dt <= 1.0) {
            return Err(format!("dt {} must be in (0, 1] seconds", self.dt));
        }
        if self.planes.is_empty() {
            return Err("a scene needs at least one plane".into());
        }
        if self.banks.len() > 8 || self.banks.iter().any(|b| b.is_empty() || b.len() > 512 || Path::new(b).is_absolute()) {
            return Err("banks: at most 8 folders, each a relative path to a model bank".into());
        }
        if self.planes.len() > limits::MAX_PLANES {
            return Err(format!("{} planes is more than the limit of {} planes per scene ({RAISE})", self.planes.len(), limits::MAX_PLANES));
        }
        let mut cells = 0u64;
        for p in &self.planes {
            let what = format!("plane '{}'", p.name.escape_debug());
            let plane_cells = match &p.shape {
                PlaneShape::Mesh { vertices, triangles } => {
                    if vertices.len() < 3 {
                        return Err(format!("{what} has {} vertices; a plane needs at least 3", vertices.len()));
                    }
                    for v in vertices {
                        near(&what, &v.to_array())?;
                    }
                    if triangles.is_empty() {
                        return Err(format!("{what} has no triangles"));
                    }
                    for t in triangles {
                        if t.iter().any(|&i| i as usize >= vertices.len()) {
                            return Err(format!("{what} has a triangle {t:?} with an index past its {} vertices", vertices.len()));
                        }
                    }
                    (triangles.len() as u64).div_ceil(2)
                }
                PlaneShape::Grid { min, size, cell, elevation, unevenness, holes, .. } => {
                    near(&what, &[min.x, min.y, size.x, size.y, *cell, *elevation, *unevenness])?;
                    if size.x <= 0.0 || size.y <= 0.0 || *cell <= 0.0 {
                        return Err(format!("{what}: size and cell must be positive"));
                    }
                    let max = *min + *size;
                    near(&what, &[max.x, max.y])?;
                    let reach = min.abs().max(max.abs()).max_element();
                    let least = limits::MIN_CELL.max(reach * limits::MIN_CELL_RELATIVE);
                    if *cell < least {
                        return Err(format!("{what}: cell {cell} m is finer than {least} m (at least 1 mm, and 1/100000 of the plane's distance from the origin)"));
                    }
                    if holes.len() > limits::MAX_HOLES_PER_PLANE {
                        return Err(format!("{what}: {} holes is more than the limit of {} holes per plane ({RAISE})", holes.len(), limits::MAX_HOLES_PER_PLANE));
                    }
                    for h in holes {
                        near(&what, &[h.center.x, h.center.y, h.radius])?;
                        if h.radius < 0.0 {
                            return Err(format!("{what}: a hole has a negative radius"));
                        }
                    }
                    // The same single-precision counts as `plane_geometry` builds.
                    let (nx, nz) = ((size.x / cell).ceil().max(1.0) as u64, (size.y / cell).ceil().max(1.0) as u64);
                    nx.saturating_mul(nz)
                }
            };
            cells = cells.saturating_add(plane_cells);
            if cells > limits::MAX_SCENE_CELLS {
                return Err(format!(
                    "{what}: the scene's planes have more than the limit of {} grid cells per scene, all planes together; an explicit mesh counts a cell per two triangles ({RAISE})",
                    limits::MAX_SCENE_CELLS
                ));
            }
        }
        let s = &self.sun;
        finite("sun", s.latitude_deg.is_finite() && s.longitude_deg.is_finite() && s.time_rate.is_finite())?;
        if !(-90.0..=90.0).contains(&s.latitude_deg) {
            return Err(format!("sun latitude {} is outside -90..=90 degrees", s.latitude_deg));
        }
        if !(-180.0..=180.0).contains(&s.longitude_deg) {
            return Err(format!("sun longitude {} is outside -180..=180 degrees", s.longitude_deg));
        }
        if s.time_rate.abs() > 1.0e6 {
            return Err(format!("sun time_rate {} is beyond ±1e6 sun seconds per simulated second", s.time_rate));
        }
        parse_utc_ms(&s.utc).map_err(|e| format!("sun utc: {e}"))?;
        let w = &self.wind;
        near("wind", &[w.direction.x, w.direction.y, w.direction.z, w.strength, w.density, w.gust_average, w.gust_strength, w.gust_frequency])?;
        if w.strength < 0.0 || w.density < 0.0 || w.gust_frequency < 0.0 {
            return Err("wind strength, density and gust frequency must not be negative".into());
        }
        w.response.validate()?;
        if self.trees.len() > limits::MAX_SCENE_TREES {
            return Err(format!("{} trees is more than the limit of {} trees per scene ({RAISE})", self.trees.len(), limits::MAX_SCENE_TREES));
        }
        for (i, t) in self.trees.iter().enumerate() {
            near(&format!("tree {i}"), &[t.position.x, t.position.y, t.position.z, t.yaw_deg])?;
            finite(&format!("tree {i}"), t.scale.is_finite())?;
            if !(t.scale > 0.0 && t.scale <= 1000.0) {
                return Err(format!("tree {i} has scale {}; scale must be positive and at most 1000", t.scale));
            }
        }
        if self.scatter.len() > limits::MAX_SCATTERS {
            return Err(format!("{} scatters is more than the limit of {} per scene ({RAISE})", self.scatter.len(), limits::MAX_SCATTERS));
        }
        let mut most = self.trees.len() as f64;
        for (i, sc) in self.scatter.iter().enumerate() {
            sc.validate().map_err(|e| format!("scatter {i}: {e}"))?;
            most += sc.most_trees().min(crate::scatter::MAX_TREES as f64);
        }
        if most > limits::MAX_SCENE_TREES as f64 {
            return Err(format!(
                "the trees and scatters could place {most:.0} trees, more than the limit of {} trees per scene ({RAISE})",
                limits::MAX_SCENE_TREES
            ));
        }
        crate::water::validate_all(&self.water)?;
        let c = &self.camera;
        near("camera", &[c.position.x, c.position.y, c.position.z, c.look_at.x, c.look_at.y, c.look_at.z])?;
        finite("camera", c.fov_y_deg.is_finite())?;
        if !(1.0..=179.0).contains(&c.fov_y_deg) {
            return Err(format!("camera fov_y_deg {} is outside 1..=179", c.fov_y_deg));
        }
        crate::grass::validate_all(&self.grass, &self.plane_outlines())?;
        if let Some(a) = &self.aerial {
            a.validate()?;
        }
        Ok(())
    }
}

impl Scene {
    /// Every plane's outline (name, bounding rectangle, holes), as grass patches see them.
    pub fn plane_outlines(&self) -> Vec<crate::grass::PlaneOutline<'_>> {
        self.planes.iter().map(PlaneDef::outline).collect()
    }
}

impl PlaneDef {
    /// The plane's name, (x, z) bounding rectangle and holes.
    pub fn outline(&self) -> crate::grass::PlaneOutline<'_> {
        let (lo, hi, holes): (Vec2, Vec2, &[Hole]) = match &self.shape {
            PlaneShape::Grid { min, size, holes, .. } => (*min, *min + *size, holes),
            PlaneShape::Mesh { vertices, .. } => {
                let (lo, hi) = crate::grass::bounds(vertices.iter().map(|v| Vec2::new(v.x, v.z)));
                (lo, hi, &[])
            }
        };
        crate::grass::PlaneOutline { name: &self.name, lo, hi, holes }
    }
}

/// Reads a scene file's text through [`crate::files`]: only a regular file (symbolic links are
/// followed) of at most [`limits::MAX_SCENE_BYTES`], checked before anything is read, never
/// blocking on a pipe, and read with that bound in case the file grows meanwhile.
pub fn read_scene_text(path: &Path) -> Result<String, SceneError> {
    crate::files::read_text(path, crate::files::Kind::Scene).map_err(|e| SceneError { file: path.display().to_string(), message: e.reason() })
}

/// A one-line description of an I/O error.
pub fn io_message(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        std::io::ErrorKind::InvalidData => "not valid UTF-8 text".into(),
        _ => e.to_string(),
    }
}

/// A time that is not RFC 3339.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("'{text}' is not an RFC 3339 time ({reason})")]
pub struct TimeError {
    /// The text as written.
    pub text: String,
    /// What the parser said.
    pub reason: String,
}

/// Parses an RFC 3339 UTC time into milliseconds since the Unix epoch.
pub fn parse_utc_ms(text: &str) -> Result<i64, TimeError> {
    let t = chrono::DateTime::parse_from_rfc3339(text.trim()).map_err(|e| TimeError { text: text.to_string(), reason: e.to_string() })?;
    Ok(t.timestamp_millis())
}

/// Formats milliseconds since the Unix epoch as RFC 3339 UTC.
pub fn format_utc_ms(ms: i64) -> String {
    chrono::DateTime::from_timestamp_millis(ms)
        .map(|t| t.to_rfc3339_opts(chrono::SecondsFormat::Millis, true))
        .unwrap_or_else(|| format!("{ms} ms"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ground() -> PlaneDef {
        let shape = PlaneShape::Grid { min: Vec2::splat(-5.0), size: Vec2::splat(10.0), cell: 1.0, elevation: 0.0, unevenness: 0.0, noise_seed: 0, holes: vec![] };
        PlaneDef { name: "ground".into(), shape }
    }

    #[test]
    fn a_scene_built_from_the_defaults_is_a_valid_file() {
        let scene = Scene { planes: vec![ground()], ..Scene::default() };
        scene.validate().unwrap();
        let text = ron::ser::to_string_pretty(&scene, Default::default()).unwrap();
        assert_eq!(Scene::parse(&text, "<text>").unwrap(), scene);
        assert_eq!((scene.dt, scene.seed, scene.camera.fov_y_deg, scene.wind.strength), (1.0 / 60.0, 0, 60.0, 0.0));
    }

    #[test]
    fn a_file_reads_as_before_the_defaults() {
        // What a file leaves out takes its field's serde default, which Default agrees with.
        let sections = [
            ("planes", r#"planes: [(name: "ground", shape: Grid(min: (-5.0, -5.0), size: (10.0, 10.0), cell: 1.0, elevation: 0.0))]"#),
            ("sun", r#"sun: (latitude_deg: 10.0, longitude_deg: 20.0, utc: "2026-01-01T00:00:00Z")"#),
            ("wind", "wind: (direction: (1.0, 0.0, 0.0), strength: 0.5, density: 0.2, gust_average: 0.1, gust_strength: 0.1, gust_frequency: 0.1)"),
            ("camera", "camera: (position: (0.0, 2.0, 5.0), look_at: (0.0, 0.0, 0.0))"),
        ];
        let file = |leave_out: &str| {
            let kept: Vec<&str> = sections.iter().filter(|(name, _)| *name != leave_out).map(|(_, text)| *text).collect();
            format!("Scene(name: \"s\", {})", kept.join(", "))
        };
        let scene = Scene::parse(&file(""), "<text>").unwrap();
        let d = Scene::default();
        assert_eq!((scene.dt, scene.seed, scene.camera.fov_y_deg, scene.sun.time_rate), (d.dt, d.seed, d.camera.fov_y_deg, d.sun.time_rate));
        assert_eq!((scene.wind.model, scene.wind.response), (d.wind.model, d.wind.response));
        assert!(scene.trees.is_empty() && scene.water.is_empty() && scene.grass.is_empty() && scene.aerial.is_none());
        assert_eq!(scene.planes, vec![ground()]);
        // The planes, the sun, the wind and the camera have no default in a file: it must name them.
        for (name, _) in sections {
            let e = Scene::parse(&file(name), "<text>").unwrap_err().to_string();
            assert!(e.contains(&format!("missing field named `{name}`")), "{name}: {e}");
        }
    }
}
