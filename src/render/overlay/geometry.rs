//! Interaction visuals as plain geometry built each frame from [`OverlayScene`] (which
//! `render::extract` copies from the world): the controller and
//! its ray, the hit marker, the anchor ball (green, or white when armed), the selection's
//! bounding box with its corner and edge handles, and the running task's target markers.
//! The controller is the Magic Leap One model ([`super::controller`]) when it loaded, else a
//! small dark box.

use glam::{Quat, Vec2, Vec3};

use super::controller::{ControllerInput, ControllerModel, TOUCH_DOT, TOUCH_DOT_RADIUS};

/// The controller as the overlay draws it.
#[derive(Clone, Copy, Debug)]
pub struct OverlayController {
    /// The ray's origin, metres.
    pub origin: Vec3,
    /// The ray's unit direction.
    pub dir: Vec3,
    /// The controller's orientation.
    pub rotation: Quat,
    /// Whether the trigger is held (the ray turns yellow).
    pub trigger: bool,
    /// Whether the bumper is held.
    pub bumper: bool,
    /// Whether the touchpad is pressed.
    pub touchpad_pressed: bool,
    /// The touch point, each axis in [−1, 1] (+Y away from the user); zero when untouched.
    pub touchpad: Vec2,
}

impl OverlayController {
    /// What the controller's model shows.
    pub fn input(&self) -> ControllerInput {
        ControllerInput {
            trigger: self.trigger,
            squeeze: self.bumper,
            touchpad_pressed: self.touchpad_pressed,
            touchpad: self.touchpad,
        }
    }
}

/// The point the controller ray hits.
#[derive(Clone, Copy, Debug)]
pub struct OverlayHit {
    /// Whether the ray hits anything.
    pub visible: bool,
    /// Distance along the ray, metres.
    pub distance: f32,
    /// The hit point, metres.
    pub position: Vec3,
    /// The surface normal there.
    pub normal: Vec3,
    /// Whether the hit is on water, where nothing can be planted (the marker turns red and
    /// gets a ring).
    pub on_water: bool,
}

/// The anchor ball below a dragged tree.
#[derive(Clone, Copy, Debug)]
pub struct OverlayAnchor {
    /// Whether it is shown.
    pub visible: bool,
    /// Whether a release would snap (white) or not (green).
    pub armed: bool,
    /// Its centre, metres.
    pub position: Vec3,
    /// The drop from the ball to the plane below, metres.
    pub distance: f32,
}

/// The selected tree's bounding box.
#[derive(Clone, Copy, Debug)]
pub struct OverlaySelection {
    /// The box's centre, metres.
    pub center: Vec3,
    /// The box's orientation (a yaw).
    pub rotation: Quat,
    /// Half extents, metres.
    pub half_extents: Vec3,
}

/// One target marker of the running task.
#[derive(Clone, Copy, Debug)]
pub struct OverlayTarget {
    /// Where a tree should go, metres.
    pub position: Vec3,
    /// Whether a tree satisfies it.
    pub done: bool,
}

/// A participant drawn as a figure: a head with a nose towards where it looks, and its ray (a
/// video's ghosts, and the participant itself seen from another camera).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlayGhost {
    /// The head's position, metres.
    pub head: Vec3,
    /// The head's orientation; it looks along its −Z axis.
    pub head_rotation: Quat,
    /// The ray's origin and unit direction.
    pub ray: (Vec3, Vec3),
    /// The ray's drawn length, metres (to its hit, or a fixed length).
    pub ray_length: f32,
    /// Linear RGBA colour.
    pub color: [f32; 4],
    /// Solid (the chosen participant) or a wire figure (the others).
    pub solid: bool,
}

/// The radius of a ghost's head, metres.
pub const GHOST_HEAD_M: f32 = 0.12;

/// What the overlay draws, copied from the world by `render::extract`.
#[derive(Clone, Debug, Default)]
pub struct OverlayScene {
    /// The controllers.
    pub controllers: Vec<OverlayController>,
    /// The hit marker.
    pub hit: Option<OverlayHit>,
    /// The anchor balls.
    pub anchors: Vec<OverlayAnchor>,
    /// The selections that hold a tree.
    pub selections: Vec<OverlaySelection>,
    /// The task's targets.
    pub targets: Vec<OverlayTarget>,
    /// The radius within which a target counts as reached, metres.
    pub target_tolerance: f32,
    /// The longest ray, metres (`Config::max_ray_length`).
    pub max_ray_length: f32,
    /// The radius of a box handle for picking, metres (`Config::handle_radius`).
    pub handle_radius: f32,
    /// The eye (the head's position), metres: markers keep a minimum size as seen from it.
    pub eye: Vec3,
    /// Participants drawn as figures ([`OverlayGhost`]).
    pub ghosts: Vec<OverlayGhost>,
}

/// One overlay vertex. A zero normal means "unlit".
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct OverlayVertex {
    /// World position.
    pub position: [f32; 3],
    /// Linear RGBA colour.
    pub color: [f32; 4],
    /// Normal, or zero for unlit lines.
    pub normal: [f32; 3],
}

/// Overlay geometry: a triangle list and a line list.
#[derive(Default)]
pub struct OverlayGeometry {
    /// Triangles (solid markers).
    pub triangles: Vec<OverlayVertex>,
    /// Lines (ray, box edges).
    pub lines: Vec<OverlayVertex>,
}

/// Colour of the anchor ball when a release would snap (armed).
pub const ANCHOR_ARMED: [f32; 4] = [1.0, 1.0, 1.0, 1.0];
/// Colour of the anchor ball when the tree is too far above the plane.
pub const ANCHOR_FAR: [f32; 4] = [0.1, 0.9, 0.15, 1.0];

impl OverlayGeometry {
    fn line(&mut self, a: Vec3, b: Vec3, color: [f32; 4]) {
        for p in [a, b] {
            self.lines.push(OverlayVertex { position: p.to_array(), color, normal: [0.0; 3] });
        }
    }

    fn tri(&mut self, p: [Vec3; 3], n: [Vec3; 3], color: [f32; 4]) {
        for k in 0..3 {
            self.triangles.push(OverlayVertex { position: p[k].to_array(), color, normal: n[k].to_array() });
        }
    }

    /// A UV sphere.
    pub fn sphere(&mut self, c: Vec3, r: f32, color: [f32; 4]) {
        let (rings, segs) = (8, 12);
        let pt = |i: u32, j: u32| {
            let th = std::f32::consts::PI * i as f32 / rings as f32;
            let ph = std::f32::consts::TAU * j as f32 / segs as f32;
            Vec3::new(th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin())
        };
        for i in 0..rings {
            for j in 0..segs {
                let (a, b, cc, d) = (pt(i, j), pt(i + 1, j), pt(i + 1, j + 1), pt(i, j + 1));
                self.tri([c + a * r, c + cc * r, c + b * r], [a, cc, b], color);
                self.tri([c + a * r, c + d * r, c + cc * r], [a, d, cc], color);
            }
        }
    }

    /// An oriented box with half extents `h`.
    pub fn cuboid(&mut self, c: Vec3, h: Vec3, rot: Quat, color: [f32; 4]) {
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let mut n = Vec3::ZERO;
                n[axis] = sign;
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let corner = |su: f32, sv: f32| {
                    let mut p = n * h;
                    p[u] = su * h[u];
                    p[v] = sv * h[v];
                    c + rot * p
                };
                let (a, b, cc, d) = (corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0));
                let wn = rot * n;
                let (p0, p1) = if sign > 0.0 { ([a, b, cc], [a, cc, d]) } else { ([a, cc, b], [a, d, cc]) };
                self.tri(p0, [wn; 3], color);
                self.tri(p1, [wn; 3], color);
            }
        }
    }

    /// A wire sphere: three great circles.
    pub fn wire_sphere(&mut self, c: Vec3, r: f32, rot: Quat, color: [f32; 4]) {
        let segs = 16;
        for axis in 0..3 {
            let p = |j: u32| {
                let a = std::f32::consts::TAU * j as f32 / segs as f32;
                let (x, y) = (a.cos() * r, a.sin() * r);
                let v = match axis {
                    0 => Vec3::new(0.0, x, y),
                    1 => Vec3::new(x, 0.0, y),
                    _ => Vec3::new(x, y, 0.0),
                };
                c + rot * v
            };
            for j in 0..segs {
                self.line(p(j), p(j + 1), color);
            }
        }
    }

    /// A participant as a figure: head, nose and ray.
    pub fn ghost(&mut self, g: &OverlayGhost) {
        let nose = g.head + g.head_rotation * Vec3::new(0.0, 0.0, -GHOST_HEAD_M * 1.2);
        if g.solid {
            self.sphere(g.head, GHOST_HEAD_M, g.color);
            self.cuboid(nose, Vec3::new(0.025, 0.025, 0.05), g.head_rotation, g.color);
        } else {
            self.wire_sphere(g.head, GHOST_HEAD_M, g.head_rotation, g.color);
            self.line(g.head, nose + g.head_rotation * Vec3::new(0.0, 0.0, -0.05), g.color);
        }
        let (o, d) = g.ray;
        self.line(o, o + d * g.ray_length.max(0.0), g.color);
    }

    /// A flat ring on the ground, facing up.
    pub fn ring(&mut self, c: Vec3, r_in: f32, r_out: f32, color: [f32; 4]) {
        let segs = 32;
        for j in 0..segs {
            let a0 = std::f32::consts::TAU * j as f32 / segs as f32;
            let a1 = std::f32::consts::TAU * (j + 1) as f32 / segs as f32;
            let p = |a: f32, r: f32| c + Vec3::new(a.cos() * r, 0.0, a.sin() * r);
            let (i0, o0, i1, o1) = (p(a0, r_in), p(a0, r_out), p(a1, r_in), p(a1, r_out));
            self.tri([i0, i1, o0], [Vec3::Y; 3], color);
            self.tri([o0, i1, o1], [Vec3::Y; 3], color);
        }
    }
}

/// The smallest angle, radians, that a target ring's outer radius and the hit marker's radius
/// subtend from the eye (about 8 pixels at 720 pixels over a 60° field of view).
pub const MIN_MARKER_ANGLE: f32 = 0.012;
/// Colour of the hit marker on ground, trees and handles (linear RGBA).
pub const MARKER: [f32; 4] = [0.2, 0.75, 1.0, 1.0];
/// Colour of the hit marker on water, where planting is refused (linear RGBA).
pub const MARKER_WATER: [f32; 4] = [1.0, 0.3, 0.15, 1.0];

/// Colour of a target ring while the controller's hit point is inside its tolerance.
pub const RING_LIT: [f32; 4] = [1.0, 0.95, 0.35, 1.0];

/// Aiming help: a marker's world size `size` (metres), grown so that at `distance` metres from
/// the eye it subtends at least [`MIN_MARKER_ANGLE`]. It only changes what is drawn.
pub fn min_on_screen(size: f32, distance: f32) -> f32 {
    size.max(distance.max(0.0) * MIN_MARKER_ANGLE.tan())
}

/// Colour of the controller's box, drawn when its model is missing (linear RGBA).
pub const CONTROLLER_BOX: [f32; 4] = [0.15, 0.15, 0.17, 1.0];

/// Builds the overlay geometry of a frame; the controllers are `model` when there is one.
pub fn build(scene: &OverlayScene, model: Option<&ControllerModel>) -> OverlayGeometry {
    let mut g = OverlayGeometry::default();
    let hit = scene.hit;
    let eye = scene.eye;
    for c in &scene.controllers {
        let (o, d) = (c.origin, c.dir);
        if let Some(m) = model {
            let tris = &mut g.triangles;
            let dot = m.pose(&c.input(), m.placement(o, c.rotation), &mut |p, n, color| {
                tris.push(OverlayVertex { position: p.to_array(), color, normal: n.to_array() })
            });
            if let Some(dot) = dot {
                g.sphere(dot, TOUCH_DOT_RADIUS, TOUCH_DOT);
            }
        } else {
            // The controller body: a small dark box along the ray.
            g.cuboid(o - d * 0.06, Vec3::new(0.02, 0.015, 0.06), c.rotation, CONTROLLER_BOX);
        }
        let len = match hit {
            Some(h) if h.visible => h.distance,
            _ => scene.max_ray_length.min(30.0),
        };
        let col = if c.trigger { [1.0, 0.85, 0.2, 1.0] } else { [0.3, 0.8, 1.0, 1.0] };
        g.line(o, o + d * len, col);
    }
    if let Some(h) = hit {
        if h.visible {
            let color = if h.on_water { MARKER_WATER } else { MARKER };
            let r = min_on_screen(0.04, eye.distance(h.position));
            g.sphere(h.position, r, color);
            let n = h.normal.normalize_or(Vec3::Y);
            g.line(h.position, h.position + n * 0.25, color);
            if h.on_water {
                // A flat ring on the surface: not a place to plant.
                g.ring(h.position + Vec3::Y * 0.01, r * 2.0, r * 3.0, color);
            }
        }
    }
    for a in &scene.anchors {
        if a.visible {
            let color = if a.armed { ANCHOR_ARMED } else { ANCHOR_FAR };
            g.sphere(a.position, 0.12, color);
            g.line(a.position, a.position + Vec3::Y * a.distance.max(0.0), color);
        }
    }
    for s in &scene.selections {
        let rot = s.rotation;
        let h = s.half_extents;
        let corner = |i: u8| {
            s.center
                + rot
                    * Vec3::new(
                        if i & 1 != 0 { h.x } else { -h.x },
                        if i & 2 != 0 { h.y } else { -h.y },
                        if i & 4 != 0 { h.z } else { -h.z },
                    )
        };
        let yellow = [1.0, 0.85, 0.1, 1.0];
        for i in 0..8u8 {
            for bit in [1u8, 2, 4] {
                if i & bit == 0 {
                    g.line(corner(i), corner(i | bit), yellow);
                }
            }
        }
        let hs = scene.handle_radius * 0.6;
        for i in 0..8u8 {
            g.cuboid(corner(i), Vec3::splat(hs), rot, [1.0, 0.55, 0.1, 1.0]);
        }
        for e in 0..4u8 {
            let x = if e & 1 != 0 { h.x } else { -h.x };
            let z = if e & 2 != 0 { h.z } else { -h.z };
            g.sphere(s.center + rot * Vec3::new(x, 0.0, z), hs, [0.95, 0.35, 0.9, 1.0]);
        }
    }
    for ghost in &scene.ghosts {
        g.ghost(ghost);
    }
    for t in &scene.targets {
        // The ring lights up while the hit point is inside the target's tolerance.
        let aimed = hit.is_some_and(|h| {
            h.visible
                && glam::Vec2::new(h.position.x - t.position.x, h.position.z - t.position.z).length()
                    <= scene.target_tolerance
        });
        let color = if aimed && !t.done {
            RING_LIT
        } else if t.done {
            [0.2, 0.95, 0.3, 1.0]
        } else {
            [1.0, 0.2, 0.6, 1.0]
        };
        let base = t.position + Vec3::Y * 0.03;
        let outer = min_on_screen(scene.target_tolerance, eye.distance(base));
        g.ring(base, outer * 0.8, outer, color);
        g.cuboid(base + Vec3::Y * 0.3, Vec3::new(0.02, 0.3, 0.02), Quat::IDENTITY, color);
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(on_water: bool) -> OverlayScene {
        OverlayScene {
            controllers: Vec::new(),
            hit: Some(OverlayHit {
                visible: true,
                distance: 5.0,
                position: Vec3::new(0.0, -0.15, -4.0),
                normal: Vec3::Y,
                on_water,
            }),
            anchors: Vec::new(),
            selections: Vec::new(),
            targets: Vec::new(),
            target_tolerance: 0.0,
            max_ray_length: 30.0,
            handle_radius: 0.1,
            eye: Vec3::new(0.0, 1.7, 4.0),
            ghosts: Vec::new(),
        }
    }

    #[test]
    fn the_hit_marker_on_water_differs_from_the_one_on_ground() {
        let count = |g: &OverlayGeometry, c: [f32; 4]| g.triangles.iter().filter(|v| v.color == c).count();
        let ground = build(&scene(false), None);
        let water = build(&scene(true), None);
        assert!(count(&ground, MARKER) > 0 && count(&ground, MARKER_WATER) == 0);
        assert_eq!(count(&water, MARKER), 0, "no blue marker on water");
        // The sphere plus a ring: more triangles than the sphere alone, all in the water colour.
        assert!(count(&water, MARKER_WATER) > count(&ground, MARKER));
    }

    fn with_controller(input: ControllerInput) -> OverlayScene {
        let mut s = scene(false);
        let rotation = Quat::from_rotation_y(0.3);
        s.controllers.push(OverlayController {
            origin: Vec3::new(0.2, 1.2, 1.0),
            dir: rotation * Vec3::NEG_Z,
            rotation,
            trigger: input.trigger,
            bumper: input.squeeze,
            touchpad_pressed: input.touchpad_pressed,
            touchpad: input.touchpad,
        });
        s
    }

    fn model() -> ControllerModel {
        let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"))
            .join(crate::render::overlay::controller::MODEL_DIR);
        ControllerModel::load(&dir).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn without_a_model_the_controller_is_a_box() {
        let boxed = |g: &OverlayGeometry| g.triangles.iter().filter(|v| v.color == CONTROLLER_BOX).count();
        let g = build(&with_controller(ControllerInput::default()), None);
        assert_eq!(boxed(&g), 36, "a box: 6 faces of 2 triangles");
        let m = model();
        let g = build(&with_controller(ControllerInput::default()), Some(&m));
        assert_eq!(boxed(&g), 0, "no box with the model");
        let without = build(&scene(false), None).triangles.len();
        assert_eq!(g.triangles.len() - without, m.triangle_count() * 3);
    }

    #[test]
    fn the_model_follows_the_controller_and_its_buttons() {
        let m = model();
        let rest = build(&with_controller(ControllerInput::default()), Some(&m));
        // The model sits at the ray's origin, behind it.
        let c = with_controller(ControllerInput::default()).controllers[0];
        let body = |g: &OverlayGeometry| {
            g.triangles.iter().filter(|v| v.color != MARKER).map(|v| Vec3::from(v.position)).collect::<Vec<_>>()
        };
        assert!(body(&rest).iter().all(|p| p.distance(c.origin) < 0.2), "the model is at the controller");
        assert!(body(&rest).iter().all(|p| (*p - c.origin).dot(c.dir) < 1e-3), "the model lies behind the ray origin");
        // A pulled trigger moves some vertices; a touch adds the dot.
        let pulled = build(&with_controller(ControllerInput { trigger: true, ..Default::default() }), Some(&m));
        assert_eq!(pulled.triangles.len(), rest.triangles.len());
        let moved = rest.triangles.iter().zip(&pulled.triangles).filter(|(a, b)| a.position != b.position).count();
        assert!(moved > 0 && moved < rest.triangles.len() / 2, "{moved} vertices moved");
        let touched =
            build(&with_controller(ControllerInput { touchpad: Vec2::new(0.3, -0.4), ..Default::default() }), Some(&m));
        let dots = |g: &OverlayGeometry| g.triangles.iter().filter(|v| v.color == TOUCH_DOT).count();
        assert_eq!(dots(&rest), 0);
        assert!(dots(&touched) > 0);
    }
}
