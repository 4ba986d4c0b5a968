//! Extract: the first stage of a frame. `common` copies what every feature reads out of a
//! [`Sim`] (the camera, the sun, the time, the wind); each drawn feature then copies its own
//! part in its `extract.rs` (`Feature::extract`). These files are the only ones
//! in `src/render` that read simulation components; every later stage works on the copies.

use glam::Vec3;
use grove_systems::wind_model::{Gust, Wind, WindModel, WindParams, WindResponse};
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
        .map_or((Vec3::new(0.3, 0.8, 0.2).normalize(), 45.0), |s| (s.direction.normalize_or(Vec3::Y), s.elevation_deg));
    let time = sim.time();
    let wind = sim.wind().unwrap_or_else(calm);
    Common { camera, sun_dir, sun_elevation_deg, time, wind: WindParams::from_wind(&wind, time), wind_model: wind.model }
}

/// The wind of a world without a `Wind` entity: strength and gust 0, the default response, so
/// only the trees' own `WindState::bend` moves them.
fn calm() -> Wind {
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

