//! Sun system: advances the sun's clock and recomputes its direction.
//!
//! Reads: `Resources::dt`, `Sun` (time, place, time rate).
//! Writes: `Sun` (`utc_ms`, elevation, azimuth, direction).
//!
//! The position comes from the NREL Solar Position Algorithm (Reda & Andreas 2003) through the
//! `solar-positioning` crate, as true geometric elevation (no refraction). World axes: +Y up,
//! −Z north, +X east; azimuth clockwise from north.

use glam::Vec3;
use hecs::World;
use solar_positioning::{time::JulianDate, Location, SolarPositions};

use crate::components::Sun;
use crate::resources::Resources;

/// The world-space unit vector towards a sun at `azimuth_deg` (clockwise from north) and
/// `elevation_deg` above the horizon.
pub fn direction_from_angles(azimuth_deg: f64, elevation_deg: f64) -> Vec3 {
    let (a, h) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
    Vec3::new((a.sin() * h.cos()) as f32, h.sin() as f32, (-a.cos() * h.cos()) as f32)
}

/// Solar azimuth and true elevation, degrees, for a place and a UTC time in milliseconds.
pub fn solar_angles(latitude_deg: f64, longitude_deg: f64, utc_ms: i64) -> Result<(f64, f64), String> {
    let t = chrono::DateTime::from_timestamp_millis(utc_ms).ok_or_else(|| format!("time {utc_ms} ms is out of range"))?;
    use chrono::{Datelike, Timelike};
    let delta_t = solar_positioning::delta_t::estimate_from_date(t.year(), t.month()).map_err(|e| e.to_string())?;
    let seconds = t.second() as f64 + t.nanosecond() as f64 * 1e-9;
    let jd = JulianDate::from_utc(t.year(), t.month(), t.day(), t.hour(), t.minute(), seconds, delta_t).map_err(|e| e.to_string())?;
    let location = Location { latitude: latitude_deg, longitude: longitude_deg };
    let pos = SolarPositions::new().at_from_julian(jd, location, 0.0, None).map_err(|e| e.to_string())?;
    Ok((pos.azimuth(), pos.elevation_angle()))
}

/// Recomputes a sun's angles and direction from its place and time.
pub fn update_sun(sun: &mut Sun) -> Result<(), String> {
    let (az, el) = solar_angles(sun.latitude_deg, sun.longitude_deg, sun.utc_ms)?;
    sun.azimuth_deg = az;
    sun.elevation_deg = el;
    sun.direction = direction_from_angles(az, el);
    Ok(())
}

/// Runs the sun system.
pub fn run(world: &mut World, res: &mut Resources) {
    for sun in world.query_mut::<&mut Sun>() {
        if sun.time_rate == 0.0 {
            continue;
        }
        // Milliseconds of sun time per tick, rounded so that the clock stays an integer.
        let step_ms = (res.dt as f64 * sun.time_rate * 1000.0).round() as i64;
        sun.utc_ms = sun.utc_ms.saturating_add(step_ms);
        // A time outside the algorithm's range keeps the last valid direction.
        let _ = update_sun(sun);
    }
}
