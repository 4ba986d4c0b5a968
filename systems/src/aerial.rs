//! Aerial photographs in a scene (issue #22): the scene's `aerial` section ([`AerialDef`]: a
//! registered summer and winter pair, their ground resolution and origin, the canopy's layer
//! masks and the crowns file), the crowns read from `crowns.csv` ([`read_crowns`]), and the
//! [`AerialCrown`] component that ties a tree entity to its photographed crown. See
//! `docs/aerial.md`.
//!
//! Reads: the crowns file the scene names (bounded by [`crate::limits`]). Writes: nothing; the
//! crown trees are spawned by `Sim::from_scene` after every other entity, so a scene without an
//! `aerial` section builds the same world as before, and [`AerialCrown`] enters the world hash
//! only where some entity has it (`hash.rs`).
//!
//! Axes: image x is world +X (east) and image y world +Z (south); metres.

use std::path::Path;

use glam::Vec2;
use serde::{Deserialize, Serialize};

use crate::limits::{self, MAX_COORD, RAISE};

/// The scene's `aerial` section: where the photographs lie and how their crowns are drawn.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AerialDef {
    /// The summer photograph: an image file (PNG or TIFF, held in memory; small pairs) or a tile
    /// folder written by `grove aerial tile`, relative to the scene file's folder.
    pub summer: String,
    /// The winter photograph of the same area, registered: the ground texture.
    pub winter: String,
    /// The canopy's layer masks (`grove aerial layers`): an image whose red byte holds one bit
    /// per layer, bit i set where layer i is treetop; without it no canopy is drawn.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layers: Option<String>,
    /// Ground sample distance of the photographs: metres per texel.
    pub gsd_m: f32,
    /// World (X, Z) of the top-left corner of the photographs' texel (0, 0), metres.
    pub origin: Vec2,
    /// The height of the photographed ground, metres (the photograph is draped flat).
    #[serde(default)]
    pub elevation: f32,
    /// `crowns.csv` written by `grove aerial segment`, relative to the scene file's folder: a
    /// tree entity is made at each crown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crowns: Option<String>,
    /// The catalogue model of the crown trees (their pick shape and, near the camera, trunk).
    #[serde(default = "default_model")]
    pub model: String,
    /// Crowns with a smaller equivalent radius are left out as noise, metres.
    #[serde(default = "default_min_radius")]
    pub min_radius_m: f32,
    /// A crown's top height over the ground per metre of its radius.
    #[serde(default = "default_height")]
    pub height_per_radius: f32,
    /// The canopy's layers, 1..=8, between the crown base and the top.
    #[serde(default = "default_layer_count")]
    pub layer_count: u32,
    /// The crowns read from `crowns` by `Scene::load`; not part of the file.
    #[serde(skip)]
    pub crown_list: Vec<CrownDef>,
}

fn default_model() -> String {
    "broadleaf-mesh".into()
}
fn default_min_radius() -> f32 {
    0.5
}
fn default_height() -> f32 {
    3.0
}
fn default_layer_count() -> u32 {
    6
}

/// The most canopy layers (bits of a layer-mask byte).
pub const MAX_LAYERS: u32 = 8;

/// The largest crowns file read, bytes.
pub const MAX_CROWNS_BYTES: u64 = limits::MAX_TABLE_BYTES;

/// One crown of `crowns.csv`, as the scene uses it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrownDef {
    /// The crown's id in the file.
    pub id: u32,
    /// Centroid, metres east of the photograph's left edge.
    pub x_m: f32,
    /// Centroid, metres south of its top edge.
    pub y_m: f32,
    /// Equivalent radius, metres.
    pub radius_m: f32,
}

/// Ties a tree entity to its photographed crown: where the crown was photographed and how tall
/// its layers stand. The canopy is drawn at the entity's current position from the photograph
/// around `photo_centre`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct AerialCrown {
    /// The crown's id in the crowns file.
    pub id: u32,
    /// World (X, Z) of the crown's centre in the photograph, metres.
    pub photo_centre: Vec2,
    /// Equivalent radius, metres.
    pub radius_m: f32,
    /// The crown's base over the tree's foot, metres.
    pub base_m: f32,
    /// The crown's top over the tree's foot, metres.
    pub top_m: f32,
}

impl AerialDef {
    /// Checks the numbers; a one-line message for the first problem.
    pub fn validate(&self) -> Result<(), crate::limits::InvalidScene> {
        self.validate_message().map_err(crate::limits::InvalidScene)
    }

    fn validate_message(&self) -> Result<(), String> {
        for (name, path) in [
            ("summer", Some(&self.summer)),
            ("winter", Some(&self.winter)),
            ("layers", self.layers.as_ref()),
            ("crowns", self.crowns.as_ref()),
        ] {
            if let Some(p) = path {
                if p.is_empty() || p.len() > 512 || Path::new(p).is_absolute() {
                    return Err(format!("aerial: {name} must be a relative path of at most 512 bytes"));
                }
            }
        }
        if !(self.gsd_m.is_finite() && self.gsd_m > 0.0 && self.gsd_m <= 1000.0) {
            return Err(format!("aerial: gsd_m {} must be in (0, 1000] metres per texel", self.gsd_m));
        }
        let nums = [self.origin.x, self.origin.y, self.elevation];
        if !nums.iter().all(|v| v.is_finite() && v.abs() <= MAX_COORD) {
            return Err(format!("aerial: origin and elevation must be finite and within ±{MAX_COORD:e} m"));
        }
        if !(self.min_radius_m.is_finite() && self.min_radius_m >= 0.0 && self.min_radius_m <= 1000.0) {
            return Err(format!("aerial: min_radius_m {} must be in [0, 1000] metres", self.min_radius_m));
        }
        if !(self.height_per_radius.is_finite() && (0.5..=20.0).contains(&self.height_per_radius)) {
            return Err(format!("aerial: height_per_radius {} must be in [0.5, 20]", self.height_per_radius));
        }
        if !(1..=MAX_LAYERS).contains(&self.layer_count) {
            return Err(format!("aerial: layer_count {} must be 1 to {MAX_LAYERS}", self.layer_count));
        }
        if self.model.is_empty() || self.model.len() > 256 {
            return Err("aerial: model must name a catalogue model".into());
        }
        Ok(())
    }

    /// The component of a crown's tree: its photographed centre in world metres, its top at
    /// `height_per_radius` radii and its base 1.2 radii lower (at least a tenth of the top).
    pub fn crown(&self, c: &CrownDef) -> AerialCrown {
        let top = self.height_per_radius * c.radius_m;
        AerialCrown {
            id: c.id,
            photo_centre: self.origin + Vec2::new(c.x_m, c.y_m),
            radius_m: c.radius_m,
            base_m: (top - 1.2 * c.radius_m).max(0.1 * top),
            top_m: top,
        }
    }
}

/// Reads the crowns of a `crowns.csv` (columns by header name: `id`, `x_m`, `y_m`,
/// `radius_m`; others ignored). At most [`MAX_CROWNS_BYTES`] bytes and
/// [`limits::MAX_SCENE_TREES`] rows; every number finite, non-negative and within the
/// coordinate limit. Errors are one line naming the file and the row.
pub fn read_crowns(path: &Path) -> Result<Vec<CrownDef>, crate::limits::InvalidScene> {
    read_crowns_message(path).map_err(crate::limits::InvalidScene)
}

fn read_crowns_message(path: &Path) -> Result<Vec<CrownDef>, String> {
    let name = path.display();
    let text = crate::files::read_text(path, crate::files::Kind::Table).map_err(|e| e.to_string())?;
    parse_crowns(&text).map_err(|e| format!("{name}: {e}"))
}

/// Parses the text of a crowns file (see [`read_crowns`]).
pub fn parse_crowns(text: &str) -> Result<Vec<CrownDef>, crate::limits::InvalidScene> {
    parse_crowns_message(text).map_err(crate::limits::InvalidScene)
}

fn parse_crowns_message(text: &str) -> Result<Vec<CrownDef>, String> {
    let mut lines = text.lines();
    let header: Vec<&str> =
        lines.next().ok_or("empty; a crowns file starts with a header row")?.split(',').map(str::trim).collect();
    let col = |n: &str| header.iter().position(|h| *h == n).ok_or(format!("the header has no '{n}' column"));
    let (ci, cx, cy, cr) = (col("id")?, col("x_m")?, col("y_m")?, col("radius_m")?);
    let mut out = Vec::new();
    for (i, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let row = i + 2;
        if out.len() >= limits::MAX_SCENE_TREES {
            return Err(format!("more than {} crowns ({RAISE})", limits::MAX_SCENE_TREES));
        }
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let num = |c: usize| -> Result<f64, String> {
            let v: f64 = cells
                .get(c)
                .ok_or(format!("row {row}: too few columns"))?
                .parse()
                .map_err(|_| format!("row {row}: not a number"))?;
            if !v.is_finite() || v < 0.0 || v > f64::from(MAX_COORD) {
                return Err(format!("row {row}: a negative, NaN, infinite or too large number"));
            }
            Ok(v)
        };
        let id = num(ci)?;
        if id.fract() != 0.0 || id > f64::from(u32::MAX) {
            return Err(format!("row {row}: the id must be a whole number"));
        }
        out.push(CrownDef { id: id as u32, x_m: num(cx)? as f32, y_m: num(cy)? as f32, radius_m: num(cr)? as f32 });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn def() -> AerialDef {
        AerialDef {
            summer: "summer.png".into(),
            winter: "winter.png".into(),
            layers: None,
            gsd_m: 0.25,
            origin: Vec2::new(-64.0, -32.0),
            elevation: 0.0,
            crowns: None,
            model: default_model(),
            min_radius_m: 0.5,
            height_per_radius: 3.0,
            layer_count: 6,
            crown_list: vec![],
        }
    }

    #[test]
    fn crowns_are_read_by_column_name() {
        let text = "id,x_px,y_px,area_px,radius_px,x_m,y_m,area_m2,radius_m\n1,4,8,50,4,1.0,2.0,3.1,1.5\n2,5,9,60,4,10.5,20.25,3.1,2\n";
        let c = parse_crowns(text).unwrap();
        assert_eq!(
            c,
            vec![
                CrownDef { id: 1, x_m: 1.0, y_m: 2.0, radius_m: 1.5 },
                CrownDef { id: 2, x_m: 10.5, y_m: 20.25, radius_m: 2.0 }
            ]
        );
    }

    #[test]
    fn bad_crowns_are_one_line_errors() {
        for bad in [
            "",
            "id,x_m,y_m\n1,2,3",
            "id,x_m,y_m,radius_m\n1,2,x,3",
            "id,x_m,y_m,radius_m\n1,2,-3,1",
            "id,x_m,y_m,radius_m\n1.5,2,3,1",
            "id,x_m,y_m,radius_m\n1,2",
        ] {
            let e = parse_crowns(bad).unwrap_err().to_string();
            assert!(!e.contains('\n'), "{e}");
        }
    }

    #[test]
    fn a_crown_stands_on_its_photographed_centre() {
        let c = def().crown(&CrownDef { id: 3, x_m: 10.0, y_m: 4.0, radius_m: 2.0 });
        // Centre: origin (-64, -32) + (10, 4). Top 3 × 2 = 6 m, base 6 − 2.4 = 3.6 m.
        assert_eq!(c.photo_centre, Vec2::new(-54.0, -28.0));
        assert!((c.top_m - 6.0).abs() < 1e-6 && (c.base_m - 3.6).abs() < 1e-5, "{c:?}");
    }

    #[test]
    fn fields_are_validated() {
        assert!(def().validate().is_ok());
        let bad = [
            AerialDef { gsd_m: 0.0, ..def() },
            AerialDef { gsd_m: f32::NAN, ..def() },
            AerialDef { origin: Vec2::new(f32::INFINITY, 0.0), ..def() },
            AerialDef { layer_count: 9, ..def() },
            AerialDef { layer_count: 0, ..def() },
            AerialDef { summer: "/etc/passwd".into(), ..def() },
            AerialDef { height_per_radius: 100.0, ..def() },
        ];
        for b in bad {
            let e = b.validate().unwrap_err().to_string();
            assert!(e.starts_with("aerial:") && !e.contains('\n'), "{e}");
        }
    }
}
