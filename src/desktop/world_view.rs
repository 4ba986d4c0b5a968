//! A simple 3D view of the world drawn with egui's painter: shaded ground triangles, trees as
//! trunks and crowns, the hit marker, the anchor ball, the selection box and task targets.
//!
//! It uses the same camera as the controller ray ([`super::input_map::project`]), so what the
//! cursor points at is what it appears to point at. The app draws the wgpu renderer's frame
//! underneath when it has one; this view is the fallback and the overlay for markers.

use egui::{Color32, Painter, Pos2, Rect, Shape, Stroke};
use glam::{Vec2, Vec3};
use grove_systems::Sim;
use grove_systems::catalogue::ModelKind;
use grove_systems::components::Head;

use super::input_map::project;

const NEAR: f32 = 0.05;

/// The head (camera) of a world, or a default one.
pub fn head_of(sim: &Sim) -> Head {
    sim.head()
}

/// What to draw.
#[derive(Clone, Copy, Debug)]
pub struct ViewOptions {
    /// Draw the sky and the ground (off when the wgpu renderer has drawn them).
    pub scenery: bool,
    /// Draw the trees, the selection box, the hit marker and the anchor ball (off when the
    /// wgpu renderer has drawn them).
    pub trees: bool,
}

impl ViewOptions {
    /// Everything, or (when a renderer drew the world) only what the renderer does not draw.
    pub fn with_renderer(renderer: bool) -> ViewOptions {
        ViewOptions { scenery: !renderer, trees: !renderer }
    }
}

/// Paints the world as seen from its head into `rect` (normally the whole window).
pub fn paint_world(painter: &Painter, rect: Rect, sim: &Sim, options: ViewOptions) {
    let head = head_of(sim);
    let size = Vec2::new(rect.width(), rect.height());
    let to_screen =
        |p: Vec3| project(&head.pose, head.fov_y, size, p, NEAR).map(|s| Pos2::new(rect.min.x + s.x, rect.min.y + s.y));
    let sun_dir = sim.sun().map_or(Vec3::Y, |s| s.direction);

    if options.scenery {
        painter.rect_filled(rect, 0.0, Color32::from_rgb(150, 190, 230));
        let mut mesh = egui::Mesh::default();
        sim.for_each_plane(|_, plane| {
            let base = if plane.name == "ground" { [92.0, 128.0, 64.0] } else { [150.0, 130.0, 100.0] };
            for tri in &plane.triangles {
                let [a, b, c] = tri.map(|i| plane.vertices[i as usize]);
                let (Some(pa), Some(pb), Some(pc)) = (to_screen(a), to_screen(b), to_screen(c)) else { continue };
                if !(rect.contains(pa) || rect.contains(pb) || rect.contains(pc)) {
                    continue;
                }
                let n = (b - a).cross(c - a).normalize_or(Vec3::Y);
                let light = 0.55 + 0.45 * n.dot(sun_dir).max(0.0);
                let col = Color32::from_rgb((base[0] * light) as u8, (base[1] * light) as u8, (base[2] * light) as u8);
                let i = mesh.vertices.len() as u32;
                for p in [pa, pb, pc] {
                    mesh.colored_vertex(p, col);
                }
                mesh.add_triangle(i, i + 1, i + 2);
            }
        });
        painter.add(Shape::mesh(mesh));
    }

    if let Some(task) = sim.task() {
        let hit = sim.hit_marker();
        for (i, t) in task.def.targets.iter().enumerate() {
            let done = task.satisfied.get(i).is_some_and(|s| s.is_some());
            // Aiming help: the ring keeps a minimum size on screen, and lights up (white and
            // thicker) while the ray's hit point is inside the target's tolerance.
            let aimed = hit.visible
                && Vec2::new(hit.position.x - t.position.x, hit.position.z - t.position.z).length()
                    <= task.def.tolerance;
            let radius = grove::render::overlay::geometry::min_on_screen(
                task.def.tolerance,
                head.pose.position.distance(t.position),
            );
            let (color, width) = if done {
                (Color32::from_rgb(40, 200, 90), 2.0)
            } else if aimed {
                (Color32::WHITE, 4.0)
            } else {
                (Color32::from_rgb(250, 210, 40), 2.0)
            };
            ring(painter, &to_screen, t.position, radius, Stroke::new(width, color));
        }
    }

    if options.trees {
        let mut trees: Vec<(f32, Vec3, f32, ModelKind, f32)> = Vec::new();
        sim.for_each_tree(|v| {
            let Some(m) = sim.catalogue().get(v.model) else { return };
            let dist = (v.transform.translation - head.pose.position).length();
            trees.push((dist, v.transform.translation, m.height() * v.scale, m.kind, m.crown_radius * v.scale));
        });
        // Far trees first, so near ones cover them.
        trees.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (_, base, height, kind, radius) in trees {
            let top = base + Vec3::Y * height;
            let crown = base + Vec3::Y * (height * 0.65);
            let (Some(pb), Some(pt), Some(pc)) = (to_screen(base), to_screen(top), to_screen(crown)) else { continue };
            let r_px =
                to_screen(crown + head.pose.rotation * Vec3::X * radius).map_or(4.0, |p| (p - pc).length()).max(2.0);
            painter.line_segment([pb, pt], Stroke::new((r_px * 0.12).clamp(1.0, 8.0), Color32::from_rgb(100, 70, 40)));
            let green = match kind {
                ModelKind::Mesh => Color32::from_rgb(40, 110, 45),
                ModelKind::Billboard => Color32::from_rgb(80, 150, 60),
            };
            painter.circle(pc, r_px, green, Stroke::new(1.0, Color32::from_rgb(20, 60, 25)));
        }
    }

    if !options.trees {
        return;
    }
    let sel = sim.selection();
    if sel.tree.is_some() {
        let (s, c) = sel.yaw.sin_cos();
        let corner = |x: f32, y: f32, z: f32| {
            let l = sel.half_extents * Vec3::new(x, y, z);
            sel.center + Vec3::new(c * l.x + s * l.z, l.y, -s * l.x + c * l.z)
        };
        let pts: Vec<Option<Pos2>> = (0..8)
            .map(|i| {
                to_screen(corner(
                    if i & 1 == 1 { 1.0 } else { -1.0 },
                    if i & 2 == 2 { 1.0 } else { -1.0 },
                    if i & 4 == 4 { 1.0 } else { -1.0 },
                ))
            })
            .collect();
        for (a, b) in [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)] {
            if let (Some(pa), Some(pb)) = (pts[a], pts[b]) {
                painter.line_segment([pa, pb], Stroke::new(1.5, Color32::from_rgb(90, 200, 255)));
            }
        }
    }

    let ball = sim.anchor_ball();
    if ball.visible {
        if let Some(p) = to_screen(ball.position) {
            let col = if ball.armed { Color32::WHITE } else { Color32::from_rgb(40, 220, 60) };
            painter.circle(p, 7.0, col, Stroke::new(1.0, Color32::BLACK));
        }
    }
    let hit = sim.hit_marker();
    if hit.visible {
        if let Some(p) = to_screen(hit.position) {
            painter.circle_stroke(p, 6.0, Stroke::new(2.0, Color32::from_rgb(255, 80, 40)));
        }
    }
}

fn ring(painter: &Painter, to_screen: &impl Fn(Vec3) -> Option<Pos2>, centre: Vec3, radius: f32, stroke: Stroke) {
    let pts: Vec<Pos2> = (0..=24)
        .filter_map(|i| {
            let a = i as f32 / 24.0 * std::f32::consts::TAU;
            to_screen(centre + Vec3::new(a.cos() * radius, 0.02, a.sin() * radius))
        })
        .collect();
    if pts.len() > 2 {
        painter.add(Shape::line(pts, stroke));
    }
}
