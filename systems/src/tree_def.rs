//! A tree a scene places at the start: the one type shared by scene files and scatters (a
//! leaf module, so `scene` and `scatter` need not import each other).

use glam::Vec3;
use serde::{Deserialize, Serialize};

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
