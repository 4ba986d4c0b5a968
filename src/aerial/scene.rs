//! A grove scene from the crowns of a segmented pair: a ground plane of the photographed size
//! and a deciduous tree at each crown.
//!
//! The photograph's top-left corner is north-west: image x (east) is world +X, image y (south)
//! is world +Z, and the image centre is the world origin. Each crown becomes a tree of the
//! catalogue's deciduous species (broadleaf, birch, shrub) whose crown radius is closest to
//! the crown's equivalent radius (on a log scale), scaled to match it; crowns smaller than a
//! minimum radius are left out as noise. Headings follow the golden angle by crown id, so the
//! scene is the same every time.

use glam::{Vec2, Vec3};
use grove_systems::catalogue::{Catalogue, ModelKind};
use grove_systems::scene::{CameraDef, PlaneDef, PlaneShape, Scene, SunDef, TreeDef, WindDef};

use super::AerialError;
use super::crowns::Crown;

/// The smallest and largest scale given to a tree.
pub const SCALE_RANGE: (f32, f32) = (0.3, 3.0);

/// Choices for the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneOptions {
    /// The scene's name.
    pub name: String,
    /// Photographed width and depth, metres.
    pub size_m: (f64, f64),
    /// Crowns with a smaller equivalent radius are left out, metres.
    pub min_radius_m: f64,
    /// Billboard (cheap) or mesh models.
    pub kind: ModelKind,
    /// Latitude and longitude of the site, degrees, and the UTC time of the sun.
    pub sun: (f64, f64, String),
}

/// The scene and how many crowns were left out as too small.
pub fn scene_from_crowns(crowns: &[Crown], opts: &SceneOptions) -> Result<(Scene, usize), AerialError> {
    let (w, d) = opts.size_m;
    if !(w.is_finite() && d.is_finite() && w > 0.0 && d > 0.0) {
        return Err(AerialError::Area { width: w, depth: d });
    }
    let catalogue = Catalogue::builtin();
    let models: Vec<_> = catalogue
        .models
        .iter()
        .filter(|m| {
            m.kind == opts.kind && matches!(m.species.as_str(), "broadleaf" | "birch" | "shrub") && m.crown_radius > 0.0
        })
        .collect();
    if models.is_empty() {
        return Err(AerialError::NoModel);
    }
    let mut trees = Vec::new();
    let mut skipped = 0;
    for c in crowns {
        if c.radius_m < opts.min_radius_m {
            skipped += 1;
            continue;
        }
        let r = c.radius_m as f32;
        let model = models
            .iter()
            .min_by(|a, b| (r / a.crown_radius).ln().abs().total_cmp(&(r / b.crown_radius).ln().abs()))
            .expect("at least one model");
        let scale = (r / model.crown_radius).clamp(SCALE_RANGE.0, SCALE_RANGE.1);
        let x = (c.x_m - w / 2.0) as f32;
        let z = (c.y_m - d / 2.0) as f32;
        trees.push(TreeDef {
            model: model.name.clone(),
            position: Vec3::new(x, 0.0, z),
            yaw_deg: (c.id as f32 * 137.507_76).rem_euclid(360.0),
            scale,
            on_ground: true,
        });
    }
    let (wf, df) = (w as f32, d as f32);
    // At most about 200 × 200 grid cells, however large the photograph.
    let cell = (wf.max(df) / 200.0).max(1.0);
    let scene = Scene {
        name: opts.name.clone(),
        planes: vec![PlaneDef {
            name: "ground".into(),
            shape: PlaneShape::Grid {
                min: Vec2::new(-wf / 2.0, -df / 2.0),
                size: Vec2::new(wf, df),
                cell,
                elevation: 0.0,
                unevenness: 0.0,
                noise_seed: 0,
                holes: Vec::new(),
            },
        }],
        sun: SunDef { latitude_deg: opts.sun.0, longitude_deg: opts.sun.1, utc: opts.sun.2.clone(), time_rate: 0.0 },
        wind: WindDef {
            direction: Vec3::new(1.0, 0.0, 0.4),
            strength: 0.3,
            density: 0.15,
            gust_average: 0.6,
            gust_strength: 0.3,
            gust_frequency: 0.2,
            ..WindDef::default()
        },
        trees,
        // From the south, above the southern edge, looking at the centre.
        camera: CameraDef { position: Vec3::new(0.0, 0.35 * wf.max(df), 0.6 * df), ..CameraDef::default() },
        ..Scene::default()
    };
    scene.validate().map_err(AerialError::Scene)?;
    Ok((scene, skipped))
}

/// The scene as RON text with a header comment; within the scene size limit, parsed back and
/// checked before it is returned.
pub fn scene_text(scene: &Scene, source: &str) -> Result<String, AerialError> {
    let limit = grove_systems::limits::MAX_SCENE_BYTES;
    let too_big = |bytes: String| AerialError::SceneTooBig { trees: scene.trees.len(), bytes };
    // A large scene is measured on a sample of its trees first, so that one far over the limit
    // is refused without writing out and reading back all of it.
    const SAMPLE: usize = 256;
    if scene.trees.len() > 4 * SAMPLE {
        let pretty = |trees: usize| {
            let part = Scene { trees: scene.trees[..trees].to_vec(), ..scene.clone() };
            ron::ser::to_string_pretty(&part, ron::ser::PrettyConfig::default())
                .map(|t| t.len())
                .map_err(AerialError::Ron)
        };
        let (none, some) = (pretty(0)?, pretty(SAMPLE)?);
        let estimate = none + (some - none) * scene.trees.len() / SAMPLE;
        if estimate as u64 > limit + limit / 4 {
            return Err(too_big(format!("about {estimate}")));
        }
    }
    let body = ron::ser::to_string_pretty(scene, ron::ser::PrettyConfig::default()).map_err(AerialError::Ron)?;
    let text = format!(
        "// Written by `grove aerial scene` from {source}: a ground plane of the photographed size and a tree at\n\
         // each treetop crown. Units: metres, degrees where a name ends in _deg. Axes: +Y up, -Z north, +X east.\n\
         // The fields are documented in docs/scenes.md.\n{body}\n"
    );
    // What is written must load in every command that takes a scene: the same size limit, then
    // the same checks.
    if text.len() as u64 > limit {
        return Err(too_big(text.len().to_string()));
    }
    Scene::parse(&text, "generated scene").map_err(AerialError::SceneText)?;
    Ok(text)
}
