//! The per-vertex wind models: the CPU reference of `src/render/trees/wind.wgsl`.
//!
//! The renderer displaces every tree vertex on the GPU with the WGSL functions in
//! `src/render/trees/wind.wgsl`. This module holds the same functions in Rust, operation for operation,
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

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

mod displace;
pub mod exact;
mod gust;
mod noise;
#[cfg(test)]
mod tests;

pub use displace::*;
pub use gust::*;
pub use noise::*;

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
    pub fn validate(&self) -> Result<(), crate::limits::InvalidScene> {
        self.validate_message().map_err(crate::limits::InvalidScene)
    }

    fn validate_message(&self) -> Result<(), String> {
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

crate::wgsl_struct! {
    /// The parameters of the per-vertex wind functions, one uniform for all trees.
    ///
    /// Declared once for Rust and WGSL ([`crate::wgsl_struct!`]): the renderer composes
    /// [`WindParams::WGSL`] into the shaders as the piece `wind_params`, which
    /// `src/render/trees/wind.wgsl` imports (64 bytes, no implicit padding); upload
    /// [`WindParams::to_le_bytes`].
    #[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
    pub struct WindParams {
        /// Offset 0, `vec2<f32>`: horizontal unit direction the wind blows towards (world X, Z).
        pub direction: [f32; 2] as "vec2<f32>",
        /// Offset 8: the wind's base strength ([`Wind::strength`]).
        pub strength: f32 as "f32",
        /// Offset 12: the current gust factor ([`Wind::current`]).
        pub gust: f32 as "f32",
        /// Offset 16: spatial frequency of the noise, per metre ([`Wind::density`]).
        pub density: f32 as "f32",
        /// Offset 20: downwind drift of the noise field, metres per second.
        pub noise_speed: f32 as "f32",
        /// Offset 24: noise model amplitude ([`WindResponse::noise_amplitude`]).
        pub noise_amplitude: f32 as "f32",
        /// Offset 28: animation time, seconds (simulated time; f32 keeps millisecond precision for
        /// about 4 hours).
        pub time: f32 as "f32",
        /// Offset 32: trunk stiffness, metres.
        pub trunk_stiffness: f32 as "f32",
        /// Offset 36: branch stiffness, metres.
        pub branch_stiffness: f32 as "f32",
        /// Offset 40: branch frequency, hertz.
        pub branch_frequency: f32 as "f32",
        /// Offset 44: leaf flutter per metre of distance to the branch.
        pub leaf_flutter: f32 as "f32",
        /// Offset 48: leaf frequency, hertz.
        pub leaf_frequency: f32 as "f32",
        /// Offset 52, `u32`: the global model, [`WindModel::code`].
        pub model: u32 as "u32",
        /// Offsets 56 and 60: padding to 64 bytes; write zeros.
        pub pad: [u32; 2] as "vec2<u32>",
    }
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

/// The wind: a direction, a strength, a spatial density and a periodic gust function.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Wind {
    /// Horizontal unit direction the wind blows towards.
    pub direction: Vec3,
    /// Base strength; a bend of roughly `strength × 0.1` metres per metre of tree height.
    pub strength: f32,
    /// Spatial frequency of the noise, per metre.
    pub density: f32,
    /// Gust function parameters.
    pub gust: Gust,
    /// The current gust factor, updated every tick (average ± strength).
    pub current: f32,
    /// The per-vertex model for all trees (a renderer may override it per tree model).
    pub model: WindModel,
    /// The constants of the per-vertex models (stiffness, flutter, noise drift).
    pub response: WindResponse,
}

impl Wind {
    /// The wind of a world without a `Wind` entity, as every drawing takes it: strength and
    /// gust 0, the default model and response, so only the trees' own `WindState::bend` moves
    /// them.
    pub fn calm() -> Wind {
        Wind {
            direction: Vec3::X,
            strength: 0.0,
            density: 0.0,
            gust: Gust { average: 0.0, strength: 0.0, frequency: 0.0 },
            current: 0.0,
            model: WindModel::Hierarchical,
            response: WindResponse::default(),
        }
    }
}

/// A periodic gust function that approximates the inertia of a trunk:
/// `average + strength × g(frequency × t)`, where `g` is a smooth periodic function in [−1, 1]
/// (two low harmonics, no sudden changes: a trunk cannot follow turbulence faster than that).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Gust {
    /// The mean factor.
    pub average: f32,
    /// The amplitude of the gusts around the mean.
    pub strength: f32,
    /// Gusts per second, hertz.
    pub frequency: f32,
}
