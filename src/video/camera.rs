//! The video's cameras, each a pure function of the replayed state: the participant's head; a
//! shoulder camera behind and above the head that follows it smoothly (a recurrence over the
//! frames: the previous camera, the head now and the time between frames); the task area from
//! straight above (orthographic); and a slow orbit around the task area.

use crate::render::{Camera, TopView};
use glam::{Vec2, Vec3};
use grove_systems::components::{Head, Pose};

/// Which camera a video is drawn from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum CameraKind {
    /// The participant's own view.
    Head,
    /// Behind and above the participant's head, following it smoothly.
    Shoulder,
    /// The task area from straight above (orthographic).
    Top,
    /// A slow orbit around the task area.
    Orbit,
}

/// The ground rectangle a task is done in: its centre and half extents (X and Z), metres, and
/// the height of its ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaskArea {
    /// Centre, world X and Z.
    pub center: Vec2,
    /// Half the width (X) and depth (Z).
    pub half: Vec2,
    /// The ground's height, metres.
    pub ground_y: f32,
}

/// Metres of margin around the points a task area holds.
pub const AREA_MARGIN_M: f32 = 2.5;

impl TaskArea {
    /// The rectangle that holds `points` (the targets and where the participant stood) with a
    /// margin, at least 10 m across.
    pub fn around(points: &[Vec3], ground_y: f32) -> TaskArea {
        let finite: Vec<Vec2> = points.iter().filter(|p| p.is_finite()).map(|p| Vec2::new(p.x, p.z)).collect();
        if finite.is_empty() {
            return TaskArea { center: Vec2::ZERO, half: Vec2::splat(5.0 + AREA_MARGIN_M), ground_y };
        }
        let min = finite.iter().fold(Vec2::splat(f32::MAX), |a, p| a.min(*p));
        let max = finite.iter().fold(Vec2::splat(f32::MIN), |a, p| a.max(*p));
        TaskArea {
            center: (min + max) * 0.5,
            half: ((max - min) * 0.5 + Vec2::splat(AREA_MARGIN_M)).max(Vec2::splat(5.0)),
            ground_y,
        }
    }

    /// The same area widened on one side so that its width over depth is `aspect` (the image's),
    /// so that an orthographic view of it is not stretched.
    pub fn fitted(&self, aspect: f32) -> TaskArea {
        let aspect = aspect.max(1e-3);
        let mut half = self.half;
        if half.x / half.y < aspect {
            half.x = half.y * aspect;
        } else {
            half.y = half.x / aspect;
        }
        TaskArea { half, ..*self }
    }
}

/// The vertical field of view of the shoulder and orbit cameras, radians (60°).
pub const FOV_Y: f32 = std::f32::consts::FRAC_PI_3;
/// How far behind the head the shoulder camera sits, metres.
pub const SHOULDER_BACK_M: f32 = 1.5;
/// How far above the head the shoulder camera sits, metres.
pub const SHOULDER_UP_M: f32 = 0.6;
/// How far to the right of the head (the controller's side) the shoulder camera sits, metres.
pub const SHOULDER_RIGHT_M: f32 = 0.4;
/// How far ahead of the head the shoulder camera looks, metres.
pub const SHOULDER_AHEAD_M: f32 = 4.0;
/// The shoulder camera's time constant: it covers 63 % of a move of the head in this many
/// seconds, so that head jitter does not shake the picture.
pub const SHOULDER_LAG_S: f32 = 0.4;
/// Seconds for one turn of the orbit camera.
pub const ORBIT_PERIOD_S: f32 = 60.0;

/// The participant's view.
pub fn head(head: &Head) -> Camera {
    Camera { position: head.pose.position, rotation: head.pose.rotation, fov_y: head.fov_y }
}

/// The head's heading on the ground (its forward direction with the pitch removed).
fn heading(pose: &Pose) -> Vec3 {
    let f = pose.forward();
    Vec3::new(f.x, 0.0, f.z).try_normalize().unwrap_or(Vec3::NEG_Z)
}

/// Where the shoulder camera wants to be for this head, and the point it looks at.
pub fn shoulder_goal(head: &Head) -> (Vec3, Vec3) {
    let ahead = heading(&head.pose);
    let right = ahead.cross(Vec3::Y);
    let p = head.pose.position;
    let eye = p - ahead * SHOULDER_BACK_M + Vec3::Y * SHOULDER_UP_M + right * SHOULDER_RIGHT_M;
    let look = p + ahead * SHOULDER_AHEAD_M - Vec3::Y * 0.8;
    (eye, look)
}

/// The shoulder camera's state between frames: its eye and the point it looks at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shoulder {
    /// The eye, metres.
    pub eye: Vec3,
    /// The point looked at, metres.
    pub look: Vec3,
}

impl Shoulder {
    /// The camera it gives.
    pub fn camera(&self) -> Camera {
        Camera { position: self.eye, rotation: Pose::looking_at(self.eye, self.look).rotation, fov_y: FOV_Y }
    }
}

/// The shoulder camera `dt_s` seconds after `prev` (none: the first frame, placed at its goal),
/// following `head`: it moves towards its goal by `1 − e^(−dt/lag)`.
pub fn shoulder_step(prev: Option<Shoulder>, head: &Head, dt_s: f32) -> Shoulder {
    let (eye, look) = shoulder_goal(head);
    match prev {
        None => Shoulder { eye, look },
        Some(p) => {
            let k = 1.0 - (-dt_s.max(0.0) / SHOULDER_LAG_S).exp();
            Shoulder { eye: p.eye.lerp(eye, k), look: p.look.lerp(look, k) }
        }
    }
}

/// The task area from straight above, fitted to the image's `aspect`.
pub fn top(area: &TaskArea, aspect: f32) -> TopView {
    let a = area.fitted(aspect);
    TopView { min: a.center - a.half, max: a.center + a.half, eye_height: area.ground_y + 60.0 }
}

/// The orbit camera `t_s` seconds into the video: on a circle around the task area's centre
/// that keeps the whole area in view, a third of its radius up, looking at the centre; it
/// starts due south of the centre and turns anticlockwise seen from above.
pub fn orbit(area: &TaskArea, t_s: f32) -> Camera {
    let radius = area.half.length() * 1.6 + 4.0;
    let angle = std::f32::consts::TAU * t_s / ORBIT_PERIOD_S;
    let center = Vec3::new(area.center.x, area.ground_y, area.center.y);
    // South is +Z; anticlockwise from above (looking down −Y) runs from +Z towards +X.
    let eye = center + Vec3::new(angle.sin() * radius, radius * 0.45, angle.cos() * radius);
    Camera { position: eye, rotation: Pose::looking_at(eye, center).rotation, fov_y: FOV_Y }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    fn head_at(p: Vec3, yaw: f32) -> Head {
        Head { pose: Pose { position: p, rotation: Quat::from_rotation_y(yaw) }, fov_y: 1.0 }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        a.distance(b) < 1e-4
    }

    #[test]
    fn the_head_camera_is_the_head() {
        let h = head_at(Vec3::new(1.0, 1.6, 2.0), 0.3);
        let c = head(&h);
        assert_eq!((c.position, c.rotation, c.fov_y), (h.pose.position, h.pose.rotation, 1.0));
    }

    #[test]
    fn the_shoulder_camera_sits_behind_above_and_right_of_a_head_looking_north() {
        // Looking north (−Z): behind is +Z, right is +X.
        let (eye, look) = shoulder_goal(&head_at(Vec3::new(0.0, 1.6, 0.0), 0.0));
        assert!(close(eye, Vec3::new(0.4, 2.2, 1.5)), "{eye}");
        assert!(close(look, Vec3::new(0.0, 0.8, -4.0)), "{look}");
        // Turned to face west (−X, a quarter turn anticlockwise): behind is +X, right is −Z.
        let (eye, _) = shoulder_goal(&head_at(Vec3::ZERO, std::f32::consts::FRAC_PI_2));
        assert!(close(eye, Vec3::new(1.5, 0.6, -0.4)), "{eye}");
    }

    #[test]
    fn the_shoulder_camera_ignores_pitch_and_looks_forward() {
        let pitched = Head { pose: Pose { position: Vec3::ZERO, rotation: Quat::from_rotation_x(-0.6) }, fov_y: 1.0 };
        let (eye, _) = shoulder_goal(&pitched);
        assert!(close(eye, Vec3::new(0.4, 0.6, 1.5)), "{eye}");
        let c = Shoulder { eye, look: Vec3::new(0.4, 0.6, -10.0) }.camera();
        assert!((c.rotation * Vec3::NEG_Z).distance(Vec3::NEG_Z) < 1e-4);
    }

    #[test]
    fn the_shoulder_camera_follows_smoothly() {
        let a = head_at(Vec3::ZERO, 0.0);
        let first = shoulder_step(None, &a, 1.0 / 30.0);
        assert_eq!((first.eye, first.look), shoulder_goal(&a));
        // The head jumps 3 m east: one frame later the camera has moved a little of the way
        // (1 − e^(−(1/30)/0.4) ≈ 8 %), after five lags nearly all of it.
        let b = head_at(Vec3::new(3.0, 0.0, 0.0), 0.0);
        let next = shoulder_step(Some(first), &b, 1.0 / 30.0);
        let moved = next.eye.x - first.eye.x;
        assert!((moved - 3.0 * (1.0 - (-1.0f32 / 12.0).exp())).abs() < 1e-4, "{moved}");
        let mut s = next;
        for _ in 0..60 {
            s = shoulder_step(Some(s), &b, 1.0 / 30.0);
        }
        assert!(s.eye.distance(shoulder_goal(&b).0) < 0.02);
    }

    #[test]
    fn the_top_view_frames_the_area_at_the_image_aspect() {
        let area = TaskArea::around(&[Vec3::new(-4.0, 0.0, -2.0), Vec3::new(6.0, 0.0, 2.0)], 0.0);
        // 10 × 4 m of points with 2.5 m margins, at least 10 m deep: 15 × 10 m around (1, 0).
        assert_eq!(area.center, Vec2::new(1.0, 0.0));
        assert_eq!(area.half, Vec2::new(7.5, 5.0));
        let t = top(&area, 16.0 / 9.0);
        let (w, d) = (t.max.x - t.min.x, t.max.y - t.min.y);
        assert!((w / d - 16.0 / 9.0).abs() < 1e-4);
        assert!(w >= 15.0 && d >= 10.0 - 1e-4, "the area stays inside: {w} × {d}");
        assert_eq!((t.min + t.max) * 0.5, Vec2::new(1.0, 0.0));
    }

    #[test]
    fn the_orbit_starts_south_turns_and_keeps_looking_at_the_centre() {
        let area = TaskArea { center: Vec2::new(2.0, -3.0), half: Vec2::new(3.0, 4.0), ground_y: 0.5 };
        let r = 5.0 * 1.6 + 4.0;
        let c0 = orbit(&area, 0.0);
        assert!(close(c0.position, Vec3::new(2.0, 0.5 + r * 0.45, -3.0 + r)), "{}", c0.position);
        let quarter = orbit(&area, ORBIT_PERIOD_S / 4.0);
        assert!(close(quarter.position, Vec3::new(2.0 + r, 0.5 + r * 0.45, -3.0)), "{}", quarter.position);
        for c in [c0, quarter, orbit(&area, 17.0)] {
            let to_center = (Vec3::new(2.0, 0.5, -3.0) - c.position).normalize();
            assert!((c.rotation * Vec3::NEG_Z).distance(to_center) < 1e-4);
        }
    }
}
