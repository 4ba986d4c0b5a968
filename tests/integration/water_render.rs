//! The water renderer on whatever adapter wgpu finds (lavapipe in CI), on the pond scene
//! (`assets/scenes/pond.ron`).
//!
//! - The reflection is right: the birch on the far shore appears in the water where its mirror
//!   image projects (computed here from the camera, independently of the renderer), upside
//!   down; nothing below the surface shows in the reflection (the pond's bed, a sunken shrub),
//!   while the refraction does show the shrub.
//! - Ripples move: two times give two water images; calm water is a still mirror.
//! - Golden images of the pond from two viewpoints (small, no MSAA, a tolerance per test, as in
//!   tests/integration/render_golden.rs). Regenerate with `UPDATE_SNAPSHOTS=1 cargo test --test integration water_render::`;
//!   a failing comparison writes the actual image to `target/snapshot-failures/`.

use std::path::PathBuf;

use glam::Vec3;
use grove::render::offscreen::{self, Gpu};
use grove::render::{Camera, Renderer, WaterOutput, camera_matrix};
use grove_systems::Sim;
use grove_systems::catalogue::ModelId;
use grove_systems::components::Pose;
use grove_systems::scene::Scene;
use image::RgbaImage;

use crate::shared_gpu;
use shared_gpu::LOCK;

const PIXEL_THRESHOLD: u8 = 40;
/// The pond's surface height and centre, as `scripts/pond-scene.py` writes them.
const SURFACE_Y: f32 = -0.15;
const CENTRE: Vec3 = Vec3::new(0.0, SURFACE_Y, -6.0);
/// The birch on the far shore: its base, and its height (catalogue bounds of `birch-mesh`).
const BIRCH: Vec3 = Vec3::new(1.5, 0.0, -13.6);

fn gpu() -> &'static Gpu {
    shared_gpu::shared_gpu("water render tests")
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The pond, with the wind calm (so that trees stand still between two times) and the given
/// ripple strength, after one tick (so that the controller's hit marker is in place).
fn pond(ripples: f32) -> Sim {
    let mut scene = Scene::load(&root().join("assets/scenes/pond.ron")).unwrap();
    scene.wind.strength = 0.0;
    scene.wind.gust_strength = 0.0;
    scene.wind.gust_average = 0.0;
    scene.water[0].ripples = ripples;
    let mut sim = Sim::from_scene(&scene, scene.seed).unwrap();
    sim.run(1);
    sim
}

fn render(sim: &Sim, w: u32, h: u32, output: WaterOutput, water: bool) -> RgbaImage {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let g = gpu();
    let mut r = Renderer::new(&g.device, &g.queue, offscreen::FORMAT, w, h).unwrap();
    r.options.water_output = output;
    r.options.water = water;
    // The default impostor threshold scaled from 720 lines to this image's height, as a
    // 1280 × 720 frame would show the trees.
    r.options.impostor_pixels = grove::render::DEFAULT_IMPOSTOR_PIXELS * h as f32 / 720.0;
    offscreen::render_image(g, &mut r, sim).unwrap()
}

/// The pixel a world point projects to in the head's camera, as (column, row), unclamped.
fn project(sim: &Sim, p: Vec3, w: u32, h: u32) -> (f32, f32) {
    let head = sim.head();
    let camera = Camera { position: head.pose.position, rotation: head.pose.rotation, fov_y: head.fov_y };
    let q = camera_matrix(&camera, w as f32 / h as f32).project_point3(p);
    ((q.x * 0.5 + 0.5) * w as f32, (0.5 - q.y * 0.5) * h as f32)
}

fn differs(a: &RgbaImage, b: &RgbaImage, x: u32, y: u32) -> bool {
    let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
    (0..3).any(|c| p[c].abs_diff(q[c]) > 30)
}

fn despawn_tree_at(sim: &mut Sim, at: Vec3) {
    let mut found: Vec<hecs::Entity> = Vec::new();
    sim.for_each_tree(|v| {
        let t = v.transform;
        if (t.translation.x - at.x).abs() < 0.01 && (t.translation.z - at.z).abs() < 0.01 {
            found.extend(hecs::Entity::from_bits(v.id));
        }
    });
    assert_eq!(found.len(), 1, "one tree at {at}");
    sim.set_up().despawn(found[0]).unwrap();
}

/// The mean absolute channel difference over a rectangle (x0, y0, x1, y1).
fn mean_diff(a: &RgbaImage, b: &RgbaImage, rect: (u32, u32, u32, u32)) -> f64 {
    let (mut sum, mut n) = (0u64, 0u64);
    for y in rect.1..rect.3 {
        for x in rect.0..rect.2 {
            let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
            sum += (0..3).map(|c| u64::from(p[c].abs_diff(q[c]))).sum::<u64>();
            n += 3;
        }
    }
    sum as f64 / n as f64
}

/// A rectangle around the pond's centre in the image: all water in the pond scene's view.
fn pond_rect(sim: &Sim, w: u32, h: u32) -> (u32, u32, u32, u32) {
    let (cx, cy) = project(sim, CENTRE, w, h);
    let (hx, hy) = (w as f32 * 0.15, h as f32 * 0.06);
    ((cx - hx) as u32, (cy - hy) as u32, (cx + hx) as u32, (cy + hy) as u32)
}

#[test]
fn the_shore_birch_appears_mirrored_and_upside_down_in_the_water() {
    let (w, h) = (320, 240);
    let with = pond(0.0);
    let mut without = pond(0.0);
    despawn_tree_at(&mut without, BIRCH);
    for output in [WaterOutput::Full, WaterOutput::Reflection] {
        let a = render(&with, w, h, output, true);
        let b = render(&without, w, h, output, true);
        // Where the far shore meets the water, below the birch: the water's edge there is the
        // outline's point nearest the birch (the pond is a circle of radius 5.45 m).
        let edge = CENTRE + (Vec3::new(BIRCH.x, SURFACE_Y, BIRCH.z) - CENTRE).normalize() * 5.45;
        let (_, shore_row) = project(&with, edge, w, h);
        let (_, near_row) = project(&with, CENTRE + Vec3::new(0.0, 0.0, 5.0), w, h);
        // The birch itself stands above the shore line.
        let (bx, top_row) = project(&with, BIRCH + Vec3::Y * 7.0, w, h);
        assert!((0..shore_row as u32).any(|y| differs(&a, &b, bx as u32, y)), "{output:?}: the birch is drawn");
        assert!(top_row < shore_row);

        // Its mirror image: each height y of the birch is seen in the water where the point
        // mirrored in the surface, (x, 2h − y, z), projects. Heights 1..5 m that land on the
        // water (between the far shore and the near one) must show the birch there.
        let (mut landed, mut found) = (0, 0);
        let mut rows = Vec::new();
        for k in 0..=8 {
            let y = 1.0 + 0.5 * k as f32;
            let mirrored = Vec3::new(BIRCH.x, 2.0 * SURFACE_Y - y, BIRCH.z);
            let (mx, my) = project(&with, mirrored, w, h);
            if my <= shore_row + 3.0 || my >= near_row - 3.0 {
                continue;
            }
            landed += 1;
            rows.push(my);
            // Look within 1 m of the trunk's mirror (the crown is about 3 m wide), ±2 rows.
            let (x1, _) = project(&with, mirrored + Vec3::X * 1.0, w, h);
            let reach = (x1 - mx).abs().max(2.0) as i32;
            let hit = (-reach..=reach)
                .any(|dx| (-2..=2).any(|dy| differs(&a, &b, (mx as i32 + dx) as u32, (my as i32 + dy) as u32)));
            found += usize::from(hit);
        }
        assert!(landed >= 5, "{output:?}: the test's view shows {landed} crown heights in the water");
        assert!(found * 10 >= landed * 8, "{output:?}: the mirrored crown shows at {found} of {landed} heights");
        // Upside down: the higher a point of the birch, the lower its mirror image in the
        // picture (farther below the shore line), while the tree itself grows upwards.
        assert!(rows.windows(2).all(|r| r[1] > r[0]), "{rows:?}");

        // Right under the shore, in a column away from the birch's mirror, nothing changed.
        let quiet_col = (bx - w as f32 * 0.2) as u32;
        let moved = (shore_row as u32 + 4..near_row as u32 - 4).filter(|&y| differs(&a, &b, quiet_col, y)).count();
        assert!(moved <= 2, "{output:?}: {moved} pixels changed away from the mirror image");
    }
}

#[test]
fn nothing_below_the_surface_shows_in_the_reflection() {
    let (w, h) = (240, 180);
    let dry = pond(0.0);
    let mut sunk = pond(0.0);
    // A shrub standing on the bed at the pond's centre, 1.5 m down: its top (1.4 m) stays under
    // the surface.
    sunk.spawn_tree(ModelId(3), Vec3::new(CENTRE.x, -1.5, CENTRE.z), 0.0, 0.9, false);
    let rect = pond_rect(&dry, w, h);

    // Around where the shrub stands (the bed's centre, seen from the camera).
    let (sx, sy) = project(&dry, Vec3::new(CENTRE.x, -0.8, CENTRE.z), w, h);
    let changed = |a: &RgbaImage, b: &RgbaImage| {
        let (x0, y0) = ((sx - 15.0) as u32, (sy - 12.0) as u32);
        (y0..y0 + 24).flat_map(|y| (x0..x0 + 30).map(move |x| (x, y))).filter(|&(x, y)| differs(a, b, x, y)).count()
    };
    let a = render(&dry, w, h, WaterOutput::Reflection, true);
    let b = render(&sunk, w, h, WaterOutput::Reflection, true);
    let n = changed(&a, &b);
    assert!(n <= 1, "the sunken shrub shows in the reflection ({n} pixels changed)");
    // Without clipping, the mirrored camera would look up through the bed; with it, the middle
    // of the pond reflects the sky: bluer than it is red, and bright.
    let (mut r, mut g, mut bl) = (0.0, 0.0, 0.0);
    for y in rect.1..rect.3 {
        for x in rect.0..rect.2 {
            let p = a.get_pixel(x, y).0;
            r += f64::from(p[0]);
            g += f64::from(p[1]);
            bl += f64::from(p[2]);
        }
    }
    assert!(bl > r * 1.2 && bl > g, "the reflection in the middle is not sky: r {r:.0} g {g:.0} b {bl:.0}");

    // The refraction does see the shrub: the two textures look at different halves of space.
    let a = render(&dry, w, h, WaterOutput::Refraction, true);
    let b = render(&sunk, w, h, WaterOutput::Refraction, true);
    let n = changed(&a, &b);
    assert!(n >= 20, "the sunken shrub does not show in the refraction ({n} pixels changed)");
}

#[test]
fn ripples_move_and_calm_water_is_a_still_mirror() {
    let (w, h) = (200, 150);
    for (ripples, moving) in [(1.0, true), (0.0, false)] {
        let mut sim = pond(ripples);
        let rect = pond_rect(&sim, w, h);
        let first = render(&sim, w, h, WaterOutput::Full, true);
        sim.run(90);
        let later = render(&sim, w, h, WaterOutput::Full, true);
        let d = mean_diff(&first, &later, rect);
        if moving {
            assert!(d > 1.5, "ripples did not move in 1.5 s (mean difference {d:.2})");
        } else {
            assert!(d < 0.2, "calm water changed (mean difference {d:.2})");
        }
    }
    // Without water, the pond is its bed: the water changes what is drawn there.
    let sim = pond(1.0);
    let rect = pond_rect(&sim, w, h);
    let on = render(&sim, w, h, WaterOutput::Full, true);
    let off = render(&sim, w, h, WaterOutput::Full, false);
    assert!(mean_diff(&on, &off, rect) > 5.0, "--no-water changes nothing");
}

/// A tolerance for one golden image.
struct Tolerance {
    /// Largest allowed mean absolute difference per channel (0..255).
    mean_abs: f64,
    /// Largest allowed share of pixels over [`PIXEL_THRESHOLD`], in percent.
    percent_over: f64,
}

fn compare(name: &str, img: &RgbaImage, tol: Tolerance) {
    let path = root().join("tests/snapshots").join(format!("{name}.png"));
    if std::env::var("UPDATE_SNAPSHOTS").is_ok_and(|v| v == "1") {
        img.save(&path).unwrap();
        return;
    }
    let want = match image::open(&path) {
        Ok(i) => i.to_rgba8(),
        Err(e) => panic!("{}: cannot read the snapshot ({e}); create it with UPDATE_SNAPSHOTS=1", path.display()),
    };
    assert_eq!(want.dimensions(), img.dimensions(), "{name}: size differs from the snapshot");
    let (mut sum, mut over) = (0u64, 0u64);
    for (a, b) in want.pixels().zip(img.pixels()) {
        let worst = (0..3).map(|c| a.0[c].abs_diff(b.0[c])).max().unwrap_or(0);
        sum += (0..3).map(|c| u64::from(a.0[c].abs_diff(b.0[c]))).sum::<u64>();
        over += u64::from(worst > PIXEL_THRESHOLD);
    }
    let n = f64::from(img.width() * img.height());
    let (mean, percent) = (sum as f64 / (n * 3.0), over as f64 * 100.0 / n);
    if mean > tol.mean_abs || percent > tol.percent_over {
        let dir = root().join("target/snapshot-failures");
        let _ = std::fs::create_dir_all(&dir);
        let _ = img.save(dir.join(format!("{name}.png")));
        panic!(
            "{name}: differs from {} (mean abs diff {mean:.2} > {} or {percent:.2}% pixels over {PIXEL_THRESHOLD} > {}%)",
            path.display(),
            tol.mean_abs,
            tol.percent_over
        );
    }
}

fn set_head(sim: &mut Sim, eye: Vec3, target: Vec3) {
    sim.set_up().camera_pose(Pose::looking_at(eye, target));
}

#[test]
fn golden_pond_from_the_south() {
    let sim = pond(1.0);
    let img = render(&sim, 160, 120, WaterOutput::Full, true);
    compare("pond-south", &img, Tolerance { mean_abs: 3.0, percent_over: 3.0 });
}

#[test]
fn golden_pond_from_the_east() {
    let mut sim = pond(1.0);
    set_head(&mut sim, Vec3::new(11.0, 2.5, -4.0), Vec3::new(0.0, 0.0, -6.5));
    assert!(sim.water_bodies().len() == 1);
    let img = render(&sim, 160, 120, WaterOutput::Full, true);
    compare("pond-east", &img, Tolerance { mean_abs: 3.0, percent_over: 3.0 });
}
