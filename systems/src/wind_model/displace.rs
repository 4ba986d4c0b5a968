//! The per-vertex displacement of both wind models and the bound on how far they move a
//! vertex ([`max_sway`]).

use glam::{Vec2, Vec3, Vec4};
use serde::{Deserialize, Serialize};

use super::{INV_TAU, Wind, WindModel, WindParams, max_bend, noise_at, noise01, wave};

/// Noise-displacement model: `v0 + d · s · w · (noise(density · v0, t) − 0.5)`.
///
/// `v0` is the rest position in world space, `w` the per-vertex weight (0 at the attachment,
/// growing outward, metres), `s` the effective strength (dimensionless), `dir` the horizontal
/// wind direction (world X, Z), `density` per metre, `speed` the field's drift in m/s, `t`
/// seconds. The displacement is horizontal, along the wind, at most `0.5 × |s| × |w|` long.
/// WGSL: `wind_displace_noise`.
pub fn displace_noise(v0: Vec3, w: f32, s: f32, dir: Vec2, density: f32, speed: f32, t: f32) -> Vec3 {
    let n = noise_at(v0, dir, density, speed, t);
    let k = s * w * (n - 0.5);
    Vec3::new(v0.x + dir.x * k, v0.y, v0.z + dir.y * k)
}

/// Hierarchical model: the rest position `v0` (world space) moved by trunk lean, branch bob and
/// leaf flutter.
///
/// - `ch` is the `_WIND` channel vector in world metres: `x` height to root, `y` distance to
///   trunk, `z` distance to branch (multiply the asset's values by the instance scale), `w` the
///   branch's random phase in [0, 1].
/// - `bend` is the tree's lean from the CPU ([`crate::components::WindState::bend`]), metres per
///   metre, world X and Z.
/// - `gain` is the tree's gain ([`crate::components::WindState::gain`]) and `tree_phase` its
///   phase in radians ([`crate::components::WindState::phase`]).
///
/// With `s = strength × gust × gain`, `d` the wind direction and `φ = ch.w + tree_phase / 2π`:
///
/// - trunk: `(bend.x, 0, bend.y) × h² / trunk_stiffness`;
/// - branch: `(0.4 d.x, 1, 0.4 d.z) × s × r² / branch_stiffness × sin 2π(branch_frequency t + φ)`;
/// - leaves: `s × leaf_flutter × b × (sin 2π(f t + φ), sin 2π(1.37 f t + φ + 0.25),
///   sin 2π(1.71 f t + φ + 0.5))` with `f = leaf_frequency`.
///
/// WGSL: `wind_displace_hierarchical`.
pub fn displace_hierarchical(v0: Vec3, ch: Vec4, bend: Vec2, gain: f32, tree_phase: f32, p: &WindParams) -> Vec3 {
    let (h, r, b) = (ch.x, ch.y, ch.z);
    let phi = ch.w + tree_phase * INV_TAU;
    let s = p.strength * p.gust * gain;
    let t = p.time;
    // The trunk leans with the CPU-driven bend, growing with the square of the height.
    let lean = h * h / p.trunk_stiffness;
    let trunk = Vec3::new(bend.x * lean, 0.0, bend.y * lean);
    // Branches bob, mostly vertically, with the square of their distance to the trunk.
    let bob = s * (r * r / p.branch_stiffness) * wave(p.branch_frequency * t + phi);
    let branch = Vec3::new(0.4 * p.direction[0] * bob, bob, 0.4 * p.direction[1] * bob);
    // Leaves flutter in all three axes, in proportion to their distance to the branch.
    let a = s * p.leaf_flutter * b;
    let f = p.leaf_frequency;
    let leaf =
        Vec3::new(a * wave(f * t + phi), a * wave(1.37 * f * t + phi + 0.25), a * wave(1.71 * f * t + phi + 0.5));
    v0 + trunk + branch + leaf
}

/// Either model, chosen by `model` (a [`WindModel::code`]; pass `p.model` for the global choice
/// or another code for a per-model override). The noise model's weight is `ch.x + ch.y` (height
/// to root plus distance to trunk) and its strength `strength × gust × gain × noise_amplitude`.
/// WGSL: `wind_displace`.
pub fn displace(model: u32, v0: Vec3, ch: Vec4, bend: Vec2, gain: f32, tree_phase: f32, p: &WindParams) -> Vec3 {
    if model == 0 {
        let s = p.strength * p.gust * gain * p.noise_amplitude;
        displace_noise(v0, ch.x + ch.y, s, Vec2::new(p.direction[0], p.direction[1]), p.density, p.noise_speed, p.time)
    } else {
        displace_hierarchical(v0, ch, bend, gain, tree_phase, p)
    }
}

/// The per-tree wind gain at a world position, in [0.5, 1.5]: `0.5 + noise01` of the horizontal
/// position times `density` (at height 0.5 lattice units, off the lattice's zero plane), so that
/// neighbouring trees sway differently. Deterministic to the bit (no `sin`, no tables).
pub fn position_gain(position: Vec3, density: f32) -> f32 {
    // A minimum spatial frequency keeps trees apart even in a scene with density 0.
    let k = density.max(0.05);
    0.5 + noise01(Vec3::new(position.x * k, 0.5, position.z * k))
}

/// The largest extents of a tree's `_WIND` channels, world metres (already scaled).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SwayExtent {
    /// Largest height to root.
    pub height: f32,
    /// Largest distance to the trunk.
    pub trunk_distance: f32,
    /// Largest distance to a branch.
    pub branch_distance: f32,
}

impl SwayExtent {
    /// A conservative extent from a model's height and crown radius and the instance's scale:
    /// height to root ≤ height, distances to trunk and branch ≤ crown radius.
    pub fn from_bounds(height: f32, crown_radius: f32, scale: f32) -> SwayExtent {
        SwayExtent {
            height: height * scale,
            trunk_distance: crown_radius * scale,
            branch_distance: crown_radius * scale,
        }
    }
}

/// The largest gust factor magnitude the wind's gust function can reach: `|average| + |strength|`.
pub fn max_gust(wind: &Wind) -> f32 {
    wind.gust.average.abs() + wind.gust.strength.abs()
}

/// The largest distance, metres, that the per-vertex function of `model` can move any vertex of
/// a tree with channel extents `extent`, at any time, for this wind (any gust phase, any tree
/// position and phase). Bounds for ray casting and snapping grow by this much, so that they
/// contain the swaying tree and do not change as it sways.
///
/// With `S = strength × max_gust × 1.5` (1.5 = the largest [`position_gain`]):
/// - noise: `0.5 × S × noise_amplitude × (height + trunk_distance)`;
/// - hierarchical: `max_bend × height² / trunk_stiffness + √1.16 × S × trunk_distance² /
///   branch_stiffness + √3 × S × leaf_flutter × branch_distance`, where `max_bend` is
///   [`max_bend`].
pub fn max_sway(wind: &Wind, model: WindModel, extent: SwayExtent) -> f32 {
    let r = &wind.response;
    let s = wind.strength.abs() * max_gust(wind) * 1.5;
    let e = extent;
    let bound = match model {
        WindModel::Noise => 0.5 * s * r.noise_amplitude.abs() * (e.height.abs() + e.trunk_distance.abs()),
        WindModel::Hierarchical => {
            let trunk = max_bend(wind) * e.height * e.height / r.trunk_stiffness;
            let branch = 1.16f32.sqrt() * s * e.trunk_distance * e.trunk_distance / r.branch_stiffness;
            let leaf = 3f32.sqrt() * s * r.leaf_flutter.abs() * e.branch_distance.abs();
            trunk + branch + leaf
        }
    };
    // A relative margin of 1e-4 covers the rounding of f32 and of the GPU's sine.
    bound * 1.0001
}
