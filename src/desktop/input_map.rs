//! Device mapping: mouse, keyboard and gamepad input become the simulation's [`InputEvent`]s.
//!
//! The camera maths are pure functions with explicit arguments ([`cursor_ray`], [`project`],
//! [`walk`], [`turn`]); [`Controls`] keeps the device state (keys and buttons held, the cursor,
//! the head pose the user is steering) and turns device changes into events. Nothing here
//! touches a window or a clock: callers pass the wall-clock seconds of each frame.
//!
//! Bindings (also shown by the help overlay, from [`BINDINGS`]):
//! - the ray runs from the camera (the Head pose) through the cursor;
//! - left button = Trigger (click or hold), right button = Bumper;
//! - wheel or Up/Down arrows = touchpad front/back; Q/E = touchpad left/right;
//! - Tab or M = Menu (a second press closes it);
//! - W/A/S/D walks the head, a drag with the right button held turns it;
//! - gamepad: South or right trigger = Trigger, East or left trigger = Bumper, Start or Select =
//!   Menu, D-pad = touchpad, left stick walks, right stick turns.

use glam::{Vec2, Vec3};
use grove_systems::components::{Pose, rotation_towards};
use grove_systems::input::{Button, InputEvent};
use winit::event::MouseButton;
use winit::keyboard::KeyCode;

/// The key bindings as (keys, action) rows, for the help overlay.
pub const BINDINGS: &[(&str, &str)] = &[
    ("Mouse", "aim the ray from the camera through the cursor"),
    ("Left button", "Trigger: plant / select / drag (click or hold)"),
    ("Right button", "Bumper: remove the tree under the ray"),
    ("Right drag", "turn the head"),
    ("W A S D", "walk the head"),
    ("Wheel, Up/Down", "touchpad front/back (move the selected tree along the ray)"),
    ("Q / E", "touchpad left/right (turn the selected tree)"),
    ("Tab or M", "Menu: open / close the model menu"),
    ("F1 or H", "show / hide this help"),
    ("F3", "show / hide the debug panel"),
    ("Escape", "quit (the recording is finished cleanly)"),
    ("Gamepad", "South/RT = Trigger, East/LT = Bumper, Start = Menu, D-pad = touchpad, sticks = walk/turn"),
];

/// Walking speed of the head, metres per second.
pub const WALK_SPEED: f32 = 2.0;
/// Head turn per pixel of right-drag, radians.
pub const TURN_PER_PIXEL: f32 = 0.004;
/// Head turn rate at full gamepad stick deflection, radians per second.
pub const STICK_TURN_RATE: f32 = 1.5;
/// How long one wheel notch holds the touchpad deflected, seconds.
pub const WHEEL_PULSE_S: f32 = 0.12;
/// Gamepad stick dead zone.
pub const STICK_DEAD_ZONE: f32 = 0.2;
/// The head's pitch is kept within ± this many radians of the horizon.
pub const MAX_PITCH: f32 = 1.45;

/// The controller pose whose ray starts at the camera and passes through the cursor.
///
/// `cursor` and `size` are in the same units (pixels), with the origin at the top left of the
/// view; `fov_y` is the vertical field of view, radians.
pub fn cursor_ray(head: &Pose, fov_y: f32, size: Vec2, cursor: Vec2) -> Pose {
    let size = size.max(Vec2::ONE);
    let ndc = Vec2::new(2.0 * cursor.x / size.x - 1.0, 1.0 - 2.0 * cursor.y / size.y);
    let t = (fov_y * 0.5).tan();
    let aspect = size.x / size.y;
    let local = Vec3::new(ndc.x * t * aspect, ndc.y * t, -1.0);
    let dir = (head.rotation * local).normalize_or(head.forward());
    Pose { position: head.position, rotation: rotation_towards(dir) }
}

/// Where a world point appears in the view (pixels from the top left), or `None` if it is
/// behind the camera (closer than `near` metres in front of it). The inverse of [`cursor_ray`].
pub fn project(head: &Pose, fov_y: f32, size: Vec2, point: Vec3, near: f32) -> Option<Vec2> {
    let local = head.rotation.inverse() * (point - head.position);
    if -local.z < near {
        return None;
    }
    let t = (fov_y * 0.5).tan();
    let aspect = size.x / size.y.max(1.0);
    let ndc = Vec2::new(local.x / (-local.z * t * aspect), local.y / (-local.z * t));
    Some(Vec2::new((ndc.x + 1.0) * 0.5 * size.x, (1.0 - ndc.y) * 0.5 * size.y))
}

/// The yaw (about +Y, 0 = looking north, positive = turning left) and pitch of a pose's forward
/// direction, radians.
pub fn yaw_pitch(pose: &Pose) -> (f32, f32) {
    let f = pose.forward();
    ((-f.x).atan2(-f.z), f.y.clamp(-1.0, 1.0).asin())
}

/// The pose at `position` looking along `yaw` and `pitch` (see [`yaw_pitch`]), without roll.
pub fn from_yaw_pitch(position: Vec3, yaw: f32, pitch: f32) -> Pose {
    let pitch = pitch.clamp(-MAX_PITCH, MAX_PITCH);
    let dir = Vec3::new(-yaw.sin() * pitch.cos(), pitch.sin(), -yaw.cos() * pitch.cos());
    Pose { position, rotation: rotation_towards(dir) }
}

/// Walks a head horizontally: `dir.y` forward, `dir.x` right (each in [−1, 1]), for `dt`
/// seconds at [`WALK_SPEED`]. Height and orientation are kept.
pub fn walk(head: &Pose, dir: Vec2, dt: f32) -> Pose {
    let (yaw, _) = yaw_pitch(head);
    let forward = Vec3::new(-yaw.sin(), 0.0, -yaw.cos());
    let right = Vec3::new(yaw.cos(), 0.0, -yaw.sin());
    let step = (forward * dir.y + right * dir.x).clamp_length_max(1.0) * WALK_SPEED * dt;
    Pose { position: head.position + step, rotation: head.rotation }
}

/// Turns a head by `dyaw` (positive = left) and `dpitch` (positive = up), radians, keeping the
/// pitch within ±[`MAX_PITCH`].
pub fn turn(head: &Pose, dyaw: f32, dpitch: f32) -> Pose {
    let (yaw, pitch) = yaw_pitch(head);
    from_yaw_pitch(head.position, yaw + dyaw, pitch + dpitch)
}

/// A gamepad input, reduced to what the mapping uses (so that it can be tested without gilrs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PadInput {
    /// A button went down (`true`) or up.
    Button(gilrs::Button, bool),
    /// An axis moved to a value in [−1, 1].
    Axis(gilrs::Axis, f32),
}

/// What the app should do besides feeding the simulation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AppKeys {
    /// Quit was asked for (Escape).
    pub quit: bool,
    /// Toggle the help overlay (F1 or H).
    pub toggle_help: bool,
    /// Toggle the debug panel (F3).
    pub toggle_debug: bool,
}

/// The device state that turns mouse, keyboard and gamepad input into controller events.
#[derive(Clone, Debug)]
pub struct Controls {
    /// The head pose the user is steering (the last one sent, or the world's at the start).
    pub head: Pose,
    /// The vertical field of view, radians.
    pub fov_y: f32,
    /// The view size, pixels.
    pub size: Vec2,
    /// The cursor position in the view, pixels; `None` until the mouse has moved into it.
    pub cursor: Option<Vec2>,
    last_pose: Option<Pose>,
    last_axes: Vec2,
    walk_keys: [bool; 4],
    pad_keys: [bool; 4],
    wheel_left: f32,
    wheel_dir: f32,
    right_drag_from: Option<Vec2>,
    left_stick: Vec2,
    right_stick: Vec2,
    dpad: Vec2,
}

impl Controls {
    /// Controls for a head pose, a field of view and a view size.
    pub fn new(head: Pose, fov_y: f32, size: Vec2) -> Controls {
        Controls {
            head,
            fov_y,
            size,
            cursor: None,
            last_pose: None,
            last_axes: Vec2::ZERO,
            walk_keys: [false; 4],
            pad_keys: [false; 4],
            wheel_left: 0.0,
            wheel_dir: 0.0,
            right_drag_from: None,
            left_stick: Vec2::ZERO,
            right_stick: Vec2::ZERO,
            dpad: Vec2::ZERO,
        }
    }

    /// The controller pose for the current head and cursor (the view centre without a cursor).
    pub fn controller_pose(&self) -> Pose {
        cursor_ray(&self.head, self.fov_y, self.size, self.cursor.unwrap_or(self.size * 0.5))
    }

    /// The events that bring the world's controller to the current cursor ray, if it moved.
    fn pose_events(&mut self, out: &mut Vec<InputEvent>) {
        let pose = self.controller_pose();
        if self.last_pose != Some(pose) {
            self.last_pose = Some(pose);
            out.push(InputEvent::ControllerPose { pose });
        }
    }

    /// The cursor moved to `pos` (pixels). A drag with the right button held turns the head.
    /// The controller pose follows at the next [`Controls::frame`] (or button), so a burst of
    /// mouse motion costs one pose event per frame, not one per motion event.
    pub fn cursor_moved(&mut self, pos: Vec2) -> Vec<InputEvent> {
        let mut out = Vec::new();
        if let (Some(from), Some(_)) = (self.right_drag_from, self.cursor) {
            let d = pos - from;
            self.head = turn(&self.head, -d.x * TURN_PER_PIXEL, -d.y * TURN_PER_PIXEL);
            self.right_drag_from = Some(pos);
            out.push(InputEvent::HeadPose { pose: self.head });
        }
        self.cursor = Some(pos);
        out
    }

    /// A mouse button went down or up over the 3D view. The controller pose is sent first, so
    /// that the button acts where the cursor is.
    pub fn mouse_button(&mut self, button: MouseButton, pressed: bool) -> Vec<InputEvent> {
        let mut out = Vec::new();
        let b = match button {
            MouseButton::Left => Button::Trigger,
            MouseButton::Right => {
                self.right_drag_from = if pressed { self.cursor } else { None };
                Button::Bumper
            }
            _ => return out,
        };
        self.pose_events(&mut out);
        out.push(if pressed { InputEvent::ButtonDown { button: b } } else { InputEvent::ButtonUp { button: b } });
        out
    }

    /// The wheel turned by `lines` notches (positive = away from the user = touchpad front).
    pub fn wheel(&mut self, lines: f32) {
        if lines != 0.0 {
            self.wheel_dir = lines.signum();
            self.wheel_left = (self.wheel_left + lines.abs() * WHEEL_PULSE_S).min(1.0);
        }
    }

    /// A key went down or up. `menu_open` is whether the world's model menu is open (Tab and M
    /// close it then). Returns the events and the app-level actions.
    pub fn key(&mut self, code: KeyCode, pressed: bool, menu_open: bool) -> (Vec<InputEvent>, AppKeys) {
        let mut out = Vec::new();
        let mut app = AppKeys::default();
        match code {
            KeyCode::KeyW => self.walk_keys[0] = pressed,
            KeyCode::KeyS => self.walk_keys[1] = pressed,
            KeyCode::KeyA => self.walk_keys[2] = pressed,
            KeyCode::KeyD => self.walk_keys[3] = pressed,
            KeyCode::ArrowUp => self.pad_keys[0] = pressed,
            KeyCode::ArrowDown => self.pad_keys[1] = pressed,
            KeyCode::KeyQ => self.pad_keys[2] = pressed,
            KeyCode::KeyE => self.pad_keys[3] = pressed,
            KeyCode::Tab | KeyCode::KeyM => out.extend(menu_button(pressed, menu_open)),
            KeyCode::Escape if pressed => app.quit = true,
            KeyCode::F1 | KeyCode::KeyH if pressed => app.toggle_help = true,
            KeyCode::F3 if pressed => app.toggle_debug = true,
            _ => {}
        }
        (out, app)
    }

    /// A gamepad input. `menu_open` as for [`Controls::key`].
    pub fn pad(&mut self, input: PadInput, menu_open: bool) -> Vec<InputEvent> {
        use gilrs::{Axis, Button as B};
        let mut out = Vec::new();
        match input {
            PadInput::Button(b, pressed) => {
                let button = match b {
                    B::South | B::RightTrigger | B::RightTrigger2 => Some(Button::Trigger),
                    B::East | B::LeftTrigger | B::LeftTrigger2 => Some(Button::Bumper),
                    B::North => Some(Button::Touchpad),
                    B::Start | B::Select => {
                        out.extend(menu_button(pressed, menu_open));
                        None
                    }
                    B::DPadUp => {
                        self.dpad.y = if pressed { 1.0 } else { 0.0 };
                        None
                    }
                    B::DPadDown => {
                        self.dpad.y = if pressed { -1.0 } else { 0.0 };
                        None
                    }
                    B::DPadLeft => {
                        self.dpad.x = if pressed { -1.0 } else { 0.0 };
                        None
                    }
                    B::DPadRight => {
                        self.dpad.x = if pressed { 1.0 } else { 0.0 };
                        None
                    }
                    _ => None,
                };
                if let Some(button) = button {
                    self.pose_events(&mut out);
                    out.push(if pressed { InputEvent::ButtonDown { button } } else { InputEvent::ButtonUp { button } });
                }
            }
            PadInput::Axis(axis, v) => {
                let v = if v.abs() < STICK_DEAD_ZONE { 0.0 } else { v.clamp(-1.0, 1.0) };
                match axis {
                    Axis::LeftStickX => self.left_stick.x = v,
                    Axis::LeftStickY => self.left_stick.y = v,
                    Axis::RightStickX => self.right_stick.x = v,
                    Axis::RightStickY => self.right_stick.y = v,
                    Axis::DPadX => self.dpad.x = v,
                    Axis::DPadY => self.dpad.y = v,
                    _ => {}
                }
            }
        }
        out
    }

    /// The touchpad deflection the held keys, the wheel and the D-pad ask for now.
    pub fn touchpad_axes(&self) -> Vec2 {
        let k = |a: bool, b: bool| (a as i32 - b as i32) as f32;
        let mut axes =
            Vec2::new(k(self.pad_keys[3], self.pad_keys[2]), k(self.pad_keys[0], self.pad_keys[1])) + self.dpad;
        if self.wheel_left > 0.0 {
            axes.y += self.wheel_dir;
        }
        axes.clamp(Vec2::splat(-1.0), Vec2::splat(1.0))
    }

    /// Advances the continuous inputs by `dt` wall-clock seconds: walking and stick turning move
    /// the head, the wheel pulse runs down, and the touchpad follows. Returns the events for the
    /// changes (head pose, controller pose, touchpad axes).
    pub fn frame(&mut self, dt: f32) -> Vec<InputEvent> {
        let mut out = Vec::new();
        let k = |a: bool, b: bool| (a as i32 - b as i32) as f32;
        let mut dir = Vec2::new(k(self.walk_keys[3], self.walk_keys[2]), k(self.walk_keys[0], self.walk_keys[1]));
        dir += self.left_stick;
        let dt = dt.clamp(0.0, 0.25);
        let mut head = self.head;
        if dir != Vec2::ZERO {
            head = walk(&head, dir, dt);
        }
        if self.right_stick != Vec2::ZERO {
            head = turn(&head, -self.right_stick.x * STICK_TURN_RATE * dt, self.right_stick.y * STICK_TURN_RATE * dt);
        }
        if head != self.head {
            self.head = head;
            out.push(InputEvent::HeadPose { pose: head });
        }
        self.pose_events(&mut out);
        let axes = self.touchpad_axes();
        if axes != self.last_axes {
            self.last_axes = axes;
            out.push(InputEvent::TouchpadAxes { axes });
        }
        self.wheel_left = (self.wheel_left - dt).max(0.0);
        out
    }
}

/// Menu button events: a press opens the menu (or closes it when it is open), a release lets
/// the button up.
fn menu_button(pressed: bool, menu_open: bool) -> Vec<InputEvent> {
    match (pressed, menu_open) {
        (true, false) => vec![InputEvent::ButtonDown { button: Button::Menu }],
        (true, true) => vec![InputEvent::CloseMenu],
        (false, _) => vec![InputEvent::ButtonUp { button: Button::Menu }],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn head() -> Pose {
        Pose::looking_at(Vec3::new(0.0, 1.7, 6.0), Vec3::new(0.0, 0.5, -4.0))
    }

    #[test]
    fn the_ray_through_the_centre_is_the_head_forward() {
        let h = head();
        let p = cursor_ray(&h, 1.0, Vec2::new(1280.0, 720.0), Vec2::new(640.0, 360.0));
        assert!((p.forward() - h.forward()).length() < 1e-5);
        assert_eq!(p.position, h.position);
    }

    #[test]
    fn project_inverts_cursor_ray() {
        let h = head();
        let size = Vec2::new(1280.0, 720.0);
        for cursor in [Vec2::new(10.0, 20.0), Vec2::new(1000.0, 700.0), Vec2::new(640.0, 100.0)] {
            let p = cursor_ray(&h, 60f32.to_radians(), size, cursor);
            let point = p.position + p.forward() * 7.0;
            let back = project(&h, 60f32.to_radians(), size, point, 0.01).unwrap();
            assert!((back - cursor).length() < 0.05, "{cursor} -> {back}");
        }
        assert!(project(&h, 1.0, size, h.position - h.forward(), 0.01).is_none());
    }

    #[test]
    fn a_cursor_low_in_the_view_aims_below_the_centre() {
        let h = head();
        let low = cursor_ray(&h, 1.0, Vec2::new(800.0, 600.0), Vec2::new(400.0, 590.0));
        assert!(low.forward().y < h.forward().y - 0.1);
        let right = cursor_ray(&h, 1.0, Vec2::new(800.0, 600.0), Vec2::new(790.0, 300.0));
        assert!(right.forward().x > 0.2, "looking north, the right edge is east");
    }

    #[test]
    fn walking_forward_follows_the_view_and_keeps_height() {
        let h = Pose::looking_at(Vec3::new(0.0, 1.7, 0.0), Vec3::new(1.0, 1.0, 0.0));
        let w = walk(&h, Vec2::new(0.0, 1.0), 0.5);
        assert!((w.position - Vec3::new(WALK_SPEED * 0.5, 1.7, 0.0)).length() < 1e-4, "{}", w.position);
        let r = walk(&h, Vec2::new(1.0, 0.0), 1.0);
        assert!((r.position.z - WALK_SPEED).abs() < 1e-4, "right of east is south (+Z): {}", r.position);
    }

    #[test]
    fn turning_round_trips_and_clamps_pitch() {
        let h = head();
        let (y, p) = yaw_pitch(&h);
        let t = turn(&turn(&h, 0.3, 0.1), -0.3, -0.1);
        let (y2, p2) = yaw_pitch(&t);
        assert!((y - y2).abs() < 1e-4 && (p - p2).abs() < 1e-4);
        let up = turn(&h, 0.0, 10.0);
        assert!((yaw_pitch(&up).1 - MAX_PITCH).abs() < 1e-3);
    }

    #[test]
    fn left_button_is_trigger_after_a_pose_and_right_is_bumper() {
        let mut c = Controls::new(head(), 1.0, Vec2::new(800.0, 600.0));
        assert!(c.cursor_moved(Vec2::new(400.0, 500.0)).is_empty(), "motion alone waits for the frame");
        let down = c.mouse_button(MouseButton::Left, true);
        assert_eq!(down.len(), 2);
        let InputEvent::ControllerPose { pose } = down[0] else { panic!("the pose comes first: {down:?}") };
        assert_eq!(pose, cursor_ray(&head(), 1.0, Vec2::new(800.0, 600.0), Vec2::new(400.0, 500.0)));
        assert_eq!(down[1], InputEvent::ButtonDown { button: Button::Trigger });
        assert!(c.frame(0.016).is_empty(), "pose unchanged: no repeat");
        c.cursor_moved(Vec2::new(410.0, 500.0));
        c.cursor_moved(Vec2::new(420.0, 500.0));
        let moved = c.frame(0.016);
        assert_eq!(moved.len(), 1, "one pose per frame: {moved:?}");
        let up = c.mouse_button(MouseButton::Left, false);
        assert_eq!(up, vec![InputEvent::ButtonUp { button: Button::Trigger }]);
        let b = c.mouse_button(MouseButton::Right, true);
        assert_eq!(b.last(), Some(&InputEvent::ButtonDown { button: Button::Bumper }));
    }

    #[test]
    fn right_drag_turns_the_head() {
        let mut c = Controls::new(head(), 1.0, Vec2::new(800.0, 600.0));
        c.cursor_moved(Vec2::new(400.0, 300.0));
        c.mouse_button(MouseButton::Right, true);
        let ev = c.cursor_moved(Vec2::new(300.0, 300.0));
        assert!(matches!(ev[0], InputEvent::HeadPose { .. }));
        let (y0, _) = yaw_pitch(&head());
        assert!(yaw_pitch(&c.head).0 > y0 + 0.3, "dragging left turns left");
    }

    #[test]
    fn keys_map_to_touchpad_menu_and_walking() {
        let mut c = Controls::new(head(), 1.0, Vec2::new(800.0, 600.0));
        c.frame(0.016);
        c.key(KeyCode::ArrowUp, true, false);
        c.key(KeyCode::KeyE, true, false);
        assert!(c.frame(0.016).contains(&InputEvent::TouchpadAxes { axes: Vec2::new(1.0, 1.0) }));
        c.key(KeyCode::ArrowUp, false, false);
        c.key(KeyCode::KeyE, false, false);
        assert!(c.frame(0.016).contains(&InputEvent::TouchpadAxes { axes: Vec2::ZERO }));
        assert_eq!(c.key(KeyCode::Tab, true, false).0, vec![InputEvent::ButtonDown { button: Button::Menu }]);
        assert_eq!(c.key(KeyCode::KeyM, true, true).0, vec![InputEvent::CloseMenu]);
        assert!(c.key(KeyCode::Escape, true, false).1.quit);
        c.key(KeyCode::KeyW, true, false);
        let ev = c.frame(0.5);
        assert!(matches!(ev[0], InputEvent::HeadPose { .. }));
        assert!(c.head.position.z < 6.0 - 0.45, "W walks north (a frame counts at most 0.25 s): {}", c.head.position);
    }

    #[test]
    fn a_wheel_notch_is_a_short_touchpad_pulse() {
        let mut c = Controls::new(head(), 1.0, Vec2::new(800.0, 600.0));
        c.frame(0.016);
        c.wheel(-1.0);
        assert!(c.frame(0.05).contains(&InputEvent::TouchpadAxes { axes: Vec2::new(0.0, -1.0) }));
        c.frame(0.05);
        c.frame(0.05);
        assert!(c.frame(0.05).contains(&InputEvent::TouchpadAxes { axes: Vec2::ZERO }));
    }

    #[test]
    fn the_gamepad_drives_the_same_controller() {
        let mut c = Controls::new(head(), 1.0, Vec2::new(800.0, 600.0));
        let t = c.pad(PadInput::Button(gilrs::Button::South, true), false);
        assert_eq!(t.last(), Some(&InputEvent::ButtonDown { button: Button::Trigger }));
        let b = c.pad(PadInput::Button(gilrs::Button::East, true), false);
        assert_eq!(b.last(), Some(&InputEvent::ButtonDown { button: Button::Bumper }));
        assert_eq!(
            c.pad(PadInput::Button(gilrs::Button::Start, true), false),
            vec![InputEvent::ButtonDown { button: Button::Menu }]
        );
        c.pad(PadInput::Button(gilrs::Button::DPadLeft, true), false);
        assert!(c.frame(0.016).contains(&InputEvent::TouchpadAxes { axes: Vec2::new(-1.0, 0.0) }));
        c.pad(PadInput::Axis(gilrs::Axis::LeftStickY, 1.0), false);
        let before = c.head.position;
        c.frame(0.5);
        assert!(c.head.position.z < before.z - 0.45);
        c.pad(PadInput::Axis(gilrs::Axis::LeftStickY, 0.1), false);
        let still = c.head.position;
        c.frame(0.5);
        assert_eq!(c.head.position, still, "inside the dead zone the head stays");
    }
}
