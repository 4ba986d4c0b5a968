//! The gust function and the trunk's lean: deterministic maths (a polynomial sine, no platform
//! `sin`), advanced every tick by the wind system (`crate::systems::wind`).

use glam::Vec2;

use super::{Gust, Wind};

/// Sine of `x` (radians) by range reduction to [−π, π] and an odd polynomial of degree 9
/// (absolute error below 1e-5). Deterministic: plain float arithmetic only.
#[inline]
pub fn det_sin(x: f32) -> f32 {
    use std::f32::consts::{PI, TAU};
    let k = super::exact::floor(x * (1.0 / TAU) + 0.5);
    let r = x - k * TAU;
    // Fold into [−π/2, π/2], where the polynomial is accurate: sin(π − r) = sin(r). Written
    // without branches (abs and copysign are exact), since random tree phases would make a
    // branch unpredictable.
    let r = (PI * 0.5 - (r.abs() - PI * 0.5).abs()).copysign(r);
    let r2 = r * r;
    r * (1.0 + r2 * (-1.0 / 6.0 + r2 * (1.0 / 120.0 + r2 * (-1.0 / 5040.0 + r2 * (1.0 / 362_880.0)))))
}

/// The smooth periodic gust shape in [−1, 1], period 1 in `u`.
#[inline]
pub fn gust_shape(u: f32) -> f32 {
    use std::f32::consts::TAU;
    0.7 * det_sin(TAU * u) + 0.3 * det_sin(2.0 * TAU * u + 1.1)
}

/// The gust factor at time `t` seconds: `average + strength × shape(frequency × t)`.
pub fn gust_at(g: &Gust, t: f64) -> f32 {
    let u = super::exact::fract(g.frequency as f64 * t) as f32;
    g.average + g.strength * gust_shape(u)
}

/// A tree's trunk lean (horizontal metres per metre of height, world X and Z) for wind
/// direction `dir` (horizontal unit), base `strength`, the shared gust factor, the tree's gain
/// and phase, at time `t` seconds:
/// `dir × 0.02 × strength × gain × (gust + 0.25 × sin(π t + phase))`.
#[inline]
pub fn tree_bend(dir: Vec2, strength: f32, gust: f32, gain: f32, phase: f32, t: f32) -> Vec2 {
    // A steady lean from the gust plus a small oscillation at about 0.5 Hz with the tree's own phase.
    let sway = det_sin(std::f32::consts::PI * t + phase);
    let amount = 0.02 * strength * gain * (gust + 0.25 * sway);
    dir * amount
}

/// The largest bend [`tree_bend`] can give for this wind at any time, any gain (≤ 1.5) and any
/// phase, metres per metre of height.
pub fn max_bend(wind: &Wind) -> f32 {
    0.02 * wind.strength.abs() * 1.5 * (wind.gust.average.abs() + wind.gust.strength.abs() + 0.25)
}
