//! The sun's light for its elevation (the direct light, the sky's ambient light and the sky's
//! brightness) and the aerial perspective's haze by distance, which every drawing of the world
//! shares (the native renderer's frame uniforms, `src/render/lighting.rs` and `src/render/haze.rs`,
//! and the headset page through [`crate::snapshot::Snapshot::light`]).
//! Pure arithmetic (no maths library): the same numbers on every target.
//!
//! Units: degrees for elevations; colours are linear RGB times intensity.

use glam::Vec3;

/// The sun's light for an elevation: direct colour×intensity (linear RGB), the ambient
/// strength and the sky brightness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunLight {
    /// Direct light, linear RGB times intensity; zero when the sun is below the horizon.
    pub direct: Vec3,
    /// Ambient (sky) light multiplier, linear RGB.
    pub ambient: Vec3,
    /// Brightness of the sky background, 0..1.
    pub sky: f32,
}

fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Light from the sun at `elevation_deg` (true elevation, degrees): off below the horizon,
/// ramping up over the first 8°, and shifting from a warm orange near the horizon to a slightly
/// warm white above 30°. The sky and ambient light fade through civil twilight (−6°).
pub fn sun_light(elevation_deg: f64) -> SunLight {
    let e = elevation_deg as f32;
    let on = if e <= 0.0 { 0.0 } else { smoothstep(0.0, 8.0, e) };
    let warm = 1.0 - smoothstep(0.0, 30.0, e);
    let white = Vec3::new(1.0, 0.96, 0.9);
    let orange = Vec3::new(1.0, 0.5, 0.2);
    let direct = white.lerp(orange, warm) * (2.6 * on);
    let sky = 0.06 + 0.94 * smoothstep(-6.0, 12.0, e);
    let ambient = Vec3::new(1.0, 1.0, 1.0).lerp(Vec3::new(1.0, 0.78, 0.6), warm) * (0.9 * sky);
    SunLight { direct, ambient, sky }
}

/// The aerial perspective's haze by distance from the eye, metres: none within [`HAZE_START`];
/// beyond it the share `1 - exp(-(d - HAZE_START) / HAZE_DEPTH)`, and at least a smoothstep
/// from [`HAZE_FULL_FROM`] to all of it at [`HAZE_FULL_AT`] (the native renderer's far plane is
/// at 600 m, where the terrain ends). `src/render/haze.rs` and the page's trees draw with these.
pub const HAZE_START: f32 = 40.0;
/// See [`HAZE_START`].
pub const HAZE_DEPTH: f32 = 400.0;
/// See [`HAZE_START`].
pub const HAZE_FULL_FROM: f32 = 350.0;
/// See [`HAZE_START`].
pub const HAZE_FULL_AT: f32 = 590.0;

/// The sun of a world without one, as every drawing takes it: light from high in the
/// south-east, 45° up.
pub const NO_SUN: (Vec3, f64) = (Vec3::new(0.3, 0.8, 0.2), 45.0);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sun_is_off_below_the_horizon() {
        assert_eq!(sun_light(-0.5).direct, Vec3::ZERO);
        assert_eq!(sun_light(0.0).direct, Vec3::ZERO);
        assert!(sun_light(2.0).direct.max_element() > 0.0);
    }

    #[test]
    fn sun_is_dimmer_and_warmer_near_the_horizon() {
        let low = sun_light(4.0).direct;
        let high = sun_light(50.0).direct;
        assert!(low.length() < high.length());
        // Warmer: less blue relative to red.
        assert!(low.z / low.x < high.z / high.x);
        assert!(sun_light(-10.0).sky < sun_light(30.0).sky);
    }
}
