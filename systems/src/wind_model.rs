//! The per-vertex wind models: the CPU reference of `src/render/wind.wgsl`.
//!
//! The renderer displaces every tree vertex on the GPU with the WGSL functions in
//! `src/render/wind.wgsl`. This module holds the same functions in Rust, operation for operation,
//! so that tests can compare the two (to within 1e-4 m) and so that ray casting and snapping can
//! bound the sway ([`max_sway`]) without a GPU.
//!
//! Two models exist ([`WindModel`]):
//!
//! - **Noise displacement** ([`displace_noise`]): `v = v0 + d · s · w · (noise(density · v0, t) − 0.5)`,
//!   where `d` is the horizontal wind direction, `s` the effective strength, `w` the per-vertex weight
//!   (0 at the attachment, growing outward) and `noise` the gradient noise [`noise01`] in [0, 1],
//!   whose field drifts downwind at `noise_speed` metres per second.
//! - **Hierarchical** ([`displace_hierarchical`]): from the asset's `_WIND` channels (height to root,
//!   distance to trunk, distance to branch, branch phase): the trunk leans with the tree's CPU bend,
//!   growing with the square of the height over the trunk stiffness; branches bob with the square
//!   of their distance to the trunk over the branch stiffness; leaves flutter in proportion to their
//!   distance to the branch. Branch and leaf motion are sines whose phase comes from the branch's
//!   random value and the tree's own phase.
//!
//! The noise is classic 3D gradient noise (Perlin's 2002 "improved noise" gradients and fade
//! curve), with the permutation table replaced by an integer hash of the lattice coordinates, so
//! the WGSL version needs no texture and no table. The per-vertex functions use `f32::sin` here
//! and `sin` in WGSL: they are not part of the hashed world state. [`position_gain`] uses the same
//! noise for the per-tree gain, which *is* hashed; it uses only `+ − × floor` and integer
//! operations, so it is bit-exact on every platform.
//!
//! Units: metres, seconds, hertz; `direction` is a horizontal unit vector in world X and Z
//! (+X east, −Z north) pointing where the wind blows to.

use glam::{Vec2, Vec3, Vec4};
use serde::{Deserialize, Serialize};

use crate::components::Wind;

/// 2π, as the WGSL source spells it.
pub const TAU: f32 = 6.283_185_5;
/// 1 / 2π, as the WGSL source spells it.
pub const INV_TAU: f32 = 0.159_154_94;
/// The seed mixed into the lattice hash, as the WGSL source spells it.
pub const NOISE_SEED: u32 = 0x6772_6f76;

/// Which per-vertex wind model displaces a tree's vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WindModel {
    /// `v0 + d · s · w · (noise − 0.5)`: gradient noise drifting downwind.
    Noise,
    /// Trunk lean, branch bob and leaf flutter from the `_WIND` vertex channels.
    #[default]
    Hierarchical,
}

impl WindModel {
    /// The code the shader uses (`WindParams::model`): 0 = noise, 1 = hierarchical.
    pub fn code(self) -> u32 {
        match self {
            WindModel::Noise => 0,
            WindModel::Hierarchical => 1,
        }
    }

    /// The model for a shader code; any code other than 0 is hierarchical, as in WGSL.
    pub fn from_code(code: u32) -> WindModel {
        if code == 0 { WindModel::Noise } else { WindModel::Hierarchical }
    }
}

/// How trees respond to the wind, vertex by vertex: the constants of both per-vertex models.
/// Part of the [`Wind`] component (and of scene files, where every field has a default).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WindResponse {
    /// Noise model: displacement per metre of weight at strength 1 and gust factor 1, metres per
    /// metre (the model's `s` is `strength × gust × gain × noise_amplitude`).
    pub noise_amplitude: f32,
    /// Noise model: how fast the noise field drifts downwind, metres per second.
    pub noise_speed: f32,
    /// Hierarchical model: trunk stiffness, metres. At height `h` the trunk moves by
    /// `bend × h² / trunk_stiffness`; larger is stiffer. Must be positive.
    pub trunk_stiffness: f32,
    /// Hierarchical model: branch stiffness, metres. A point at distance `r` from the trunk bobs
    /// by up to `s × r² / branch_stiffness`; larger is stiffer. Must be positive.
    pub branch_stiffness: f32,
    /// Hierarchical model: branch oscillation frequency, hertz.
    pub branch_frequency: f32,
    /// Hierarchical model: leaf flutter per metre of distance to the branch, at `s = 1`.
    pub leaf_flutter: f32,
    /// Hierarchical model: leaf flutter frequency, hertz.
    pub leaf_frequency: f32,
}

impl Default for WindResponse {
    fn default() -> Self {
        WindResponse {
            noise_amplitude: 0.06,
            noise_speed: 3.0,
            trunk_stiffness: 5.0,
            branch_stiffness: 20.0,
            branch_frequency: 0.7,
            leaf_flutter: 0.08,
            leaf_frequency: 2.5,
        }
    }
}

impl WindResponse {
    /// Checks that every number is finite, the stiffnesses positive and the rest non-negative.
    pub fn validate(&self) -> Result<(), String> {
        let all = [
            self.noise_amplitude,
            self.noise_speed,
            self.trunk_stiffness,
            self.branch_stiffness,
            self.branch_frequency,
            self.leaf_flutter,
            self.leaf_frequency,
        ];
        if all.iter().any(|x| !x.is_finite() || *x < 0.0) {
            return Err("wind response values must be finite and not negative".into());
        }
        if self.trunk_stiffness <= 0.0 || self.branch_stiffness <= 0.0 {
            return Err("wind trunk_stiffness and branch_stiffness must be positive".into());
        }
        Ok(())
    }
}

/// The parameters of the per-vertex wind functions, one uniform for all trees.
///
/// The WGSL struct `WindParams` in `src/render/wind.wgsl` mirrors this one field by field
/// (64 bytes, no implicit padding): upload [`WindParams::to_le_bytes`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[repr(C)]
pub struct WindParams {
    /// Offset 0, `vec2<f32>`: horizontal unit direction the wind blows towards (world X, Z).
    pub direction: [f32; 2],
    /// Offset 8: the wind's base strength ([`Wind::strength`]).
    pub strength: f32,
    /// Offset 12: the current gust factor ([`Wind::current`]).
    pub gust: f32,
    /// Offset 16: spatial frequency of the noise, per metre ([`Wind::density`]).
    pub density: f32,
    /// Offset 20: downwind drift of the noise field, metres per second.
    pub noise_speed: f32,
    /// Offset 24: noise model amplitude ([`WindResponse::noise_amplitude`]).
    pub noise_amplitude: f32,
    /// Offset 28: animation time, seconds (simulated time; f32 keeps millisecond precision for
    /// about 4 hours).
    pub time: f32,
    /// Offset 32: trunk stiffness, metres.
    pub trunk_stiffness: f32,
    /// Offset 36: branch stiffness, metres.
    pub branch_stiffness: f32,
    /// Offset 40: branch frequency, hertz.
    pub branch_frequency: f32,
    /// Offset 44: leaf flutter per metre of distance to the branch.
    pub leaf_flutter: f32,
    /// Offset 48: leaf frequency, hertz.
    pub leaf_frequency: f32,
    /// Offset 52, `u32`: the global model, [`WindModel::code`].
    pub model: u32,
    /// Offsets 56 and 60: padding to 64 bytes (WGSL `pad0`, `pad1`); write zeros.
    pub pad: [u32; 2],
}

impl WindParams {
    /// Size of the uniform in bytes.
    pub const SIZE: usize = 64;

    /// The parameters for a wind at simulated time `time` seconds.
    pub fn from_wind(wind: &Wind, time: f64) -> WindParams {
        let r = &wind.response;
        let d = Vec2::new(wind.direction.x, wind.direction.z).normalize_or(Vec2::X);
        WindParams {
            direction: [d.x, d.y],
            strength: wind.strength,
            gust: wind.current,
            density: wind.density,
            noise_speed: r.noise_speed,
            noise_amplitude: r.noise_amplitude,
            time: time as f32,
            trunk_stiffness: r.trunk_stiffness,
            branch_stiffness: r.branch_stiffness,
            branch_frequency: r.branch_frequency,
            leaf_flutter: r.leaf_flutter,
            leaf_frequency: r.leaf_frequency,
            model: wind.model.code(),
            pad: [0; 2],
        }
    }

    /// The uniform's bytes, little-endian, in the WGSL layout.
    pub fn to_le_bytes(&self) -> [u8; WindParams::SIZE] {
        let words: [u32; 16] = [
            self.direction[0].to_bits(),
            self.direction[1].to_bits(),
            self.strength.to_bits(),
            self.gust.to_bits(),
            self.density.to_bits(),
            self.noise_speed.to_bits(),
            self.noise_amplitude.to_bits(),
            self.time.to_bits(),
            self.trunk_stiffness.to_bits(),
            self.branch_stiffness.to_bits(),
            self.branch_frequency.to_bits(),
            self.leaf_flutter.to_bits(),
            self.leaf_frequency.to_bits(),
            self.model,
            self.pad[0],
            self.pad[1],
        ];
        let mut out = [0u8; WindParams::SIZE];
        for (chunk, w) in out.chunks_exact_mut(4).zip(words) {
            chunk.copy_from_slice(&w.to_le_bytes());
        }
        out
    }

    /// The horizontal wind direction as a 3D vector (Y = 0).
    pub fn direction3(&self) -> Vec3 {
        Vec3::new(self.direction[0], 0.0, self.direction[1])
    }
}

/// A 32-bit integer hash with good avalanche (Wellons' "lowbias32"). WGSL: `wind_hash`.
#[inline]
pub fn hash_u32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// The hash of an integer lattice point; it replaces Perlin's permutation table.
/// WGSL: `wind_lattice_hash`.
#[inline]
pub fn lattice_hash(x: i32, y: i32, z: i32) -> u32 {
    hash_u32((x as u32).wrapping_add(hash_u32((y as u32).wrapping_add(hash_u32((z as u32).wrapping_add(NOISE_SEED))))))
}

/// Perlin's improved-noise gradient: the dot product of one of 12 edge directions (chosen by
/// the low 4 bits of `h`) with the offset `(x, y, z)`. WGSL: `wind_grad`.
#[inline]
pub fn grad(h: u32, x: f32, y: f32, z: f32) -> f32 {
    let h = h & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    let a = if h & 1 == 0 { u } else { -u };
    let b = if h & 2 == 0 { v } else { -v };
    a + b
}

/// Perlin's fade curve `6t⁵ − 15t⁴ + 10t³`. WGSL: `wind_fade`.
#[inline]
pub fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + t * (b - a)
}

/// Classic 3D gradient noise at `p`, roughly in [−1, 1], 0 at every lattice point.
/// WGSL: `wind_perlin3`.
pub fn perlin3(p: Vec3) -> f32 {
    let (fx, fy, fz) = (p.x.floor(), p.y.floor(), p.z.floor());
    let (ix, iy, iz) = (fx as i32, fy as i32, fz as i32);
    let (x, y, z) = (p.x - fx, p.y - fy, p.z - fz);
    let (u, v, w) = (fade(x), fade(y), fade(z));
    let n000 = grad(lattice_hash(ix, iy, iz), x, y, z);
    let n100 = grad(lattice_hash(ix.wrapping_add(1), iy, iz), x - 1.0, y, z);
    let n010 = grad(lattice_hash(ix, iy.wrapping_add(1), iz), x, y - 1.0, z);
    let n110 = grad(lattice_hash(ix.wrapping_add(1), iy.wrapping_add(1), iz), x - 1.0, y - 1.0, z);
    let n001 = grad(lattice_hash(ix, iy, iz.wrapping_add(1)), x, y, z - 1.0);
    let n101 = grad(lattice_hash(ix.wrapping_add(1), iy, iz.wrapping_add(1)), x - 1.0, y, z - 1.0);
    let n011 = grad(lattice_hash(ix, iy.wrapping_add(1), iz.wrapping_add(1)), x, y - 1.0, z - 1.0);
    let n111 = grad(lattice_hash(ix.wrapping_add(1), iy.wrapping_add(1), iz.wrapping_add(1)), x - 1.0, y - 1.0, z - 1.0);
    let x00 = lerp(n000, n100, u);
    let x10 = lerp(n010, n110, u);
    let x01 = lerp(n001, n101, u);
    let x11 = lerp(n011, n111, u);
    let y0 = lerp(x00, x10, v);
    let y1 = lerp(x01, x11, v);
    lerp(y0, y1, w)
}

/// Gradient noise mapped to [0, 1]: `clamp(0.5 + 0.5 × perlin3(p), 0, 1)`. WGSL: `wind_noise01`.
pub fn noise01(p: Vec3) -> f32 {
    (0.5 + 0.5 * perlin3(p)).clamp(0.0, 1.0)
}

/// The model's `noise(density · v0, t)`: the noise field at world point `v0`, drifting downwind
/// along `dir` at `speed` metres per second. WGSL: `wind_noise_at`.
pub fn noise_at(v0: Vec3, dir: Vec2, density: f32, speed: f32, t: f32) -> f32 {
    let drift = speed * t;
    let p = Vec3::new(v0.x - dir.x * drift, v0.y, v0.z - dir.y * drift);
    noise01(Vec3::new(density * p.x, density * p.y, density * p.z))
}

/// A sine of `cycles` full turns, with the argument reduced to [−π, π) first so that the GPU's
/// `sin` is used where it is accurate: `sin(2π × (fract(cycles + 0.5) − 0.5))`. WGSL: `wind_wave`.
#[inline]
pub fn wave(cycles: f32) -> f32 {
    let u = cycles + 0.5;
    let f = u - u.floor();
    (TAU * (f - 0.5)).sin()
}

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
    let leaf = Vec3::new(
        a * wave(f * t + phi),
        a * wave(1.37 * f * t + phi + 0.25),
        a * wave(1.71 * f * t + phi + 0.5),
    );
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
        SwayExtent { height: height * scale, trunk_distance: crown_radius * scale, branch_distance: crown_radius * scale }
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
///   [`crate::systems::wind::max_bend`].
pub fn max_sway(wind: &Wind, model: WindModel, extent: SwayExtent) -> f32 {
    let r = &wind.response;
    let s = wind.strength.abs() * max_gust(wind) * 1.5;
    let e = extent;
    let bound = match model {
        WindModel::Noise => 0.5 * s * r.noise_amplitude.abs() * (e.height.abs() + e.trunk_distance.abs()),
        WindModel::Hierarchical => {
            let trunk = crate::systems::wind::max_bend(wind) * e.height * e.height / r.trunk_stiffness;
            let branch = 1.16f32.sqrt() * s * e.trunk_distance * e.trunk_distance / r.branch_stiffness;
            let leaf = 3f32.sqrt() * s * r.leaf_flutter.abs() * e.branch_distance.abs();
            trunk + branch + leaf
        }
    };
    // A relative margin of 1e-4 covers the rounding of f32 and of the GPU's sine.
    bound * 1.0001
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::Gust;

    fn wind() -> Wind {
        Wind {
            direction: Vec3::new(0.8, 0.0, 0.6),
            strength: 1.3,
            density: 0.2,
            gust: Gust { average: 0.6, strength: 0.4, frequency: 0.2 },
            current: 0.6,
            model: WindModel::Hierarchical,
            response: WindResponse::default(),
        }
    }

    /// A small deterministic sequence in [0, 1) for test inputs.
    fn seq(i: u32, salt: u32) -> f32 {
        (hash_u32(i.wrapping_mul(2654435761) ^ salt) >> 8) as f32 / (1u32 << 24) as f32
    }

    #[test]
    fn noise_is_zero_on_the_lattice_and_stays_in_range() {
        for i in 0..50 {
            let p = Vec3::new(i as f32 - 25.0, (i * 7 % 11) as f32, (i * 3 % 5) as f32 - 2.0);
            assert_eq!(perlin3(p), 0.0, "lattice point {p}");
        }
        let (mut lo, mut hi) = (f32::MAX, f32::MIN);
        for i in 0..20_000 {
            let p = Vec3::new(seq(i, 1) * 40.0 - 20.0, seq(i, 2) * 40.0 - 20.0, seq(i, 3) * 40.0 - 20.0);
            let n = perlin3(p);
            lo = lo.min(n);
            hi = hi.max(n);
            assert!((0.0..=1.0).contains(&noise01(p)));
        }
        // Gradient noise should use most of its range, symmetric about zero.
        assert!(lo < -0.6 && hi > 0.6, "range {lo}..{hi}");
        assert!(lo > -1.1 && hi < 1.1, "range {lo}..{hi}");
    }

    #[test]
    fn noise_is_continuous() {
        for i in 0..2000 {
            let p = Vec3::new(seq(i, 4) * 10.0, seq(i, 5) * 10.0, seq(i, 6) * 10.0);
            let q = p + Vec3::splat(1e-3);
            // The gradient of improved noise is bounded by a few units, so 1e-3 apart means close.
            assert!((perlin3(p) - perlin3(q)).abs() < 0.02, "jump at {p}");
        }
    }

    #[test]
    fn wave_matches_sine_of_full_turns() {
        for i in 0..1000 {
            let c = seq(i, 7) * 200.0 - 100.0;
            let exact = (std::f64::consts::TAU * c as f64).sin() as f32;
            assert!((wave(c) - exact).abs() < 1e-4, "wave({c}) = {} vs {exact}", wave(c));
        }
    }

    #[test]
    fn noise_displacement_is_along_the_wind_and_zero_at_the_attachment() {
        let dir = Vec2::new(0.6, -0.8);
        let v0 = Vec3::new(1.0, 2.0, 3.0);
        assert_eq!(displace_noise(v0, 0.0, 2.0, dir, 0.3, 3.0, 5.0), v0);
        let mut moved = 0;
        for i in 0..200 {
            let t = i as f32 * 0.1;
            let v = displace_noise(v0, 4.0, 0.5, dir, 0.3, 3.0, t);
            let dv = v - v0;
            assert_eq!(dv.y, 0.0);
            // Parallel to the wind: the cross product with (dir.x, dir.y) vanishes.
            assert!((dv.x * dir.y - dv.z * dir.x).abs() < 1e-6);
            assert!(dv.length() <= 0.5 * 0.5 * 4.0 + 1e-6);
            moved += (dv.length() > 1e-3) as u32;
        }
        assert!(moved > 100, "the noise field should move the vertex most of the time ({moved}/200)");
    }

    #[test]
    fn hierarchical_parts_grow_with_their_channels() {
        let mut p = WindParams::from_wind(&wind(), 3.7);
        p.gust = 1.0;
        let v0 = Vec3::new(0.0, 1.0, 0.0);
        let bend = Vec2::new(0.02, 0.01);
        // Root: nothing moves.
        assert_eq!(displace_hierarchical(v0, Vec4::new(0.0, 0.0, 0.0, 0.3), bend, 1.0, 0.0, &p), v0);
        // Trunk only: along the bend, quadratic in height.
        let d1 = displace_hierarchical(v0, Vec4::new(2.0, 0.0, 0.0, 0.3), bend, 1.0, 0.0, &p) - v0;
        let d2 = displace_hierarchical(v0, Vec4::new(4.0, 0.0, 0.0, 0.3), bend, 1.0, 0.0, &p) - v0;
        assert!((d2.length() / d1.length() - 4.0).abs() < 1e-4);
        assert!((d1.x * bend.y - d1.z * bend.x).abs() < 1e-7);
        // A stiffer trunk bends less.
        let mut stiff = p;
        stiff.trunk_stiffness *= 2.0;
        let d3 = displace_hierarchical(v0, Vec4::new(4.0, 0.0, 0.0, 0.3), bend, 1.0, 0.0, &stiff) - v0;
        assert!((d3.length() * 2.0 - d2.length()).abs() < 1e-5);
        // Branch phase changes the branch and leaf motion.
        let a = displace_hierarchical(v0, Vec4::new(0.0, 1.5, 0.5, 0.1), bend, 1.0, 0.0, &p);
        let b = displace_hierarchical(v0, Vec4::new(0.0, 1.5, 0.5, 0.6), bend, 1.0, 0.0, &p);
        assert!((a - b).length() > 1e-3);
    }

    #[test]
    fn displacement_never_exceeds_max_sway() {
        let mut w = wind();
        let extent = SwayExtent { height: 8.0, trunk_distance: 2.5, branch_distance: 0.8 };
        for model in [WindModel::Noise, WindModel::Hierarchical] {
            w.model = model;
            let bound = max_sway(&w, model, extent);
            assert!(bound > 0.0);
            let mut largest = 0.0f32;
            for i in 0..20_000 {
                let t = seq(i, 8) as f64 * 600.0;
                w.current = crate::systems::wind::gust_at(&w.gust, t);
                let p = WindParams::from_wind(&w, t);
                let ch = Vec4::new(seq(i, 9) * extent.height, seq(i, 10) * extent.trunk_distance, seq(i, 11) * extent.branch_distance, seq(i, 12));
                let gain = 0.5 + seq(i, 13);
                let phase = seq(i, 14) * TAU;
                let dir = Vec2::new(p.direction[0], p.direction[1]);
                let bend = crate::systems::wind::tree_bend(dir, w.strength, w.current, gain, phase, (t % 2.0) as f32);
                let v0 = Vec3::new(seq(i, 15) * 60.0 - 30.0, ch.x, seq(i, 16) * 60.0 - 30.0);
                let d = (displace(model.code(), v0, ch, bend, gain, phase, &p) - v0).length();
                largest = largest.max(d);
                assert!(d <= bound, "{model:?}: {d} > {bound}");
            }
            // The bound should not be wildly loose either.
            assert!(largest > 0.3 * bound, "{model:?}: largest {largest}, bound {bound}");
        }
    }

    #[test]
    fn params_bytes_follow_the_wgsl_layout() {
        let mut w = wind();
        w.model = WindModel::Noise;
        let p = WindParams::from_wind(&w, 12.5);
        let b = p.to_le_bytes();
        let f = |off: usize| f32::from_le_bytes(b[off..off + 4].try_into().unwrap());
        assert_eq!(f(0), 0.8);
        assert_eq!(f(4), 0.6);
        assert_eq!(f(8), 1.3);
        assert_eq!(f(28), 12.5);
        assert_eq!(f(32), w.response.trunk_stiffness);
        assert_eq!(f(48), w.response.leaf_frequency);
        assert_eq!(u32::from_le_bytes(b[52..56].try_into().unwrap()), 0);
        assert_eq!(std::mem::size_of::<WindParams>(), WindParams::SIZE);
    }

    #[test]
    fn gain_varies_with_position_within_its_range() {
        let mut gains = Vec::new();
        for i in 0..400 {
            let p = Vec3::new((i % 20) as f32 * 1.7, 0.0, (i / 20) as f32 * 1.7);
            let g = position_gain(p, 0.15);
            assert!((0.5..=1.5).contains(&g));
            gains.push(g);
        }
        let mean = gains.iter().sum::<f32>() / gains.len() as f32;
        let var = gains.iter().map(|g| (g - mean) * (g - mean)).sum::<f32>() / gains.len() as f32;
        assert!(var.sqrt() > 0.05, "gains barely vary: sd {}", var.sqrt());
    }
}
