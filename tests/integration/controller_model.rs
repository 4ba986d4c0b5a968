//! The controller's model follows a recording: replaying a committed recording, the trigger
//! node of the Magic Leap One model moves between a tick before a trigger press and a tick
//! during it (issue #36).

use crate::common;

use grove::render::overlay::controller::{ControllerModel, model_dir};
use grove::render::overlay::extract::overlay_scene;
use grove::render::overlay::geometry::OverlayController;
use grove_systems::replay::{ReplayOptions, replay_file};

/// The recording: a trigger press and release at its start.
const RECORDING: &str = "replays/scenarios/plant-two.jsonl";
/// The trigger's value node in the registry's naming.
const TRIGGER: &str = "xr_standard_trigger_pressed_value";

/// The controller as the overlay sees it after replaying up to `tick`.
fn controller_at(tick: u64) -> OverlayController {
    let path = common::root().join(RECORDING);
    let outcome = replay_file(&path, &ReplayOptions { until: Some(tick), ..Default::default() })
        .unwrap_or_else(|e| panic!("{e}"));
    let scene = overlay_scene(&outcome.sim);
    assert_eq!(scene.controllers.len(), 1, "one controller");
    scene.controllers[0]
}

#[test]
fn the_trigger_node_moves_between_a_frame_before_a_press_and_one_during_it() {
    let model = ControllerModel::load(&model_dir(&common::root().join("assets"))).unwrap_or_else(|e| panic!("{e}"));
    // The first tick at which the replayed world holds the trigger, and a tick before it at
    // which it does not (both read from the replayed controller, not from the file's events).
    let mut before = None;
    let mut during = None;
    for tick in 0..30 {
        let c = controller_at(tick);
        if c.trigger {
            during = Some((tick, c));
            break;
        }
        before = Some((tick, c));
    }
    let (t0, released) = before.expect("a tick before the press");
    let (t1, held) = during.expect("the recording presses the trigger");
    assert!(t0 < t1 && !released.trigger && held.trigger);
    let (a, b) = (released.input(), held.input());
    let (ma, mb) = (model.node_transform(&a, TRIGGER).unwrap(), model.node_transform(&b, TRIGGER).unwrap());
    assert!(!ma.abs_diff_eq(mb, 1e-4), "tick {t0} → {t1}: the trigger node does not move");
    // The trigger's mesh, relative to the controller, moves by more than a millimetre.
    let (ca, cb) = (model.mesh_centre(&a, TRIGGER).unwrap(), model.mesh_centre(&b, TRIGGER).unwrap());
    assert!(ca.distance(cb) > 1e-3, "tick {t0} → {t1}: trigger centre {ca} → {cb}");
    // And in the world, where the overlay draws it.
    let world = |c: &OverlayController, m: glam::Vec3| model.placement(c.origin, c.rotation).transform_point3(m);
    assert!(world(&released, ca).distance(world(&held, cb)) > 1e-3);
}
