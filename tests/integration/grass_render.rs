//! Grass on the GPU (whatever adapter wgpu finds; lavapipe in CI): golden images of a shell
//! lawn, a blade patch, a patch with a hole and blades bent near the camera, each with a
//! property that must hold whatever the snapshot says; the wind moves blades and a calm does
//! not; the compute pass culls; both kinds receive the trees' shadows; `--no-grass`; bad grass
//! fields exit 2 with one line.
//!
//! Images are small (160×120), without MSAA, compared with `tests/snapshots/<name>.png` as in
//! `tests/integration/render_golden.rs`, each with its tolerance. Regenerate with
//! `UPDATE_SNAPSHOTS=1 cargo test --test integration grass_render::`.

use crate::common;

use std::path::PathBuf;

use glam::Vec3;
use grove::render::Renderer;
use grove::render::grass::{BLOCK_BLADES, BladeCounts, BladeLists, LOD_CAPS};
use grove::render::offscreen::{self, Gpu};
use grove_systems::Sim;
use grove_systems::components::{HitMarker, HitTarget};
use grove_systems::scene::Scene;
use image::RgbaImage;

const W: u32 = 160;
const H: u32 = 120;
const PIXEL_THRESHOLD: u8 = 40;

use crate::shared_gpu;
use shared_gpu::LOCK;

fn gpu() -> &'static Gpu {
    shared_gpu::shared_gpu("grass tests")
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A 6 × 6 m flat plane (with an optional hole at the centre), one grass patch over all of it,
/// the camera at `eye` looking at `look`, the wind of `strength`.
fn scene(kind: &str, density: f32, hole: f32, strength: f32, eye: Vec3, look: Vec3) -> Scene {
    let holes = if hole > 0.0 { format!("(center: (0.0, 0.0), radius: {hole:?})") } else { String::new() };
    let text = format!(
        r#"Scene(
    name: "grass test", seed: 3,
    planes: [(name: "ground", shape: Grid(min: (-3.0, -3.0), size: (6.0, 6.0), cell: 0.25, elevation: 0.0, holes: [{holes}]))],
    sun: (latitude_deg: 47.4, longitude_deg: 8.5, utc: "2026-06-21T09:30:00Z"),
    wind: (direction: (1.0, 0.0, 0.3), strength: {strength:?}, density: 0.15, gust_average: 1.0, gust_strength: 0.3, gust_frequency: 0.3),
    grass: [(name: "patch", kind: {kind}, density: {density:?}, height: (0.15, 0.3), shells: 16)],
    camera: (position: ({:?}, {:?}, {:?}), look_at: ({:?}, {:?}, {:?}), fov_y_deg: 60.0),
)"#,
        eye.x, eye.y, eye.z, look.x, look.y, look.z
    );
    Scene::parse(&text, "grass test").unwrap()
}

fn sim(s: &Scene) -> Sim {
    Sim::from_scene(s, s.seed).unwrap()
}

/// A renderer at `w` × `h` with only the catalogue's models that `sim`'s trees use: loading
/// every model and baking its impostor atlas, as `Renderer::new` does, costs far more than
/// these small frames, and a model no tree uses draws nothing.
fn renderer_for(g: &Gpu, sim: &Sim, w: u32, h: u32) -> Renderer {
    let assets = grove::render::default_assets_dir();
    let mut r = Renderer::empty(&g.device, &g.queue, offscreen::FORMAT, w, h, &assets).unwrap();
    let mut used = Vec::new();
    sim.for_each_tree(|t| used.push(t.model));
    for m in grove_systems::catalogue::Catalogue::builtin().models.iter().filter(|m| used.contains(&m.id)) {
        let data = grove::models::load_model(&assets.join("trees").join(format!("{}.gltf", m.name))).unwrap();
        r.features.trees.set_model(m.id, &data);
    }
    r
}

fn render_with(sim: &Sim, grass: bool, bend: bool) -> (RgbaImage, BladeCounts) {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let g = gpu();
    let mut r = renderer_for(g, sim, W, H);
    r.options.grass = grass;
    r.options.grass_bend = bend;
    let img = offscreen::render_image(g, &mut r, sim).unwrap();
    let counts = r.features.grass.visible_blades().unwrap();
    (img, counts)
}

fn render(sim: &Sim) -> RgbaImage {
    render_with(sim, true, true).0
}

/// The mean absolute difference per channel (0..255) over a rectangle.
fn diff(a: &RgbaImage, b: &RgbaImage, rect: (u32, u32, u32, u32)) -> f64 {
    let (x0, y0, x1, y1) = rect;
    let mut sum = 0u64;
    for y in y0..y1 {
        for x in x0..x1 {
            let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
            sum += (0..3).map(|c| u64::from(p[c].abs_diff(q[c]))).sum::<u64>();
        }
    }
    sum as f64 / (3.0 * f64::from((x1 - x0) * (y1 - y0)))
}

/// The share of pixels in a rectangle that are grass green: green well above red and blue.
fn green_share(img: &RgbaImage, rect: (u32, u32, u32, u32)) -> f64 {
    let (x0, y0, x1, y1) = rect;
    let mut n = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            let p = img.get_pixel(x, y).0;
            n += usize::from(p[1] as f64 > 1.15 * p[0] as f64 && p[1] as f64 > 1.15 * p[2] as f64);
        }
    }
    n as f64 / f64::from((x1 - x0) * (y1 - y0))
}

fn compare(name: &str, img: &RgbaImage, mean_abs: f64, percent_over: f64) {
    let path = root().join("tests/snapshots").join(format!("{name}.png"));
    if std::env::var("UPDATE_SNAPSHOTS").is_ok_and(|v| v == "1") {
        img.save(&path).unwrap();
        return;
    }
    let want = image::open(&path)
        .unwrap_or_else(|e| {
            panic!("{}: cannot read the snapshot ({e}); create it with UPDATE_SNAPSHOTS=1", path.display())
        })
        .to_rgba8();
    assert_eq!(want.dimensions(), img.dimensions(), "{name}: size differs from the snapshot");
    let mean = diff(&want, img, (0, 0, W, H));
    let over = want
        .pixels()
        .zip(img.pixels())
        .filter(|(a, b)| (0..3).any(|c| a.0[c].abs_diff(b.0[c]) > PIXEL_THRESHOLD))
        .count();
    let percent = over as f64 * 100.0 / f64::from(W * H);
    if mean > mean_abs || percent > percent_over {
        let dir = root().join("target/snapshot-failures");
        let _ = std::fs::create_dir_all(&dir);
        let _ = img.save(dir.join(format!("{name}.png")));
        panic!(
            "{name}: differs from {} (mean abs diff {mean:.2} > {mean_abs} or {percent:.2}% pixels over {PIXEL_THRESHOLD} > {percent_over}%); actual image in target/snapshot-failures/",
            path.display()
        );
    }
}

const EYE: Vec3 = Vec3::new(0.0, 1.2, 3.5);
const LOOK: Vec3 = Vec3::new(0.0, 0.0, 0.0);

#[test]
fn shell_lawn() {
    let s = sim(&scene("Shells", 3000.0, 0.0, 0.0, EYE, LOOK));
    let (img, counts) = render_with(&s, true, true);
    assert_eq!(counts, BladeCounts::default(), "a shell lawn has no blades");
    let (bare, _) = render_with(&s, false, true);
    // The lawn covers the plane: the lower half of the image changes with it and is green.
    let lower = (0, H / 2, W, H);
    assert!(diff(&img, &bare, lower) > 8.0, "the shells changed nothing");
    assert!(green_share(&img, lower) > 0.9, "the lawn is not green: {}", green_share(&img, lower));
    compare("grass-shell-lawn", &img, 3.0, 3.0);
}

#[test]
fn blade_patch() {
    let s = sim(&scene("Blades", 600.0, 0.0, 0.0, EYE, LOOK));
    let (img, counts) = render_with(&s, true, true);
    // 36 m² at 600 per m²: about 21,600 blades, of which the frame sees most. At 120 pixels and
    // 60°, one metre at d covers 120 / (2 tan 30°) / d ≈ 104 / d pixels: 7 segments within
    // 104 / 156 ≈ 0.67 m, 3 within 104 / 30 ≈ 3.5 m, lines beyond. The eye is 1.2 m above the
    // patch's near edge, 6.6 m from its far edge: the middle and far levels are drawn.
    let BladeCounts { near, mid, far } = counts;
    assert!(counts.total() > 8_000 && counts.total() < 21_600, "{counts:?}");
    assert!(near == 0 && mid > 0 && far > mid, "{counts:?}");
    // From 0.3 m above the near edge, the blades from about 0.4 m (the view's lower edge) to
    // 0.67 m ahead are near ones.
    let low = sim(&scene("Blades", 600.0, 0.0, 0.0, Vec3::new(0.0, 0.3, 3.5), LOOK));
    let (_, low_counts) = render_with(&low, true, true);
    assert!(low_counts.near > 0 && low_counts.mid > 0 && low_counts.far > 0, "{low_counts:?}");
    let (bare, _) = render_with(&s, false, true);
    assert!(diff(&img, &bare, (0, H / 2, W, H)) > 8.0, "the blades changed nothing");
    compare("grass-blade-patch", &img, 4.0, 5.0);
}

#[test]
fn patch_with_a_hole() {
    let s = sim(&scene("Blades", 600.0, 1.0, 0.0, Vec3::new(0.0, 3.0, 2.5), LOOK));
    let img = render(&s);
    // The hole at the centre of the view shows no grass; the lawn around it does.
    let (cx, cy) = (W / 2, H / 2);
    let hole = green_share(&img, (cx - 6, cy - 4, cx + 6, cy + 4));
    let lawn = green_share(&img, (cx - 40, cy + 30, cx + 40, cy + 40));
    assert!(hole < 0.2 && lawn > 0.8, "green in the hole {hole:.2}, on the lawn {lawn:.2}");
    compare("grass-patch-with-hole", &img, 4.0, 5.0);
}

#[test]
fn blades_bend_near_the_camera_and_the_hit_point() {
    // A low camera over the patch: the blades below and in front of it bend away.
    let mut s = sim(&scene("Blades", 600.0, 0.0, 0.0, Vec3::new(0.0, 0.45, 1.8), Vec3::new(0.0, 0.0, 0.6)));
    let hit = Vec3::new(1.2, 0.0, -0.5);
    s.set_up().hit_marker(HitMarker {
        visible: true,
        position: hit,
        normal: Vec3::Y,
        distance: 2.0,
        target: HitTarget::Plane(0),
    });
    let (bent, _) = render_with(&s, true, true);
    let (upright, _) = render_with(&s, true, false);
    // Near the eye (the bottom of the image) the bend changes the picture; far beyond both
    // the eye's and the hit point's radius (the top rows of the lawn) it does not.
    let near = diff(&bent, &upright, (0, H - 30, W, H));
    assert!(near > 10.0, "bending changed the near blades by only {near:.1}");
    compare("grass-bent-near-camera", &bent, 4.0, 5.0);
}

#[test]
fn wind_moves_blades_and_a_calm_does_not() {
    for kind in ["Blades", "Shells"] {
        let windy = scene(kind, 600.0, 0.0, 1.0, EYE, LOOK);
        let mut s = sim(&windy);
        let a = render(&s);
        s.run(45);
        let b = render(&s);
        let moved = diff(&a, &b, (0, H / 2, W, H));
        assert!(moved > 1.0, "{kind}: the wind moved nothing ({moved:.2})");

        // In a calm only time passes; one tick first, so that the controller's ray has found
        // its hit point (the blades bend away from it) before the first frame.
        let calm = scene(kind, 600.0, 0.0, 0.0, EYE, LOOK);
        let mut s = sim(&calm);
        s.run(1);
        let a = render(&s);
        s.run(45);
        let b = render(&s);
        assert_eq!(diff(&a, &b, (0, 0, W, H)), 0.0, "{kind}: grass moved in a calm");
    }
}

/// The near and middle lists the cull pass left for a frame of `sim`.
fn lists(sim: &Sim) -> BladeLists {
    lists_at(sim, W, H).0
}

/// The lists, the blades drawn at each level and the image of a frame of `sim` at `w` × `h`.
fn lists_at(sim: &Sim, w: u32, h: u32) -> (BladeLists, BladeCounts, RgbaImage) {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let g = gpu();
    let mut r = renderer_for(g, sim, w, h);
    let img = offscreen::render_image(g, &mut r, sim).unwrap();
    let grass = &r.features.grass;
    (grass.listed_blades().unwrap(), grass.visible_blades().unwrap(), img)
}

/// Checks that `list` holds its blocks' blades one block after the other, each block's in the
/// order of their indices; the number of blocks.
fn block_runs(name: &str, list: &[u32]) -> usize {
    let mut seen = std::collections::HashSet::new();
    let mut blocks = 0;
    for run in list.chunk_by(|p, q| p / BLOCK_BLADES == q / BLOCK_BLADES) {
        assert!(seen.insert(run[0] / BLOCK_BLADES), "{name}: block {} in two runs", run[0] / BLOCK_BLADES);
        assert!(
            run.windows(2).all(|w| w[0] < w[1]),
            "{name}: block {} out of order: {:?}",
            run[0] / BLOCK_BLADES,
            &run[..run.len().min(40)]
        );
        blocks += 1;
    }
    blocks
}

#[test]
fn blades_are_drawn_in_the_same_order_every_frame() {
    // Where two blades meet at the same depth in a pixel, the one drawn first stays; so the
    // lists must not depend on the order the cull pass's invocations ran in. Each list holds
    // its blocks' blades one block after the other, each block's in the order of their indices.
    let s = sim(&scene("Blades", 600.0, 0.0, 0.0, Vec3::new(0.0, 0.25, 2.0), LOOK));
    let a = lists(&s);
    assert!(a.near.len() > 100 && a.mid.len() > 1_000, "near {} middle {}", a.near.len(), a.mid.len());
    for (name, list) in [("near", &a.near), ("middle", &a.mid)] {
        assert!(block_runs(name, list) > 1, "{name}: one block only");
    }
    for _ in 0..3 {
        assert_eq!(lists(&s), a, "the lists changed between two frames of one world");
    }
}

/// Checks a frame of `density` blades a square metre over the 6 × 6 m patch, seen from 1.2 m
/// above its edge at 1280 × 720, where the near list is full: whole blocks in order; each blade
/// listed once; the middle list its own blades, then the near ones that did not fit, each part
/// in block order; the same lists and image in the next frame. The blades drawn at each level.
fn full_near_list(density: f32) -> BladeCounts {
    let s = sim(&scene("Blades", density, 0.0, 0.0, Vec3::new(0.0, 1.2, 3.0), Vec3::new(0.0, 0.0, -1.0)));
    let (a, counts, image) = lists_at(&s, 1280, 720);
    let [near_cap, mid_cap] = LOD_CAPS;
    assert_eq!(counts.near, near_cap, "{counts:?}: the near list is not full");
    assert_eq!((a.near.len(), a.mid.len()), (near_cap as usize, counts.mid as usize));
    assert!(counts.mid > 0 && counts.mid <= mid_cap, "{counts:?}");
    block_runs("near", &a.near);
    let mut all: Vec<u32> = a.near.iter().chain(&a.mid).copied().collect();
    all.sort_unstable();
    let listed = all.len();
    all.dedup();
    assert_eq!(all.len(), listed, "{density}: {} blades listed twice", listed - all.len());
    // The middle list's longest prefix in block order (its own blades, and perhaps the first
    // near ones that did not fit); the rest must be in block order too.
    let mut seen = std::collections::HashSet::new();
    let split = (0..a.mid.len())
        .find(|&i| {
            let block = a.mid[i] / BLOCK_BLADES;
            if i > 0 && a.mid[i - 1] / BLOCK_BLADES == block { a.mid[i] <= a.mid[i - 1] } else { !seen.insert(block) }
        })
        .unwrap_or(a.mid.len());
    block_runs("the rest of the middle list", &a.mid[split..]);
    let (b, c, img) = lists_at(&s, 1280, 720);
    assert_eq!(c, counts);
    assert!(b == a, "{density}: the lists changed between two frames of one world");
    assert!(img == image, "{density}: the image changed between two frames of one world");
    counts
}

#[test]
fn a_full_near_list_passes_its_later_blades_on_in_order() {
    // 6,000 blades a square metre: more near blades than the near list holds, fewer than both
    // lists hold. The near list is filled in the order of the blocks; the blades past its end
    // go to the middle list after the middle list's own blades, and every one is drawn.
    let some = full_near_list(6_000.0);
    assert!(some.mid < LOD_CAPS[1], "{some:?}");
    // 20,000: more than both lists hold; the rest are drawn as far blades.
    let many = full_near_list(20_000.0);
    assert!(many.mid == LOD_CAPS[1] && many.far > 0, "{many:?}");
    assert!(many.total() > 3 * some.total(), "{some:?} {many:?}");
}

#[test]
fn blades_behind_the_camera_are_culled() {
    // Looking away from the patch, up into the sky: the cull pass keeps no blade.
    let s = sim(&scene("Blades", 600.0, 0.0, 0.0, Vec3::new(0.0, 1.0, 6.0), Vec3::new(0.0, 3.0, 12.0)));
    let (_, counts) = render_with(&s, true, true);
    assert_eq!(counts, BladeCounts::default());
    // From 17 m away and more every visible blade is a line (beyond 3.5 m at 120 pixels).
    let s = sim(&scene("Blades", 600.0, 0.0, 0.0, Vec3::new(0.0, 6.0, 20.0), LOOK));
    let (_, counts) = render_with(&s, true, true);
    assert!(counts.near == 0 && counts.mid == 0 && counts.far > 10_000, "{counts:?}");
}

/// Luminance (Rec. 709 weights on the 0..255 channels) of one pixel.
fn luma(img: &RgbaImage, x: u32, y: u32) -> f64 {
    let p = img.get_pixel(x, y).0;
    0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])
}

#[test]
fn grass_receives_the_trees_shadows() {
    // Four trees around an 8 × 8 m patch under a low morning sun, seen from 5 m straight above
    // its centre: the view holds only the patch, the trees stand outside it and their long
    // shadows fall into it. At 160 × 120 the blades are far (rasterised by the cull pass), at
    // 480 × 360 they are middle blades (shadowed per vertex).
    for (kind, w, h) in [("Shells", W, H), ("Blades", W, H), ("Blades", 3 * W, 3 * H)] {
        let text = format!(
            r#"Scene(
    name: "grass shadow test", seed: 3,
    planes: [(name: "ground", shape: Grid(min: (-12.0, -12.0), size: (24.0, 24.0), cell: 0.5, elevation: 0.0, holes: []))],
    sun: (latitude_deg: 47.4, longitude_deg: 8.5, utc: "2026-06-21T06:00:00Z"),
    wind: (direction: (1.0, 0.0, 0.3), strength: 0.0, density: 0.15, gust_average: 1.0, gust_strength: 0.3, gust_frequency: 0.3),
    grass: [(name: "patch", kind: {kind}, density: 3000.0, height: (0.15, 0.3), shells: 16, polygon: [(-4.0, -4.0), (4.0, -4.0), (4.0, 4.0), (-4.0, 4.0)])],
    trees: [
        (model: "broadleaf-mesh", position: (-7.0, 0.0, 0.0), yaw_deg: 0.0),
        (model: "broadleaf-mesh", position: (7.0, 0.0, 0.0), yaw_deg: 0.0),
        (model: "broadleaf-mesh", position: (0.0, 0.0, 7.0), yaw_deg: 0.0),
        (model: "broadleaf-mesh", position: (0.0, 0.0, -7.0), yaw_deg: 0.0),
    ],
    camera: (position: (0.0, 5.0, 0.01), look_at: (0.0, 0.0, 0.0), fov_y_deg: 60.0),
)"#
        );
        let s = sim(&Scene::parse(&text, "grass shadow test").unwrap());
        let shot = |grass: bool, shadows: bool| {
            let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
            let g = gpu();
            let mut r = renderer_for(g, &s, w, h);
            r.options.grass = grass;
            r.options.shadows = shadows;
            (offscreen::render_image(g, &mut r, &s).unwrap(), r.features.grass.visible_blades().unwrap())
        };
        let ((grass_lit, _), (grass_shadowed, counts)) = (shot(true, false), shot(true, true));
        let ((bare_lit, _), (bare_shadowed, _)) = (shot(false, false), shot(false, true));
        if kind == "Blades" {
            let level = if w == W { counts.far } else { counts.mid };
            assert!(level > counts.total() / 2, "{kind} at {w} × {h}: {counts:?}");
        }
        // The pixels where the grass covers the ground (it changes the unshadowed picture) and
        // where the ground lies in a tree's shadow (the bare ground darkens with shadows on).
        let (mut n, mut darker) = (0usize, 0.0);
        for y in 0..h {
            for x in 0..w {
                let grass_here = (luma(&grass_lit, x, y) - luma(&bare_lit, x, y)).abs() > 10.0;
                let in_shadow = luma(&bare_lit, x, y) - luma(&bare_shadowed, x, y) > 10.0;
                if grass_here && in_shadow {
                    n += 1;
                    darker += luma(&grass_lit, x, y) - luma(&grass_shadowed, x, y);
                }
            }
        }
        // A shadow covers a good part of the view, and the grass in it is darker too.
        assert!(n > 500, "{kind} at {w} × {h}: only {n} grass pixels in a tree's shadow");
        let mean = darker / n as f64;
        assert!(mean > 8.0, "{kind} at {w} × {h}: the grass in the trees' shadows is only {mean:.1} darker");
    }
}

#[test]
fn bad_grass_fields_exit_2_with_one_line() {
    let dir = std::env::temp_dir().join(format!("grove-grass-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let park = std::fs::read_to_string(root().join("assets/scenes/park.ron")).unwrap();
    let cases = [
        ("density: 4000.0,", "density: -1.0,", "density -1 must be positive"),
        ("shells: 20,", "shells: 0,", "shells 0"),
        ("planes: [\"ground\"],", "planes: [\"pond\"],", "names plane 'pond'"),
    ];
    for (i, (from, to, needle)) in cases.into_iter().enumerate() {
        let path = dir.join(format!("bad-{i}.ron"));
        std::fs::write(&path, park.replacen(from, to, 1)).unwrap();
        common::assert_one_line_error(&common::grove_with(&["scene", "check"], &path), 2, needle);
        let out = dir.join(format!("bad-{i}.png"));
        let o = common::grove(&["render", "--scene", path.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        common::assert_one_line_error(&o, 2, needle);
        assert!(!out.exists(), "a failed render left {}", out.display());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn no_grass_and_the_overlay_from_the_command_line() {
    let dir = std::env::temp_dir().join(format!("grove-grass-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args =
            vec!["render", "--scene", "assets/scenes/park.ron", "--width", "160", "--height", "120", "--out"];
        args.push(out.to_str().unwrap());
        args.extend_from_slice(extra);
        let o = common::grove(&args);
        assert!(o.status.success(), "{extra:?}: {}", String::from_utf8_lossy(&o.stderr));
        image::open(&out).unwrap().to_rgba8()
    };
    let plain = run("plain.png", &[]);
    let bare = run("bare.png", &["--no-grass"]);
    let ray = run("ray.png", &["--overlay", "interaction"]);
    let none = run("none.png", &["--overlay", "none"]);
    // The park's lawns fill the lower half: without grass it looks different.
    assert!(diff(&plain, &bare, (0, H / 2, W, H)) > 3.0, "--no-grass changed nothing");
    // A scene render draws no overlay unless asked: the default is `none`.
    assert_eq!(diff(&plain, &none, (0, 0, W, H)), 0.0);
    assert!(diff(&plain, &ray, (0, 0, W, H)) > 0.0, "--overlay interaction drew nothing");
    let _ = std::fs::remove_dir_all(&dir);
}
