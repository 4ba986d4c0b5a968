//! Extract: the first stage of a frame. `common` copies what every feature reads out of a
//! [`Sim`] (the camera, the sun, the time, the wind); each drawn feature then copies its own
//! part in its `extract.rs` (`Feature::extract`). These files are the only ones
//! in `src/render` that read simulation components; every later stage works on the copies.

use glam::Vec3;
use grove_systems::wind_model::{Wind, WindParams};
use grove_systems::light::NO_SUN;
use grove_systems::Sim;

use super::feature::Common;
use super::options::RenderOptions;
use super::view::Camera;

/// The frame's common data: the head's camera (or the options' top view or camera instead),
/// the sun (without one, light from high in the south-east), the time and the wind.
pub(crate) fn common(sim: &Sim, options: &RenderOptions) -> Common {
    let head = sim.head();
    let mut camera = Camera { position: head.pose.position, rotation: head.pose.rotation, fov_y: head.fov_y };
    if let Some(top) = options.top_view {
        camera = top.camera();
    } else if let Some(c) = options.camera {
        camera = c;
    }
    let (sun_dir, sun_elevation_deg) = sim
        .sun()
        .map_or((NO_SUN.0.normalize(), NO_SUN.1), |s| (s.direction.normalize_or(Vec3::Y), s.elevation_deg));
    let time = sim.time();
    let wind = sim.wind().unwrap_or_else(Wind::calm);
    Common { camera, sun_dir, sun_elevation_deg, time, wind: WindParams::from_wind(&wind, time), wind_model: wind.model }
}
