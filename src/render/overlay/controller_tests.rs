//! Tests of the controller model on the committed Magic Leap One asset.

use super::*;

fn dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets")).join(MODEL_DIR)
}

fn model() -> ControllerModel {
    ControllerModel::load(&dir()).unwrap_or_else(|e| panic!("{e}"))
}

fn pressed_trigger() -> ControllerInput {
    ControllerInput { trigger: true, ..Default::default() }
}

fn close(a: Mat4, b: Mat4) -> bool {
    a.abs_diff_eq(b, 1e-5)
}

#[test]
fn nodes_are_found_although_the_profile_names_another_root() {
    let text = std::fs::read_to_string(dir().join("profile.json")).unwrap();
    let profile: serde_json::Value = serde_json::from_str(&text).unwrap();
    let profile_root = profile["layouts"][LAYOUT]["rootNodeName"].as_str().unwrap();
    let m = model();
    assert!(
        m.node_transform(&ControllerInput::default(), profile_root).is_none(),
        "the profile's root {profile_root:?} is not a node of the glb"
    );
    assert!(m.node_transform(&ControllerInput::default(), "magic_leap_one_none").is_some());
    // Trigger 1, squeeze 2 (with its mirror), touchpad 6: every response of the layout.
    assert_eq!(m.responses.len(), 9);
    assert_eq!(m.responses.iter().filter(|r| r.part == Part::Trigger).count(), 1);
    assert!(m.touch_point.is_some());
    assert!(m.triangle_count() > 1000, "{} triangles", m.triangle_count());
}

#[test]
fn a_response_naming_a_missing_node_is_an_error() {
    let text = std::fs::read_to_string(dir().join("profile.json"))
        .unwrap()
        .replace("xr_standard_trigger_pressed_min", "no_such_node");
    let glb = std::fs::read(dir().join("none.glb")).unwrap();
    match ControllerModel::from_bytes(&text, &glb) {
        Err(ControllerError::MissingNode(n)) => assert_eq!(n, "no_such_node"),
        other => panic!("expected a missing node, got {:?}", other.map(|_| ())),
    }
}

#[test]
fn the_trigger_value_node_goes_from_its_min_to_its_max() {
    let m = model();
    let at = |input: &ControllerInput, name: &str| m.node_transform(input, name).unwrap();
    let (rest, held) = (ControllerInput::default(), pressed_trigger());
    let value = "xr_standard_trigger_pressed_value";
    assert!(close(at(&rest, value), at(&rest, "xr_standard_trigger_pressed_min")));
    assert!(close(at(&held, value), at(&held, "xr_standard_trigger_pressed_max")));
    assert!(!close(at(&rest, value), at(&held, value)), "the trigger's transform does not change");
    // The trigger turns about its hinge: its mesh moves by millimetres.
    let (a, b) = (m.mesh_centre(&rest, value).unwrap(), m.mesh_centre(&held, value).unwrap());
    assert!(a.distance(b) > 1e-3, "trigger centre {a} → {b}");
    // Nothing else moves with the trigger.
    let pad = "xr_standard_touchpad_pressed_value";
    assert!(close(at(&rest, pad), at(&held, pad)));
}

#[test]
fn the_bumper_and_the_touchpad_press_move_their_parts() {
    let m = model();
    let rest = ControllerInput::default();
    let bumper = "xr_standard_squeeze_pressed_value";
    let squeezed = ControllerInput { squeeze: true, ..rest };
    assert!(close(
        m.node_transform(&squeezed, bumper).unwrap(),
        m.node_transform(&rest, "xr_standard_squeeze_pressed_max").unwrap()
    ));
    assert!(m.mesh_centre(&rest, bumper).unwrap().distance(m.mesh_centre(&squeezed, bumper).unwrap()) > 5e-4);
    let pad = "xr_standard_touchpad_pressed_value";
    let pressed = ControllerInput { touchpad_pressed: true, ..rest };
    assert!(close(
        m.node_transform(&pressed, pad).unwrap(),
        m.node_transform(&rest, "xr_standard_touchpad_pressed_max").unwrap()
    ));
    assert!(!close(m.node_transform(&rest, pad).unwrap(), m.node_transform(&pressed, pad).unwrap()));
}

#[test]
fn the_touch_dot_shows_only_while_touched_and_follows_the_axes() {
    let m = model();
    let dot = "xr_standard_touchpad_axes_touched_value";
    let none = |_: Vec3, _: Vec3, _: [f32; 4]| {};
    let rest = ControllerInput::default();
    assert_eq!(m.node_drawn(&rest, dot), Some(false));
    assert_eq!(m.pose(&rest, Mat4::IDENTITY, &mut none.clone()), None);
    let touch = |x: f32, y: f32| ControllerInput { touchpad: Vec2::new(x, y), ..rest };
    let at = |i: ControllerInput| {
        m.pose(&i, Mat4::IDENTITY, &mut none.clone()).expect("the touch dot is shown while touched")
    };
    assert_eq!(m.node_drawn(&touch(0.5, 0.0), dot), Some(true));
    // Grip space: +X right, −Z forward. Right on the pad is right; front (away from the user)
    // is forward.
    let (left, right) = (at(touch(-1.0, 0.0)), at(touch(1.0, 0.0)));
    assert!(right.x - left.x > 0.02, "left {left}, right {right}");
    let (back, front) = (at(touch(0.0, -1.0)), at(touch(0.0, 1.0)));
    assert!(back.z - front.z > 0.02, "back {back}, front {front}");
    // Pressed, the dot shows too.
    assert!(
        m.pose(&ControllerInput { touchpad_pressed: true, ..touch(0.2, 0.2) }, Mat4::IDENTITY, &mut none.clone())
            .is_some()
    );
}

#[test]
fn the_model_sits_behind_the_ray_origin_with_its_touchpad_on_top() {
    let m = model();
    let rest = ControllerInput::default();
    let mut points = Vec::new();
    let mut normals = 0;
    m.pose(&rest, m.placement(Vec3::ZERO, Quat::IDENTITY), &mut |p, n, _| {
        points.push(p);
        normals += usize::from((n.length() - 1.0).abs() < 1e-3);
    });
    assert_eq!(points.len(), m.triangle_count() * 3);
    assert_eq!(normals, points.len(), "every normal is a unit vector");
    let lo = points.iter().fold(Vec3::MAX, |a, &p| a.min(p));
    let hi = points.iter().fold(Vec3::MIN, |a, &p| a.max(p));
    // The front tip is at the origin, the controller (about 13 cm) behind it along +Z.
    assert!(lo.z.abs() < 1e-4, "front at z = {}", lo.z);
    assert!(hi.z > 0.1 && hi.z < 0.2, "back at z = {}", hi.z);
    assert!((lo.x + hi.x).abs() < 0.01, "not centred: {lo} {hi}");
    // The touchpad is above the trigger (+Y up).
    let pad = m.mesh_centre(&rest, "xr_standard_touchpad_pressed_value").unwrap();
    let trigger = m.mesh_centre(&rest, "xr_standard_trigger_pressed_value").unwrap();
    assert!(pad.y > trigger.y + 0.005, "touchpad {pad}, trigger {trigger}");
    // Placed at a pose, the model moves and turns with it.
    let turn = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
    let mut turned = Vec::new();
    m.pose(&rest, m.placement(Vec3::new(1.0, 2.0, 3.0), turn), &mut |p, _, _| turned.push(p));
    let want = Vec3::new(1.0, 2.0, 3.0) + turn * points[0];
    assert!(turned[0].distance(want) < 1e-5, "{} vs {want}", turned[0]);
}
