//! The staging scene: a small world built to show one model alone (`grove render --model`, the
//! desktop's model thumbnails, the renderer's golden images), so that no renderer has to build
//! or edit a [`Sim`] itself.
//!
//! Units: metres, radians; right-handed, +Y up.

use glam::Vec3;

use crate::catalogue::{Catalogue, ModelId, ModelInfo, ModelKind};
use crate::components::{Controller, Head, Pose, Sun};
use crate::scene::{CameraDef, Hole, PlaneDef, PlaneShape, Scene, SunDef};
use crate::sim::Sim;

/// The eye position and target that show the box `min..max` whole with a vertical field of
/// view `fov_y` (radians) and an aspect ratio (width over height), looking from the south-east
/// and a bit above.
pub fn frame_bounds(min: Vec3, max: Vec3, fov_y: f32, aspect: f32) -> (Vec3, Vec3) {
    let centre = (min + max) * 0.5;
    let radius = ((max - min).length() * 0.5).max(0.01);
    let half = (fov_y * 0.5).min(libm::atanf(libm::tanf(fov_y * 0.5) * aspect));
    let dist = radius / libm::sinf(half) * 1.05;
    let dir = Vec3::new(0.55, 0.3, 0.78).normalize();
    (centre + dir * dist, centre)
}

/// A small world for showing one model: a ground plane under its bounds, a fixed morning sun,
/// no wind, one tree of `model` at the origin, and the camera framing the bounds (from
/// [`frame_bounds`], a 40° field of view for an image of `aspect` width over height); with
/// `with_hole`, a hole in the plane to the camera's right. `bounds` are the model's, in model
/// space, metres. The catalogue holds one entry, `model`, with those bounds.
pub fn model_stage(
    bounds: (Vec3, Vec3),
    aspect: f32,
    with_hole: bool,
    model: ModelId,
) -> Result<Sim, crate::sim::SimError> {
    let (min, max) = bounds;
    let size = (max - min).max_element().max(0.1);
    let half = size * 1.5;
    let scene = Scene {
        name: "model stage".into(),
        seed: 1,
        planes: vec![PlaneDef {
            name: "ground".into(),
            shape: PlaneShape::Grid {
                min: glam::Vec2::new(-half, -half),
                size: glam::Vec2::splat(2.0 * half),
                cell: (size / 8.0).max(0.05),
                elevation: min.y,
                unevenness: 0.0,
                noise_seed: 0,
                holes: if with_hole {
                    vec![Hole { center: glam::Vec2::new(half * 0.55, half * 0.3), radius: size * 0.2 }]
                } else {
                    vec![]
                },
            },
        }],
        sun: SunDef { utc: "2026-06-21T08:00:00Z".into(), ..SunDef::default() },
        camera: CameraDef { position: Vec3::new(0.0, 1.0, 5.0), look_at: Vec3::ZERO, fov_y_deg: 40.0 },
        ..Scene::default()
    };
    let info = ModelInfo {
        id: model,
        name: "model".into(),
        species: "any".into(),
        kind: ModelKind::Mesh,
        bounds_min: min,
        bounds_max: max,
        crown_radius: Vec3::new(min.x.abs().max(max.x.abs()), 0.0, min.z.abs().max(max.z.abs())).length(),
        triangles: 0,
        pick: None,
    };
    let mut sim = Sim::from_scene_with(&scene, 1, Catalogue { models: vec![info] })?;
    sim.spawn_tree(model, Vec3::ZERO, 0.0, 1.0, false);
    let fov = 40f32.to_radians();
    let (eye, target) = frame_bounds(min, max, fov, aspect);
    for (_, head) in sim.world.query_mut::<(hecs::Entity, &mut Head)>() {
        *head = Head { pose: Pose::looking_at(eye, target), fov_y: fov };
    }
    // A sun from over the camera's left shoulder, 40° up, so the model is lit from the front
    // and its shadow falls to the right where the camera sees it.
    for (_, sun) in sim.world.query_mut::<(hecs::Entity, &mut Sun)>() {
        sun.elevation_deg = 40.0;
        sun.azimuth_deg = 110.0;
        sun.direction = crate::systems::sun::direction_from_angles(110.0, 40.0);
    }
    // No controller ray in a model view.
    let controllers: Vec<hecs::Entity> =
        sim.world.query::<(hecs::Entity, &Controller)>().iter().map(|(e, _)| e).collect();
    for e in controllers {
        let _ = sim.world.despawn(e);
    }
    Ok(sim)
}

/// A walker's eye height on a stage, metres: the view of [`walker_view`].
pub const WALKER_EYE_HEIGHT: f32 = 1.7;
/// Where a walker looks on the model: this share of its height above the ground.
pub const WALKER_AIM: f32 = 0.45;
/// A walker's vertical field of view, degrees.
pub const WALKER_FOV_DEG: f32 = 50.0;
/// The sun of a walker's view: its elevation and azimuth, degrees (from behind the camera's left
/// shoulder).
pub const WALKER_SUN_DEG: (f64, f64) = (40.0, 150.0);

/// Turns a stage's camera into a walker's view of its model (docs/species.md, "From 3, 10 and
/// 30 m"): the eye [`WALKER_EYE_HEIGHT`] above the ground, `distance` metres south of the
/// model's axis, looking at [`WALKER_AIM`] of `height` (the model's top, metres) with a
/// [`WALKER_FOV_DEG`] field of view, the sun at [`WALKER_SUN_DEG`]. The species' pictures of
/// grove's renderer and of the headset page (`render.mjs --from`) both take their view from here.
pub fn walker_view(sim: &mut Sim, height: f32, distance: f32) {
    let (elevation, azimuth) = WALKER_SUN_DEG;
    sim.set_up()
        .camera(Head {
            pose: Pose::looking_at(
                Vec3::new(0.0, WALKER_EYE_HEIGHT, distance),
                Vec3::new(0.0, height * WALKER_AIM, 0.0),
            ),
            fov_y: WALKER_FOV_DEG.to_radians(),
        })
        .sun_angles(elevation, azimuth);
}

/// Puts the study scene's wind on a stage: its strength, density and gusts, the gust factor
/// at its average, so that a model's wind channels (its own, or those grove computes) show as
/// motion as the stage's ticks run (`grove render --model FILE --tick T` and `--frames`, and the
/// headset page's `render.mjs --tick`). A stage without a `Wind` entity is left as it is.
pub fn in_study_wind(sim: &mut Sim) -> Result<(), crate::sim::SimError> {
    let study = Scene::builtin("study")
        .ok_or_else(|| crate::limits::InvalidScene("the built-in study scene is missing".into()))?;
    if let Some(mut w) = sim.wind() {
        let d = &study.wind;
        w.strength = d.strength;
        w.density = d.density;
        w.gust =
            crate::components::Gust { average: d.gust_average, strength: d.gust_strength, frequency: d.gust_frequency };
        w.current = d.gust_average;
        sim.set_up().wind(w);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stage_holds_one_tree_of_the_model_and_no_controller() {
        let sim = model_stage((Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 3.0, 1.0)), 1.5, true, ModelId(3)).unwrap();
        let ids = sim.tree_ids();
        assert_eq!(ids.len(), 1);
        assert_eq!(sim.tree(ids[0]).unwrap().tree.model, ModelId(3));
        assert_eq!(sim.world.query::<&Controller>().iter().count(), 0);
        let sun = sim.sun().unwrap();
        assert_eq!((sun.elevation_deg, sun.azimuth_deg), (40.0, 110.0));
        // The camera looks at the middle of the bounds.
        let head = sim.head();
        let to_centre = (Vec3::new(0.0, 1.5, 0.0) - head.pose.position).normalize();
        assert!(head.pose.forward().dot(to_centre) > 0.9999);
    }

    #[test]
    fn a_walker_looks_from_eye_height_at_the_model_s_aim() {
        let mut sim =
            model_stage((Vec3::new(-2.0, 0.0, -2.0), Vec3::new(2.0, 20.0, 2.0)), 4.0 / 3.0, false, ModelId(0)).unwrap();
        walker_view(&mut sim, 20.0, 10.0);
        let head = sim.head();
        assert_eq!(head.pose.position, Vec3::new(0.0, 1.7, 10.0));
        let to_aim = (Vec3::new(0.0, 9.0, 0.0) - head.pose.position).normalize();
        assert!(head.pose.forward().dot(to_aim) > 0.9999);
        assert!((head.fov_y - 50f32.to_radians()).abs() < 1e-6);
        let sun = sim.sun().unwrap();
        assert_eq!((sun.elevation_deg, sun.azimuth_deg), (40.0, 150.0));
    }

    #[test]
    fn the_study_wind_on_a_stage_is_the_study_scene_s() {
        let mut sim =
            model_stage((Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 3.0, 1.0)), 1.5, false, ModelId(0)).unwrap();
        assert_eq!(sim.wind().unwrap().strength, 0.0, "the stage is calm");
        in_study_wind(&mut sim).unwrap();
        let (w, d) = (sim.wind().unwrap(), Scene::builtin("study").unwrap().wind);
        assert!(d.strength > 0.0 && d.gust_strength > 0.0, "the study scene has gusts");
        assert_eq!(
            (w.strength, w.density, w.gust.strength, w.current),
            (d.strength, d.density, d.gust_strength, d.gust_average)
        );
    }
}
