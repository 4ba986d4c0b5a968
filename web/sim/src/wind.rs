//! The native renderer's wind displacement of tree vertices, computed by its CPU reference
//! (`grove_systems::wind_model`, the twin of `src/render/trees/wind.wgsl`), for pages that
//! displace vertices themselves: the headset page's GLSL (`web/page/draw/wind.mjs`) is held
//! against it by a test.

use glam::{Vec2, Vec3, Vec4};
use grove_systems::wind_model::{displace, WindParams};
use serde::Deserialize;

use crate::error::Error;

/// At most this many vertices per call.
pub const MAX_POINTS: usize = 1 << 16;

/// A tree as the snapshot has it: where it stands and its state in the wind.
#[derive(Debug, Deserialize)]
pub struct TreeIn {
    /// The base of its trunk, metres.
    pub position: [f32; 3],
    /// Its heading, radians.
    pub yaw: f32,
    /// Its uniform scale.
    pub scale: f32,
    /// Its trunk's lean, gain and phase; none for a tree that stands still.
    pub wind: Option<TreeWindIn>,
}

/// A tree's state in the wind (the snapshot's `wind` of a tree).
#[derive(Debug, Deserialize)]
pub struct TreeWindIn {
    /// The trunk's lean, metres per metre (world X, Z).
    pub bend: [f32; 2],
    /// The wind's gain at the tree.
    pub gain: f32,
    /// Its phase, radians.
    pub phase: f32,
}

/// What [`displace_points`] reads: the wind (the snapshot's), the tree, and its model-space
/// vertices, each `[x, y, z, height, trunk, branch, phase]` (position and `_WIND` channels).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindIn {
    /// The snapshot's wind.
    pub wind: WindParams,
    /// The tree.
    pub tree: TreeIn,
    /// The vertices.
    pub points: Vec<[f32; 7]>,
}

fn rotate_y(v: Vec3, yaw: f32) -> Vec3 {
    let (s, c) = yaw.sin_cos();
    Vec3::new(c * v.x + s * v.z, v.y, -s * v.x + c * v.z)
}

/// Each vertex's world position as the native renderer's `world_position` (trees.wgsl) places
/// and displaces it, metres.
pub fn displace_points(json: &str) -> Result<Vec<[f32; 3]>, Error> {
    let input: WindIn = serde_json::from_str(json).map_err(|e| Error::input("wind", e))?;
    if input.points.len() > MAX_POINTS {
        return Err(Error::input("wind", format!("{} points; at most {MAX_POINTS} a call", input.points.len())));
    }
    let t = &input.tree;
    let (bend, gain, phase) = t.wind.as_ref().map_or((Vec2::ZERO, 0.0, 0.0), |w| (Vec2::from(w.bend), w.gain, w.phase));
    let origin = Vec3::from(t.position);
    Ok(input
        .points
        .iter()
        .map(|p| {
            let v0 = origin + rotate_y(Vec3::new(p[0], p[1], p[2]) * t.scale, t.yaw);
            let ch = Vec4::new(p[3] * t.scale, p[4] * t.scale, p[5] * t.scale, p[6]);
            displace(input.wind.model, v0, ch, bend, gain, phase, &input.wind).to_array()
        })
        .collect())
}
