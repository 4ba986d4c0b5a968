//! The model catalogue: each tree model's kind and bounds, as plain data.
//!
//! The catalogue is `assets/trees/catalogue.ron`. `grove assets` writes it from the same
//! geometry it writes to the glTF files, and a test recomputes the bounds from the glTF files, so
//! the two never disagree. This module only reads it; it knows nothing about glTF.

use glam::Vec3;
use serde::{Deserialize, Serialize};

crate::message_error::message_error! {
    /// A model reference the catalogue does not hold: one line listing the known models.
    UnknownModel
}

/// The catalogue that ships with grove, embedded at compile time.
pub const DEFAULT_CATALOGUE: &str = include_str!("../../assets/trees/catalogue.ron");

/// Number of models that ship with grove: ids 0 to 7 in every catalogue, before any model of a
/// bank (`assets/trees/catalogue.ron`).
pub const SHIPPED_MODELS: usize = 8;

/// Index of a model in the catalogue (0..8 for the shipped models).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ModelId(pub u8);

/// A model as an input event or a file names it: by its stable name (what grove writes), or by
/// the index of a shipped model (0–7, what recordings made before the model bank wrote, and what
/// the study's synthetic recordings still carry). In JSON a name is a string and an index a
/// number, so both forms read back unchanged.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ModelRef {
    /// A catalogue index: one of the shipped models, which keep ids 0–7 in every catalogue.
    Id(ModelId),
    /// A model's name, e.g. "birch-mesh" or the name a model was added to a bank under.
    Name(String),
}

impl From<ModelId> for ModelRef {
    fn from(id: ModelId) -> ModelRef {
        ModelRef::Id(id)
    }
}

impl From<&str> for ModelRef {
    fn from(name: &str) -> ModelRef {
        ModelRef::Name(name.to_string())
    }
}

impl std::fmt::Display for ModelRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ModelRef::Id(id) => write!(f, "{}", id.0),
            ModelRef::Name(n) => write!(f, "'{n}'"),
        }
    }
}

/// How a model draws its foliage.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ModelKind {
    /// Foliage as real geometry (leaf clusters): the expensive kind.
    Mesh,
    /// Foliage as alpha-clipped textured cards: the cheap kind.
    Billboard,
}

/// One model's description and bounds, in model space (origin at the base of the trunk, +Y up).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelInfo {
    /// The model's index.
    pub id: ModelId,
    /// A short name, also the file stem under `assets/trees/`, e.g. "broadleaf-mesh".
    pub name: String,
    /// The species, e.g. "broadleaf", "conifer", "birch" or "shrub".
    pub species: String,
    /// Mesh or billboard foliage.
    pub kind: ModelKind,
    /// Minimum corner of the axis-aligned bounds, metres. `bounds_min.y` is the lowest point.
    pub bounds_min: Vec3,
    /// Maximum corner of the axis-aligned bounds, metres.
    pub bounds_max: Vec3,
    /// Horizontal radius of the crown around the trunk axis, metres.
    pub crown_radius: f32,
    /// Triangle count of the model, for cost reports.
    pub triangles: u32,
    /// The shape ray picking tests, tighter than the bounds; `None` picks by the bounds.
    #[serde(default)]
    pub pick: Option<PickShape>,
}

/// Number of height bands of a [`PickShape`].
pub const PICK_BANDS: usize = 12;

/// The shape a tree is picked by, in model space (metres, +Y up, origin at the base of the
/// trunk): a stack of [`PICK_BANDS`] vertical cylinders around the Y axis, of equal height from
/// `bottom` to `top`, each as wide as the model is at that height. `grove assets` computes it from
/// the mesh so that every vertex lies inside: the trunk's bands are as thin as the trunk, a
/// conifer's narrow towards the top, a broadleaf's follow its round crown. Ground beside the
/// trunk, under the rim of a crown, is outside, so it can be clicked.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PickShape {
    /// Height of the lowest band's bottom (the model's lowest point), metres.
    pub bottom: f32,
    /// Height of the highest band's top (the model's highest point), metres.
    pub top: f32,
    /// Per band, from the bottom up, the largest horizontal distance of any vertex in it from
    /// the Y axis, metres (0 for an empty band).
    pub radii: [f32; PICK_BANDS],
}

impl PickShape {
    /// The height of one band, metres.
    pub fn band_height(&self) -> f32 {
        (self.top - self.bottom) / PICK_BANDS as f32
    }

    /// The band a height falls in, if any (the top belongs to the highest band).
    pub fn band(&self, y: f32) -> Option<usize> {
        let h = self.band_height();
        if !(h > 0.0) || y < self.bottom || y > self.top {
            return None;
        }
        Some((((y - self.bottom) / h) as usize).min(PICK_BANDS - 1))
    }

    /// Whether a model-space point is inside the shape with every band's radius grown by its
    /// entry in `pads`, metres.
    pub fn contains(&self, p: Vec3, pads: &[f32; PICK_BANDS]) -> bool {
        self.band(p.y).is_some_and(|i| {
            let r = self.radii[i] + pads[i];
            self.radii[i] > 0.0 && p.x * p.x + p.z * p.z <= r * r
        })
    }
}

impl ModelInfo {
    /// Height from the lowest point to the top, metres.
    pub fn height(&self) -> f32 {
        self.bounds_max.y - self.bounds_min.y
    }

    /// The lowest point's height relative to the model origin, metres (usually ≤ 0).
    pub fn lowest_point(&self) -> f32 {
        self.bounds_min.y
    }
}

/// All models, indexed by [`ModelId`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Catalogue {
    /// The models in id order.
    pub models: Vec<ModelInfo>,
}

/// A catalogue that could not be read.
#[derive(Debug, thiserror::Error)]
pub enum CatalogueError {
    /// The RON text did not parse.
    #[error("catalogue: {0}")]
    Parse(String),
    /// The contents are inconsistent.
    #[error("catalogue: {0}")]
    Invalid(String),
}

impl Catalogue {
    /// Parses and checks a catalogue from RON text.
    pub fn from_ron(text: &str) -> Result<Catalogue, CatalogueError> {
        let cat: Catalogue = ron::from_str(text).map_err(|e| CatalogueError::Parse(e.to_string()))?;
        for (i, m) in cat.models.iter().enumerate() {
            if m.id.0 as usize != i {
                return Err(CatalogueError::Invalid(format!("model {} has id {} at position {i}", m.name, m.id.0)));
            }
            if !(m.bounds_min.is_finite() && m.bounds_max.is_finite()) || m.bounds_min.cmpgt(m.bounds_max).any() {
                return Err(CatalogueError::Invalid(format!("model {} has invalid bounds", m.name)));
            }
            if let Some(p) = &m.pick {
                let valid = p.bottom.is_finite()
                    && p.top.is_finite()
                    && p.bottom < p.top
                    && p.radii.iter().all(|r| r.is_finite() && *r >= 0.0);
                if !valid {
                    return Err(CatalogueError::Invalid(format!("model {} has an invalid pick shape", m.name)));
                }
            }
        }
        Ok(cat)
    }

    /// The catalogue embedded in the binary.
    pub fn builtin() -> Catalogue {
        // Parsed once per process: every replayed recording starts from it.
        static BUILTIN: std::sync::OnceLock<Catalogue> = std::sync::OnceLock::new();
        // The embedded file is checked by a unit test, so this cannot fail in a built binary.
        BUILTIN.get_or_init(|| Catalogue::from_ron(DEFAULT_CATALOGUE).expect("embedded catalogue is valid")).clone()
    }

    /// The model with this id, if it exists.
    pub fn get(&self, id: ModelId) -> Option<&ModelInfo> {
        self.models.get(id.0 as usize)
    }

    /// The model with this name, if it exists.
    pub fn by_name(&self, name: &str) -> Option<&ModelInfo> {
        self.models.iter().find(|m| m.name == name)
    }

    /// The id of the model a reference names, or one line that lists the known names. An index
    /// is accepted only for the shipped models (below [`SHIPPED_MODELS`]): added models are
    /// named, since their index depends on which banks are loaded.
    pub fn resolve(&self, model: &ModelRef) -> Result<ModelId, UnknownModel> {
        self.resolve_message(model).map_err(UnknownModel)
    }

    fn resolve_message(&self, model: &ModelRef) -> Result<ModelId, String> {
        match model {
            ModelRef::Id(id) if (id.0 as usize) < SHIPPED_MODELS && self.get(*id).is_some() => Ok(*id),
            ModelRef::Id(id) => Err(format!(
                "unknown model {}: a model index must be one of the shipped models 0 to {}; name other models (known models: {})",
                id.0,
                SHIPPED_MODELS.min(self.len()).saturating_sub(1),
                self.known_names()
            )),
            ModelRef::Name(n) => self.by_name(n).map(|m| m.id).ok_or_else(|| self.unknown_name(n)),
        }
    }

    /// The message for a model name that is not in the catalogue: it lists the known names.
    pub fn unknown_name(&self, name: &str) -> String {
        format!("unknown model '{name}'; known models: {}", self.known_names())
    }

    /// The names of all models, comma-separated, in catalogue order.
    pub fn known_names(&self) -> String {
        self.models.iter().map(|m| m.name.as_str()).collect::<Vec<_>>().join(", ")
    }

    /// Number of models.
    pub fn len(&self) -> usize {
        self.models.len()
    }

    /// Whether the catalogue has no models.
    pub fn is_empty(&self) -> bool {
        self.models.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_catalogue_has_four_mesh_and_four_billboard_models() {
        let cat = Catalogue::from_ron(DEFAULT_CATALOGUE).unwrap();
        assert_eq!(cat.len(), 8);
        assert_eq!(cat.models.iter().filter(|m| m.kind == ModelKind::Mesh).count(), 4);
        assert_eq!(cat.models.iter().filter(|m| m.kind == ModelKind::Billboard).count(), 4);
        for m in &cat.models {
            assert!(m.height() > 0.3, "{} is too small", m.name);
        }
    }

    #[test]
    fn references_resolve_by_name_or_shipped_index_and_unknown_names_list_the_known_ones() {
        let cat = Catalogue::builtin();
        assert_eq!(cat.resolve(&ModelRef::Name("birch-mesh".into())), Ok(ModelId(2)));
        assert_eq!(cat.resolve(&ModelRef::Id(ModelId(7))), Ok(ModelId(7)));
        let e = cat.resolve(&ModelRef::Name("flower".into())).unwrap_err().to_string();
        assert!(
            e.contains("unknown model 'flower'") && e.contains("broadleaf-mesh") && e.contains("shrub-billboard"),
            "{e}"
        );
        assert!(cat.resolve(&ModelRef::Id(ModelId(8))).is_err());
        // JSON: a number is an index, a string a name.
        assert_eq!(serde_json::from_str::<ModelRef>("3").unwrap(), ModelRef::Id(ModelId(3)));
        assert_eq!(serde_json::from_str::<ModelRef>("\"oak\"").unwrap(), ModelRef::Name("oak".into()));
        assert_eq!(serde_json::to_string(&ModelRef::Name("oak".into())).unwrap(), "\"oak\"");
    }

    #[test]
    fn inconsistent_ids_are_rejected() {
        let text = DEFAULT_CATALOGUE.replacen("id: 0", "id: 5", 1);
        assert!(Catalogue::from_ron(&text).is_err());
    }
}
