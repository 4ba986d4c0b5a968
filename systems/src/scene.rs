//! Scenes: the starting state of a simulation, read from RON files in `assets/scenes/`.
//!
//! The fields are documented on the types below and in `docs/scenes.md`. Loading checks every
//! number (finite, positive where it must be) and every plane (at least 3 vertices, valid
//! triangles), and reports the first problem as one line naming the file and, where RON says,
//! the line and column.

use std::path::Path;

use glam::{Vec2, Vec3};
use noise::{NoiseFn, Perlin};
use serde::{Deserialize, Serialize};

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
}

fn default_dt() -> f32 {
    1.0 / 60.0
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

/// A circular hole in a grid plane.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hole {
    /// Centre (X, Z), metres.
    pub center: Vec2,
    /// Radius, metres.
    pub radius: f32,
}

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

/// A tree present at the start.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TreeDef {
    /// Model name from the catalogue, e.g. "conifer-billboard".
    pub model: String,
    /// Position of the base, metres. With `on_ground`, Y is replaced by the ground height.
    pub position: Vec3,
    /// Heading about +Y, degrees.
    #[serde(default)]
    pub yaw_deg: f32,
    /// Uniform scale.
    #[serde(default = "one")]
    pub scale: f32,
    /// Put the tree's lowest point on the plane below it.
    #[serde(default = "yes")]
    pub on_ground: bool,
}

fn one() -> f32 {
    1.0
}
fn yes() -> bool {
    true
}

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
    /// Reads and checks a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let file = path.display().to_string();
        if path.is_dir() {
            return Err(SceneError { file, message: "is a directory, not a scene file".into() });
        }
        let text = std::fs::read_to_string(path).map_err(|e| SceneError { file: file.clone(), message: io_message(&e) })?;
        Scene::parse(&text, &file)
    }

    /// A scene that ships with grove, by name (e.g. "study").
    pub fn builtin(name: &str) -> Option<Scene> {
        let (_, text) = BUILTIN_SCENES.iter().find(|(n, _)| *n == name)?;
        Scene::parse(text, name).ok()
    }

    /// Parses and checks scene text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Scene, SceneError> {
        let scene: Scene = ron::from_str(text).map_err(|e| SceneError {
            file: file.to_string(),
            message: format!("line {}, column {}: {}", e.span.start.line, e.span.start.col, e.code),
        })?;
        scene.validate().map_err(|message| SceneError { file: file.to_string(), message })?;
        Ok(scene)
    }

    /// Checks the numbers and shapes; returns a one-line message for the first problem.
    pub fn validate(&self) -> Result<(), String> {
        let finite = |what: &str, ok: bool| if ok { Ok(()) } else { Err(format!("{what} has a NaN or infinite number")) };
        if !(self.dt.is_finite() && self.dt > 0.0 && self.dt <= 1.0) {
            return Err(format!("dt {} must be in (0, 1] seconds", self.dt));
        }
        if self.planes.is_empty() {
            return Err("a scene needs at least one plane".into());
        }
        for p in &self.planes {
            let what = format!("plane '{}'", p.name);
            match &p.shape {
                PlaneShape::Mesh { vertices, triangles } => {
                    if vertices.len() < 3 {
                        return Err(format!("{what} has {} vertices; a plane needs at least 3", vertices.len()));
                    }
                    finite(&what, vertices.iter().all(|v| v.is_finite()))?;
                    if triangles.is_empty() {
                        return Err(format!("{what} has no triangles"));
                    }
                    for t in triangles {
                        if t.iter().any(|&i| i as usize >= vertices.len()) {
                            return Err(format!("{what} has a triangle {t:?} with an index past its {} vertices", vertices.len()));
                        }
                    }
                }
                PlaneShape::Grid { min, size, cell, elevation, unevenness, holes, .. } => {
                    finite(&what, min.is_finite() && size.is_finite() && cell.is_finite() && elevation.is_finite() && unevenness.is_finite())?;
                    if size.x <= 0.0 || size.y <= 0.0 || *cell <= 0.0 {
                        return Err(format!("{what}: size and cell must be positive"));
                    }
                    let cells = (size.x / cell).ceil() * (size.y / cell).ceil();
                    if cells > 4.0e6 {
                        return Err(format!("{what}: {cells} grid cells is too many (at most 4 million)"));
                    }
                    for h in holes {
                        finite(&what, h.center.is_finite() && h.radius.is_finite())?;
                        if h.radius < 0.0 {
                            return Err(format!("{what}: a hole has a negative radius"));
                        }
                    }
                }
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
        parse_utc_ms(&s.utc).map_err(|e| format!("sun utc: {e}"))?;
        let w = &self.wind;
        finite(
            "wind",
            w.direction.is_finite() && w.strength.is_finite() && w.density.is_finite() && w.gust_average.is_finite() && w.gust_strength.is_finite() && w.gust_frequency.is_finite(),
        )?;
        if w.strength < 0.0 || w.density < 0.0 || w.gust_frequency < 0.0 {
            return Err("wind strength, density and gust frequency must not be negative".into());
        }
        w.response.validate()?;
        for (i, t) in self.trees.iter().enumerate() {
            finite(&format!("tree {i}"), t.position.is_finite() && t.yaw_deg.is_finite() && t.scale.is_finite())?;
            if t.scale <= 0.0 {
                return Err(format!("tree {i} has scale {}; scale must be positive", t.scale));
            }
        }
        for (i, sc) in self.scatter.iter().enumerate() {
            sc.validate().map_err(|e| format!("scatter {i}: {e}"))?;
        }
        let c = &self.camera;
        finite("camera", c.position.is_finite() && c.look_at.is_finite() && c.fov_y_deg.is_finite())?;
        if !(1.0..=179.0).contains(&c.fov_y_deg) {
            return Err(format!("camera fov_y_deg {} is outside 1..=179", c.fov_y_deg));
        }
        Ok(())
    }
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

/// Parses an RFC 3339 UTC time into milliseconds since the Unix epoch.
pub fn parse_utc_ms(text: &str) -> Result<i64, String> {
    let t = chrono::DateTime::parse_from_rfc3339(text.trim()).map_err(|e| format!("'{text}' is not an RFC 3339 time ({e})"))?;
    Ok(t.timestamp_millis())
}

/// Formats milliseconds since the Unix epoch as RFC 3339 UTC.
pub fn format_utc_ms(ms: i64) -> String {
    chrono::DateTime::from_timestamp_millis(ms)
        .map(|t| t.to_rfc3339_opts(chrono::SecondsFormat::Millis, true))
        .unwrap_or_else(|| format!("{ms} ms"))
}

/// Builds the vertices and triangles of a plane shape.
pub fn plane_geometry(shape: &PlaneShape) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    match shape {
        PlaneShape::Mesh { vertices, triangles } => (vertices.clone(), triangles.clone()),
        PlaneShape::Grid { min, size, cell, elevation, unevenness, noise_seed, holes } => {
            let nx = (size.x / cell).ceil().max(1.0) as u32;
            let nz = (size.y / cell).ceil().max(1.0) as u32;
            let perlin = Perlin::new(*noise_seed);
            let mut vertices = Vec::with_capacity(((nx + 1) * (nz + 1)) as usize);
            for j in 0..=nz {
                for i in 0..=nx {
                    let x = min.x + size.x * i as f32 / nx as f32;
                    let z = min.y + size.y * j as f32 / nz as f32;
                    let n = perlin.get([x as f64 * 0.23, z as f64 * 0.23]) as f32;
                    vertices.push(Vec3::new(x, elevation + unevenness * n, z));
                }
            }
            let mut triangles = Vec::with_capacity((nx * nz * 2) as usize);
            let idx = |i: u32, j: u32| j * (nx + 1) + i;
            let in_hole = |p: Vec3| holes.iter().any(|h| Vec2::new(p.x, p.z).distance(h.center) < h.radius);
            for j in 0..nz {
                for i in 0..nx {
                    let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
                    // Counter-clockwise seen from above (+Y), so the normal points up.
                    for tri in [[a, d, b], [b, d, c]] {
                        let centre = (vertices[tri[0] as usize] + vertices[tri[1] as usize] + vertices[tri[2] as usize]) / 3.0;
                        if !in_hole(centre) {
                            triangles.push(tri);
                        }
                    }
                }
            }
            (vertices, triangles)
        }
    }
}
