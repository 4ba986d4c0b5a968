//! Sun system: advances the sun's clock and recomputes its direction.
//!
//! Reads: `Resources::tick`, `Resources::dt`, `Sun` (time, place, time rate).
//! Writes: `Sun` (`utc_ms`, elevation, azimuth, direction) when its time rate is not zero.
//!
//! The position comes from the NREL Solar Position Algorithm (Reda & Andreas 2003) through the
//! `solar-positioning` crate, as the true geometric (topocentric, unrefracted) elevation at sea
//! level, with ΔT (TT − UT) from the crate's Espenak–Meeus estimate. World axes: +Y up, −Z north,
//! +X east; azimuth clockwise from north, so a sun at azimuth 90° lies towards +X.
//!
//! The clock advances by a whole number of milliseconds per tick, rounded so that the total
//! never drifts: after `n` ticks at a constant rate it has moved by `round(n × dt × rate × 1000)` ms.

use glam::Vec3;
use hecs::World;
use serde::Serialize;
use solar_positioning::{Location, SolarPositions, time::JulianDate};

use crate::components::Sun;
use crate::resources::Resources;
use crate::single;

/// The Julian date of the Unix epoch, 1970-01-01T00:00:00Z.
pub const UNIX_EPOCH_JD: f64 = 2_440_587.5;
/// Milliseconds per day.
const MS_PER_DAY: f64 = 86_400_000.0;

/// The sun's position seen from a place at a time.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SolarAngles {
    /// True geometric elevation above the horizon, degrees (no refraction).
    pub elevation_deg: f64,
    /// Azimuth, degrees clockwise from north, 0..360.
    pub azimuth_deg: f64,
    /// Zenith angle, degrees: `90 − elevation_deg`.
    pub zenith_deg: f64,
    /// World-space unit vector from the ground towards the sun (+X east, +Y up, −Z north).
    pub direction: [f64; 3],
    /// The ΔT used, seconds.
    pub delta_t_s: f64,
}

/// Why the sun's position could not be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SunError {
    /// A latitude outside −90..=90 degrees, or not finite.
    #[error("latitude {0} is outside -90..=90 degrees")]
    Latitude(f64),
    /// A longitude outside −180..=180 degrees, or not finite.
    #[error("longitude {0} is outside -180..=180 degrees")]
    Longitude(f64),
    /// A year outside the ΔT model's range.
    #[error("no ΔT for year {year}: {reason}")]
    DeltaT {
        /// The year, rounded down.
        year: f64,
        /// The model's message.
        reason: String,
    },
    /// A Julian date the solar model refuses.
    #[error("{0}")]
    JulianDate(String),
    /// The solar model failed.
    #[error("solar position: {0}")]
    Position(String),
}

/// Checks a place: latitude in −90..=90 and longitude in −180..=180 degrees, both finite.
pub fn check_place(latitude_deg: f64, longitude_deg: f64) -> Result<(), SunError> {
    if !latitude_deg.is_finite() || !(-90.0..=90.0).contains(&latitude_deg) {
        return Err(SunError::Latitude(latitude_deg));
    }
    if !longitude_deg.is_finite() || !(-180.0..=180.0).contains(&longitude_deg) {
        return Err(SunError::Longitude(longitude_deg));
    }
    Ok(())
}

/// The world-space unit vector (f64) towards a sun at `azimuth_deg` (clockwise from north) and
/// `elevation_deg` above the horizon: `(sin A cos h, sin h, −cos A cos h)`.
pub fn direction_from_angles_f64(azimuth_deg: f64, elevation_deg: f64) -> [f64; 3] {
    let (a, h) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
    [libm::sin(a) * libm::cos(h), libm::sin(h), -libm::cos(a) * libm::cos(h)]
}

/// The world-space unit vector towards a sun at `azimuth_deg` (clockwise from north) and
/// `elevation_deg` above the horizon.
pub fn direction_from_angles(azimuth_deg: f64, elevation_deg: f64) -> Vec3 {
    let [x, y, z] = direction_from_angles_f64(azimuth_deg, elevation_deg);
    Vec3::new(x as f32, y as f32, z as f32)
}

/// The azimuth (degrees clockwise from north, 0..360) and elevation (degrees) of a world-space
/// direction; the inverse of [`direction_from_angles`].
pub fn angles_from_direction(direction: Vec3) -> (f64, f64) {
    let d = direction.as_dvec3().normalize_or_zero();
    let azimuth = libm::atan2(d.x, -d.z).to_degrees().rem_euclid(360.0);
    let elevation = libm::asin(d.y.clamp(-1.0, 1.0)).to_degrees();
    (azimuth, elevation)
}

/// The Julian date (UT) of a UTC time in milliseconds since the Unix epoch.
pub fn julian_date(utc_ms: i64) -> f64 {
    UNIX_EPOCH_JD + utc_ms as f64 / MS_PER_DAY
}

/// ΔT (TT − UT), seconds, estimated for a UTC time (Espenak–Meeus polynomials as updated in
/// the `solar-positioning` crate; valid for years −500..3000).
pub fn delta_t(utc_ms: i64) -> Result<f64, SunError> {
    let year = 2000.0 + (julian_date(utc_ms) - 2_451_544.5) / 365.2425;
    solar_positioning::delta_t::estimate(year)
        .map_err(|e| SunError::DeltaT { year: year.floor(), reason: e.to_string() })
}

/// The sun's position from a place and a UTC time in milliseconds, with SPA at sea level, no
/// refraction, and the estimated ΔT.
pub fn sun_position(latitude_deg: f64, longitude_deg: f64, utc_ms: i64) -> Result<SolarAngles, SunError> {
    check_place(latitude_deg, longitude_deg)?;
    let dt = delta_t(utc_ms)?;
    let jd = JulianDate::new(julian_date(utc_ms), dt).map_err(|e| SunError::JulianDate(e.to_string()))?;
    let location = Location { latitude: latitude_deg, longitude: longitude_deg };
    let pos =
        SolarPositions::new().at_from_julian(jd, location, 0.0, None).map_err(|e| SunError::Position(e.to_string()))?;
    let (azimuth_deg, elevation_deg) = (pos.azimuth(), pos.elevation_angle());
    Ok(SolarAngles {
        elevation_deg,
        azimuth_deg,
        zenith_deg: pos.zenith_angle(),
        direction: direction_from_angles_f64(azimuth_deg, elevation_deg),
        delta_t_s: dt,
    })
}

/// Solar azimuth and true elevation, degrees, for a place and a UTC time in milliseconds.
pub fn solar_angles(latitude_deg: f64, longitude_deg: f64, utc_ms: i64) -> Result<(f64, f64), SunError> {
    let p = sun_position(latitude_deg, longitude_deg, utc_ms)?;
    Ok((p.azimuth_deg, p.elevation_deg))
}

/// Recomputes a sun's angles and direction from its place and time.
pub fn update_sun(sun: &mut Sun) -> Result<(), SunError> {
    let p = sun_position(sun.latitude_deg, sun.longitude_deg, sun.utc_ms)?;
    sun.azimuth_deg = p.azimuth_deg;
    sun.elevation_deg = p.elevation_deg;
    sun.direction = direction_from_angles(p.azimuth_deg, p.elevation_deg);
    Ok(())
}

/// Milliseconds the sun's clock advances in the tick that starts at simulated time `t` seconds
/// and lasts `dt` seconds, at `rate` sun seconds per simulated second. Successive steps add up
/// to `round(t_end × rate × 1000)` exactly, so the clock does not drift.
pub fn clock_step_ms(t: f64, dt: f64, rate: f64) -> i64 {
    let at = |s: f64| (s * rate * 1000.0).round();
    let step = at(t + dt) - at(t);
    if step.is_finite() { step.clamp(i64::MIN as f64, i64::MAX as f64) as i64 } else { 0 }
}

/// Runs the sun system.
pub fn run(world: &mut World, res: &mut Resources) {
    let t = res.time();
    single::for_each_mut::<Sun>(world, &res.singles, |sun| {
        if sun.time_rate == 0.0 {
            return;
        }
        let step_ms = clock_step_ms(t, res.dt as f64, sun.time_rate);
        sun.utc_ms = sun.utc_ms.saturating_add(step_ms);
        // A time outside the algorithm's range keeps the last valid direction.
        let _ = update_sun(sun);
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clock_steps_add_up_without_drift() {
        let dt = 1.0f64 / 60.0;
        for rate in [1.0, 60.0, 3600.0, -7.3] {
            let total: i64 = (0..6000).map(|n| clock_step_ms(n as f64 * dt, dt, rate)).sum();
            let expected = (6000.0 * dt * rate * 1000.0).round() as i64;
            assert!((total - expected).abs() <= 1, "rate {rate}: {total} vs {expected}");
        }
    }

    #[test]
    fn bad_places_are_rejected() {
        assert!(check_place(91.0, 0.0).is_err());
        assert!(check_place(0.0, 200.0).is_err());
        assert!(check_place(f64::NAN, 0.0).is_err());
        assert!(check_place(45.0, -180.0).is_ok());
        assert!(sun_position(-90.5, 10.0, 0).is_err());
    }

    #[test]
    fn direction_and_angles_round_trip() {
        for az in [0.0, 45.0, 90.0, 135.0, 180.0, 270.0, 359.0] {
            for el in [-30.0, 0.0, 10.0, 60.0, 89.0] {
                let (a, e) = angles_from_direction(direction_from_angles(az, el));
                assert!(((a - az + 180.0).rem_euclid(360.0) - 180.0).abs() < 1e-3, "{az} {el} -> {a}");
                assert!((e - el).abs() < 1e-3);
            }
        }
    }
}
