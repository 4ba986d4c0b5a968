//! `grove sun`: the sun's position for a place and a UTC time.
//!
//! `grove sun --lat 47.37 --lon 8.54 --utc 2026-06-21T12:00:00Z [--json]` prints the true
//! geometric elevation (no refraction), the azimuth clockwise from north, the zenith angle and
//! the world-space direction towards the sun (+X east, +Y up, −Z north), from NREL's SPA.

use std::process::ExitCode;

use anyhow::anyhow;
use clap::Args;
use grove_systems::scene::{format_utc_ms, parse_utc_ms};
use grove_systems::systems::sun::sun_position;
use serde::Serialize;

/// Arguments of `grove sun`.
#[derive(Args)]
pub struct SunArgs {
    /// Latitude, degrees north (−90..=90).
    #[arg(long, allow_negative_numbers = true)]
    pub lat: String,
    /// Longitude, degrees east (−180..=180).
    #[arg(long, allow_negative_numbers = true)]
    pub lon: String,
    /// UTC date and time, RFC 3339, e.g. 2026-06-21T12:00:00Z.
    #[arg(long)]
    pub utc: String,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct SunReport {
    latitude_deg: f64,
    longitude_deg: f64,
    utc: String,
    elevation_deg: f64,
    azimuth_deg: f64,
    zenith_deg: f64,
    direction: [f64; 3],
    delta_t_s: f64,
}

/// Parses a number argument, with a one-line error that names the option.
fn number(name: &str, text: &str) -> anyhow::Result<f64> {
    let x: f64 = text.trim().parse().map_err(|_| anyhow!("{name} '{text}' is not a number"))?;
    if !x.is_finite() {
        return Err(anyhow!("{name} '{text}' must be a finite number"));
    }
    Ok(x)
}

/// Runs `grove sun`.
pub fn run(args: SunArgs) -> anyhow::Result<ExitCode> {
    let lat = number("--lat", &args.lat)?;
    let lon = number("--lon", &args.lon)?;
    let utc_ms = parse_utc_ms(&args.utc).map_err(|e| anyhow!("--utc {e}"))?;
    let p = sun_position(lat, lon, utc_ms).map_err(|e| anyhow!("{e}"))?;
    let report = SunReport {
        latitude_deg: lat,
        longitude_deg: lon,
        utc: format_utc_ms(utc_ms),
        elevation_deg: p.elevation_deg,
        azimuth_deg: p.azimuth_deg,
        zenith_deg: p.zenith_deg,
        direction: p.direction,
        delta_t_s: p.delta_t_s,
    };
    if args.json {
        crate::cli::print_json(&report)?;
    } else {
        let [x, y, z] = report.direction;
        println!("sun at {lat}° N, {lon}° E, {}:", report.utc);
        println!("  elevation_deg {:.5} (true geometric, no refraction)", report.elevation_deg);
        println!("  azimuth_deg   {:.5} (clockwise from north)", report.azimuth_deg);
        println!("  zenith_deg    {:.5}", report.zenith_deg);
        println!("  direction     ({x:.6}, {y:.6}, {z:.6}) (towards the sun; +X east, +Y up, -Z north)");
    }
    Ok(ExitCode::SUCCESS)
}
