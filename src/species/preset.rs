//! Species presets: the named numbers of a Weber–Penn tree (`assets/species/*.ron`, described in
//! `docs/species.md`), read with serde and RON (unknown fields refused) and checked field by field
//! against the ranges stated once here, in `check`.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::SpeciesError;

/// The distribution of first-level branches along the trunk and their lengths (Weber and Penn's
/// shape ratios).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
pub enum Shape {
    /// Longest branches at the bottom.
    Conical,
    /// Longest in the middle, round.
    Spherical,
    /// Longest low, rounded top.
    Hemispherical,
    /// All the same length.
    Cylindrical,
    /// Slightly longer at the bottom.
    TaperedCylindrical,
    /// Longest at 70 % of the crown's height.
    Flame,
    /// Longest at the top.
    InverseConical,
    /// A flame that never reaches zero.
    TendFlame,
    /// The pruning envelope's own shape.
    Envelope,
}

/// The outline of the leaf image.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
pub enum LeafShape {
    /// A pointed ellipse (beech, birch).
    Oval,
    /// Rounded lobes along the edge (oak).
    Lobed,
    /// Single needles all round a twig (spruce); a card is a shoot.
    Needles,
    /// Needles in pairs from one sheath, in tufts at the shoots' ends (pine); a card is a tuft.
    NeedlePairs,
}

/// The pattern of the bark texture.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
pub enum BarkStyle {
    /// Deep vertical ridges (oak, pine).
    Ridged,
    /// Smooth, faintly mottled (beech, shrubs).
    Smooth,
    /// White with dark horizontal lenticels (birch).
    Birch,
    /// Reddish plates (spruce).
    Plated,
}

/// One level of stems (0 the trunk, 1 its branches, …).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Level {
    /// Length: the trunk's as a fraction of `height`, a branch's as a fraction of its parent's.
    pub length: f32,
    /// Random variation of `length` (±).
    pub length_v: f32,
    /// How much the radius narrows from base to tip (0 none, 1 to a point).
    pub taper: f32,
    /// Splits (clones) per segment, fractions carried over.
    pub seg_splits: f32,
    /// Angle between a split's clones, degrees.
    pub split_angle_deg: f32,
    /// Its random variation, degrees (±).
    pub split_angle_v_deg: f32,
    /// Segments per stem.
    pub curve_res: u32,
    /// Total bend of a stem, degrees.
    pub curve_deg: f32,
    /// Bend of the stem's second half (0: the whole stem bends by `curve_deg`), degrees.
    pub curve_back_deg: f32,
    /// Random bend per stem, degrees (±, spread over the segments).
    pub curve_v_deg: f32,
    /// Angle between a stem and its parent, degrees.
    pub down_angle_deg: f32,
    /// Its variation, degrees: ± at random, or, negative, the angle steepening towards the
    /// parent's tip.
    pub down_angle_v_deg: f32,
    /// Turn about the parent from one stem to the next, degrees (negative: alternate sides, 180°).
    pub rotate_deg: f32,
    /// Its random variation, degrees (±).
    pub rotate_v_deg: f32,
    /// Stems of this level on each parent stem (unused on level 0).
    pub branches: f32,
    /// Whether the stems of this level grow level, to either side of their parent in the
    /// horizontal plane (a pine's shoots forming flat plates); `down_angle_deg` is then the angle
    /// from the parent's heading in that plane.
    #[serde(default)]
    pub flat: bool,
}

/// A species preset.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Preset {
    /// Distribution of first-level branch lengths along the trunk.
    pub shape: Shape,
    /// The tree's scale, metres (the trunk is `levels[0].length` of it).
    pub height: f32,
    /// Random variation of `height`, metres (±).
    pub height_v: f32,
    /// The bare part of the trunk below the crown, fraction of the height.
    pub base_size: f32,
    /// Extra stems from the root (a shrub), splayed by `levels[0].split_angle_deg`.
    pub base_splits: u32,
    /// Trunk radius as a fraction of the trunk's length.
    pub ratio: f32,
    /// How fast a child's radius falls with its length relative to its parent's.
    pub ratio_power: f32,
    /// Widening of the trunk's base (0 none).
    pub flare: f32,
    /// Lobes around the trunk's section.
    pub lobes: u32,
    /// Depth of the lobes, fraction of the radius.
    pub lobe_depth: f32,
    /// Bend of stems of level 2 and deeper towards the sky (negative: towards the ground).
    pub attraction_up: f32,
    /// How much branches outside the envelope are cut back (0 none, 1 to the envelope).
    pub prune_ratio: f32,
    /// The envelope's widest radius, fraction of the height.
    pub prune_width: f32,
    /// Where the envelope is widest, fraction of the crown's height from its base.
    pub prune_width_peak: f32,
    /// Curvature of the envelope below the peak.
    pub prune_power_low: f32,
    /// Curvature of the envelope above the peak.
    pub prune_power_high: f32,
    /// Leaves (or shoot cards) on each stem of the last level.
    pub leaves: f32,
    /// Leaf outline.
    pub leaf_shape: LeafShape,
    /// One leaf's (or needle's) length, stalk included, metres.
    pub leaf_scale: f32,
    /// The botanical range of the leaf's (or needle's) length, centimetres, lowest first: the
    /// median leaf drawn in the model of level of detail 1 falls in it.
    pub leaf_length_cm: [f32; 2],
    /// Where that range is from.
    pub leaf_source: String,
    /// Leaves (or needles, or pairs) on one card of level of detail 0: 1, each leaf its own card.
    pub card_leaves: u32,
    /// Leaves (or needles, or pairs) on one card of levels 1 and 2 (a spray, at the same leaf
    /// size): level 1 keeps `card_leaves / spray_leaves` of the cards of level 0.
    pub spray_leaves: u32,
    /// Leaf width as a fraction of its length.
    pub leaf_scale_x: f32,
    /// Angle between a leaf and its stem, degrees.
    pub leaf_down_angle_deg: f32,
    /// Its random variation, degrees (±).
    pub leaf_down_angle_v_deg: f32,
    /// Turn about the stem from one leaf to the next, degrees (± 30 at random).
    pub leaf_rotate_deg: f32,
    /// How much leaves turn their faces up towards the light (0 none, 1 flat).
    pub leaf_bend: f32,
    /// Leaf colour of the texture, sRGB 0..1.
    pub leaf_colour: [f32; 3],
    /// Per-leaf colour variation (0 none).
    pub leaf_colour_v: f32,
    /// The share of each last-level stem's leaves gathered in a clump at its tip (0: spread
    /// evenly along it, the default).
    #[serde(default)]
    pub leaf_clumps: f32,
    /// A clump's radius, leaf lengths (with `leaf_clumps` above 0).
    #[serde(default = "default_clump_radius")]
    pub clump_radius: f32,
    /// Colour variation from one clump to the next (0 none, the default), on top of each leaf's.
    #[serde(default)]
    pub clump_colour_v: f32,
    /// Bark pattern.
    pub bark_style: BarkStyle,
    /// Mean bark colour of the texture, sRGB 0..1.
    pub bark_colour: [f32; 3],
    /// The bark's colour high on the tree (a Scots pine's orange-red upper trunk), sRGB 0..1,
    /// reached at `upper_bark_from` of the height and above (none: `bark_colour` throughout).
    #[serde(default)]
    pub upper_bark_colour: Option<[f32; 3]>,
    /// Where the upper bark's colour is reached, fraction of the height (it blends in over the
    /// fifth of the height below).
    #[serde(default)]
    pub upper_bark_from: f32,
    /// Fallen leaves on the ground under the crown, out to this share of the crown's radius
    /// (0: none).
    #[serde(default)]
    pub litter: f32,
    /// Darkening of the crown's inside by ambient occlusion (0 none, 1 black at the centre).
    pub ao: f32,
    /// The stem levels, trunk first (1 to 4).
    pub levels: Vec<Level>,
}

fn default_clump_radius() -> f32 {
    1.5
}

/// Why a preset's numbers are refused: the first field out of its range.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InvalidPreset {
    /// A number out of its range: the field, the value, the range and the unit.
    #[error("{field} = {value} is out of range; allowed {lo} to {hi}{}", if unit.is_empty() { String::new() } else { format!(" ({unit})") })]
    OutOfRange {
        /// The field, as the preset names it (`levels[1].length`).
        field: String,
        /// The value given.
        value: f32,
        /// The smallest allowed value.
        lo: f32,
        /// The largest allowed value.
        hi: f32,
        /// The unit, or empty.
        unit: &'static str,
    },
    /// A `levels` list of the wrong length.
    #[error("levels has {0} entries; allowed 1 to 4")]
    Levels(usize),
}

/// Keeps the first number out of its range.
fn range(errs: &mut Option<InvalidPreset>, field: &str, v: f32, lo: f32, hi: f32, unit: &'static str) {
    if errs.is_none() && !(v.is_finite() && v >= lo && v <= hi) {
        *errs = Some(InvalidPreset::OutOfRange { field: field.to_string(), value: v, lo, hi, unit });
    }
}

impl Preset {
    /// The first field out of its range, as "field = value is out of range; allowed lo to hi".
    pub fn check(&self) -> Result<(), InvalidPreset> {
        let mut e = None;
        let r = &mut e;
        range(r, "height", self.height, 0.3, 60.0, "metres");
        range(r, "height_v", self.height_v, 0.0, self.height * 0.5, "metres, at most half the height");
        range(r, "base_size", self.base_size, 0.0, 0.95, "fraction of the height");
        range(r, "base_splits", self.base_splits as f32, 0.0, 12.0, "stems");
        range(r, "ratio", self.ratio, 0.002, 0.1, "radius per length");
        range(r, "ratio_power", self.ratio_power, 0.0, 5.0, "");
        range(r, "flare", self.flare, 0.0, 3.0, "");
        range(r, "lobes", self.lobes as f32, 0.0, 12.0, "");
        range(r, "lobe_depth", self.lobe_depth, 0.0, 0.5, "fraction of the radius");
        range(r, "attraction_up", self.attraction_up, -3.0, 3.0, "");
        range(r, "prune_ratio", self.prune_ratio, 0.0, 1.0, "");
        range(r, "prune_width", self.prune_width, 0.05, 2.0, "fraction of the height");
        range(r, "prune_width_peak", self.prune_width_peak, 0.0, 1.0, "fraction of the crown");
        range(r, "prune_power_low", self.prune_power_low, 0.0, 5.0, "");
        range(r, "prune_power_high", self.prune_power_high, 0.0, 5.0, "");
        range(r, "leaves", self.leaves, 0.0, 200.0, "per stem");
        range(r, "leaf_scale", self.leaf_scale, 0.01, 2.0, "metres");
        range(r, "leaf_length_cm[0]", self.leaf_length_cm[0], 0.1, 100.0, "centimetres");
        range(
            r,
            "leaf_length_cm[1]",
            self.leaf_length_cm[1],
            self.leaf_length_cm[0],
            100.0,
            "centimetres, at least the lowest",
        );
        range(r, "leaf_scale_x", self.leaf_scale_x, 0.02, 2.0, "fraction of the length");
        range(r, "card_leaves", self.card_leaves as f32, 1.0, 200.0, "leaves per card");
        range(
            r,
            "spray_leaves",
            self.spray_leaves as f32,
            self.card_leaves as f32,
            2000.0,
            "leaves per card, at least card_leaves",
        );
        range(r, "leaf_down_angle_deg", self.leaf_down_angle_deg, 0.0, 180.0, "degrees");
        range(r, "leaf_down_angle_v_deg", self.leaf_down_angle_v_deg, 0.0, 90.0, "degrees");
        range(r, "leaf_rotate_deg", self.leaf_rotate_deg, 0.0, 360.0, "degrees");
        range(r, "leaf_bend", self.leaf_bend, 0.0, 1.0, "");
        for (i, c) in self.leaf_colour.iter().enumerate() {
            range(r, &format!("leaf_colour[{i}]"), *c, 0.0, 1.0, "sRGB");
        }
        range(r, "leaf_colour_v", self.leaf_colour_v, 0.0, 0.5, "");
        range(r, "leaf_clumps", self.leaf_clumps, 0.0, 1.0, "share of the leaves");
        range(r, "clump_radius", self.clump_radius, 0.5, 10.0, "leaf lengths");
        range(r, "clump_colour_v", self.clump_colour_v, 0.0, 0.5, "");
        for (i, c) in self.bark_colour.iter().enumerate() {
            range(r, &format!("bark_colour[{i}]"), *c, 0.0, 1.0, "sRGB");
        }
        if let Some(c) = self.upper_bark_colour {
            for (i, c) in c.iter().enumerate() {
                range(r, &format!("upper_bark_colour[{i}]"), *c, 0.0, 1.0, "sRGB");
            }
        }
        range(r, "upper_bark_from", self.upper_bark_from, 0.0, 1.0, "fraction of the height");
        range(r, "litter", self.litter, 0.0, 2.0, "share of the crown's radius");
        range(r, "ao", self.ao, 0.0, 1.0, "");
        if e.is_none() && !(1..=4).contains(&self.levels.len()) {
            e = Some(InvalidPreset::Levels(self.levels.len()));
        }
        for (i, l) in self.levels.iter().enumerate() {
            let r = &mut e;
            let f = |n: &str| format!("levels[{i}].{n}");
            range(r, &f("length"), l.length, 0.01, 1.5, "fraction");
            range(r, &f("length_v"), l.length_v, 0.0, l.length.min(1.0) * 0.9, "fraction, under the length");
            range(r, &f("taper"), l.taper, 0.0, 1.0, "");
            range(r, &f("seg_splits"), l.seg_splits, 0.0, 2.0, "per segment");
            range(r, &f("split_angle_deg"), l.split_angle_deg, 0.0, 90.0, "degrees");
            range(r, &f("split_angle_v_deg"), l.split_angle_v_deg, 0.0, 45.0, "degrees");
            range(r, &f("curve_res"), l.curve_res as f32, 1.0, 16.0, "segments");
            range(r, &f("curve_deg"), l.curve_deg, -360.0, 360.0, "degrees");
            range(r, &f("curve_back_deg"), l.curve_back_deg, -360.0, 360.0, "degrees");
            range(r, &f("curve_v_deg"), l.curve_v_deg, 0.0, 360.0, "degrees");
            range(r, &f("down_angle_deg"), l.down_angle_deg, -180.0, 180.0, "degrees");
            range(r, &f("down_angle_v_deg"), l.down_angle_v_deg, -180.0, 180.0, "degrees");
            range(r, &f("rotate_deg"), l.rotate_deg, -360.0, 360.0, "degrees");
            range(r, &f("rotate_v_deg"), l.rotate_v_deg, 0.0, 360.0, "degrees");
            range(r, &f("branches"), l.branches, 0.0, if i == 1 { 200.0 } else { 60.0 }, "stems per parent");
        }
        match e {
            Some(m) => Err(m),
            None => Ok(()),
        }
    }

    /// Parses and checks a preset's text; `file` names it in the error.
    pub fn parse(text: &str, file: &str) -> Result<Preset, SpeciesError> {
        let bad =
            |message: String| SpeciesError::Preset { file: file.to_string(), message: message.replace('\n', " ") };
        let p: Preset = ron::from_str(text).map_err(|e| bad(e.to_string()))?;
        p.check().map_err(|e| bad(e.to_string()))?;
        Ok(p)
    }
}

/// The folder of the shipped presets: `species/` in the assets folder (`$GROVE_ASSETS`,
/// `./assets`, or the source tree's).
pub fn preset_dir() -> PathBuf {
    crate::render::default_assets_dir().join("species")
}

/// The names of the shipped presets, sorted.
pub fn preset_names() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(preset_dir())
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "ron"))
                .filter_map(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

/// A preset by name (a file in `assets/species`) or by the path of a `.ron` file; returns the
/// species' name (the file's stem) and the preset.
pub fn load(name_or_path: &str) -> Result<(String, Preset), SpeciesError> {
    let as_path = Path::new(name_or_path);
    let path = if name_or_path.ends_with(".ron") || name_or_path.contains('/') {
        as_path.to_path_buf()
    } else {
        let p = preset_dir().join(format!("{name_or_path}.ron"));
        if !p.is_file() {
            return Err(SpeciesError::Unknown { name: name_or_path.to_string(), known: preset_names().join(", ") });
        }
        p
    };
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    if !grove_systems::bank::valid_name(&name) || name.contains('.') {
        return Err(SpeciesError::BadName(name));
    }
    let text = grove_systems::files::read_text(&path, grove_systems::files::Kind::Index)?;
    Ok((name, Preset::parse(&text, &path.display().to_string())?))
}
