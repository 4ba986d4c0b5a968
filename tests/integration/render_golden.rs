//! Golden-image tests of the renderer on whatever adapter wgpu finds (lavapipe in CI).
//!
//! Images are small (160×120), without MSAA, compared with `tests/snapshots/<name>.png`. Each
//! test states its tolerance: the mean absolute difference per channel (0..255) and the share of
//! pixels whose largest channel difference exceeds 40. Regenerate with
//! `UPDATE_SNAPSHOTS=1 cargo test --test integration render_golden::`. A failing comparison writes the actual
//! image to `target/snapshot-failures/`. Without an adapter, every test fails loudly.
//!
//! Besides the goldens, each test checks a property of the image that must hold whatever the
//! snapshot says (e.g. the back of a leaf is lit, clipped texels show the background, shadows
//! darken the ground).

use std::path::PathBuf;

use glam::Vec3;
use grove::render::offscreen::{self, Gpu};
use grove::render::{Camera, RenderOptions, Renderer, camera_matrix};
use grove_systems::Sim;
use grove_systems::catalogue::ModelId;
use grove_systems::components::*;
use grove_systems::scene::Scene;
use grove_systems::task::{TaskDef, TaskState};
use image::RgbaImage;

use crate::striped_card;
use striped_card::striped_card;

const W: u32 = 160;
const H: u32 = 120;

/// The largest channel difference above which a pixel counts as different.
const PIXEL_THRESHOLD: u8 = 40;

use crate::shared_gpu;
use shared_gpu::LOCK;

fn gpu() -> &'static Gpu {
    shared_gpu::shared_gpu("golden tests")
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A tolerance for one test.
struct Tolerance {
    /// Largest allowed mean absolute difference per channel (0..255).
    mean_abs: f64,
    /// Largest allowed share of pixels over [`PIXEL_THRESHOLD`], in percent.
    percent_over: f64,
}

fn compare(name: &str, img: &RgbaImage, tol: Tolerance) {
    let path = root().join("tests/snapshots").join(format!("{name}.png"));
    if std::env::var("UPDATE_SNAPSHOTS").is_ok_and(|v| v == "1") {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
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
        let mut worst = 0u8;
        for c in 0..3 {
            let d = a.0[c].abs_diff(b.0[c]);
            sum += d as u64;
            worst = worst.max(d);
        }
        if worst > PIXEL_THRESHOLD {
            over += 1;
        }
    }
    let n = (img.width() * img.height()) as f64;
    let mean = sum as f64 / (n * 3.0);
    let percent = over as f64 * 100.0 / n;
    if mean > tol.mean_abs || percent > tol.percent_over {
        let dir = root().join("target/snapshot-failures");
        let _ = std::fs::create_dir_all(&dir);
        let _ = img.save(dir.join(format!("{name}.png")));
        panic!(
            "{name}: differs from {} (mean abs diff {mean:.2} > {} or {percent:.2}% pixels over {PIXEL_THRESHOLD} > {}%); actual image in target/snapshot-failures/",
            path.display(),
            tol.mean_abs,
            tol.percent_over
        );
    }
}

fn luminance(img: &RgbaImage, rect: (u32, u32, u32, u32)) -> f64 {
    let (x0, y0, x1, y1) = rect;
    let mut sum = 0.0;
    let mut n = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            let p = img.get_pixel(x, y).0;
            sum += 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64;
            n += 1.0;
        }
    }
    sum / n
}

fn study() -> Sim {
    let scene = Scene::load(&root().join("assets/scenes/study.ron")).unwrap();
    Sim::from_scene(&scene, scene.seed).unwrap()
}

fn render(sim: &Sim, shadows: bool) -> RgbaImage {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let g = gpu();
    let mut r = Renderer::new(&g.device, &g.queue, offscreen::FORMAT, W, H).unwrap();
    r.options.shadows = shadows;
    r.options.impostor_pixels = impostor_pixels();
    offscreen::render_image(g, &mut r, sim).unwrap()
}

/// The default impostor threshold scaled from 720 lines to the goldens' height, so that these
/// small images show the trees as a 1280 × 720 frame would.
fn impostor_pixels() -> f32 {
    grove::render::DEFAULT_IMPOSTOR_PIXELS * H as f32 / 720.0
}

fn set_head(sim: &mut Sim, eye: Vec3, target: Vec3, fov_deg: f32) {
    sim.set_up().camera(Head { pose: Pose::looking_at(eye, target), fov_y: fov_deg.to_radians() });
}

fn set_sun(sim: &mut Sim, utc: &str) {
    sim.set_up().sun_utc(utc).unwrap();
}

/// The pixel a world point projects to.
fn project(sim: &Sim, p: Vec3) -> (u32, u32) {
    let head = sim.head();
    let camera = Camera { position: head.pose.position, rotation: head.pose.rotation, fov_y: head.fov_y };
    let q = camera_matrix(&camera, W as f32 / H as f32).project_point3(p);
    (((q.x * 0.5 + 0.5) * W as f32) as u32, ((0.5 - q.y * 0.5) * H as f32) as u32)
}

macro_rules! model_test {
    ($fn:ident, $name:literal) => {
        #[test]
        fn $fn() {
            let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
            let path = root().join(concat!("assets/trees/", $name, ".gltf"));
            let img = offscreen::render_model_file(gpu(), &path, W, H, RenderOptions::default()).unwrap();
            // The tree fills part of the frame: the centre column differs from the sky corner.
            let sky = luminance(&img, (0, 0, 8, 8));
            let centre = luminance(&img, (W / 2 - 4, H / 2 - 4, W / 2 + 4, H / 2 + 4));
            assert!(
                (sky - centre).abs() > 10.0,
                "{}: nothing drawn in the centre (sky {sky:.0}, centre {centre:.0})",
                $name
            );
            compare(concat!("model-", $name), &img, Tolerance { mean_abs: 3.0, percent_over: 2.0 });
        }
    };
}

model_test!(model_broadleaf_mesh, "broadleaf-mesh");
model_test!(model_conifer_mesh, "conifer-mesh");
model_test!(model_birch_mesh, "birch-mesh");
model_test!(model_shrub_mesh, "shrub-mesh");
model_test!(model_broadleaf_billboard, "broadleaf-billboard");
model_test!(model_conifer_billboard, "conifer-billboard");
model_test!(model_birch_billboard, "birch-billboard");
model_test!(model_shrub_billboard, "shrub-billboard");

#[test]
fn alpha_clipping_and_two_sided_flip() {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let g = gpu();
    let mut sim = grove_systems::stage::model_stage(
        (Vec3::new(-1.5, 0.0, -0.1), Vec3::new(1.5, 1.0, 0.1)),
        W as f32 / H as f32,
        false,
        ModelId(0),
    )
    .unwrap();
    // Two cards side by side: the left one shows its front to the camera, the right one its back.
    let mut trees: Vec<hecs::Entity> = Vec::new();
    sim.for_each_tree(|t| trees.extend(hecs::Entity::from_bits(t.id)));
    for e in trees {
        sim.set_up().despawn(e).unwrap();
    }
    sim.spawn_tree(ModelId(0), Vec3::new(-0.7, 0.0, 0.0), 0.0, 1.0, false);
    sim.spawn_tree(ModelId(0), Vec3::new(0.7, 0.0, 0.0), std::f32::consts::PI, 1.0, false);
    set_head(&mut sim, Vec3::new(0.0, 0.5, 2.6), Vec3::new(0.0, 0.5, 0.0), 40.0);
    // The sun behind the camera, so both visible sides face it once the back face is flipped.
    sim.set_up().sun_angles(30.0, 180.0);
    let mut r = Renderer::empty(&g.device, &g.queue, offscreen::FORMAT, W, H, &root().join("assets")).unwrap();
    // The card itself, however small it is on screen (impostors have their own goldens).
    r.options.impostor_pixels = 0.0;
    r.features.trees.set_model(ModelId(0), &striped_card());
    let img = offscreen::render_image(g, &mut r, &sim).unwrap();

    // Stripes: along a row through the card, opaque and clipped texels alternate, so the row
    // has many strong colour changes; clipped texels show what lies behind (not card green).
    let (lx, ly) = project(&sim, Vec3::new(-0.7, 0.5, 0.0));
    let (rx, _) = project(&sim, Vec3::new(0.7, 0.5, 0.0));
    let row: Vec<[u8; 4]> = (lx.saturating_sub(20)..(lx + 20).min(W)).map(|x| img.get_pixel(x, ly).0).collect();
    let greenish = |p: &[u8; 4]| p[1] as i32 - p[0].max(p[2]) as i32 > 40;
    let changes = row.windows(2).filter(|w| greenish(&w[0]) != greenish(&w[1])).count();
    assert!(changes >= 4, "expected alternating clipped stripes, got {changes} changes in {row:?}");
    // The back side is lit like the front (its normal flipped towards the viewer and sun).
    let front = luminance(&img, (lx - 10, ly - 8, lx + 10, ly + 8));
    let back = luminance(&img, (rx - 10, ly - 8, rx + 10, ly + 8));
    assert!(back > 0.75 * front, "back face too dark: front {front:.1}, back {back:.1}");
    compare("alpha-clip-two-sided", &img, Tolerance { mean_abs: 3.0, percent_over: 2.0 });
}

#[test]
fn shadowed_scene() {
    let mut sim = study();
    // A broadleaf and a conifer beside the camera's view, late morning sun from the south-east.
    let bl = sim.catalogue().by_name("broadleaf-mesh").unwrap().id;
    let cb = sim.catalogue().by_name("conifer-billboard").unwrap().id;
    sim.spawn_tree(bl, Vec3::new(-1.0, 0.0, -3.0), 0.3, 1.0, true);
    sim.spawn_tree(cb, Vec3::new(3.0, 0.0, -5.0), 0.0, 1.0, true);
    set_head(&mut sim, Vec3::new(2.0, 4.0, 8.0), Vec3::new(0.0, 0.5, -3.0), 60.0);
    set_sun(&mut sim, "2026-06-21T08:30:00Z");
    let lit = render(&sim, false);
    let shadowed = render(&sim, true);
    // Shadows only darken: the whole image, and clearly somewhere.
    let (a, b) = (luminance(&lit, (0, 0, W, H)), luminance(&shadowed, (0, 0, W, H)));
    assert!(b < a - 1.0, "shadows did not darken the image ({a:.1} → {b:.1})");
    compare("shadowed-scene", &shadowed, Tolerance { mean_abs: 3.0, percent_over: 2.5 });
}

#[test]
fn interaction_visuals() {
    let mut sim = study();
    let id = sim.catalogue().by_name("shrub-mesh").unwrap().id;
    let tree = sim.spawn_tree(id, Vec3::new(0.5, 0.0, -2.0), 0.0, 1.0, true);
    let info = sim.catalogue().get(id).unwrap().clone();
    let pos = sim.tree(tree.to_bits().get()).unwrap().transform.translation;
    set_head(&mut sim, Vec3::new(0.0, 1.7, 2.0), Vec3::new(0.0, 0.3, -2.0), 60.0);
    let anchor = Vec3::new(-1.2, 0.0, -1.5);
    let hit = Vec3::new(0.9, 0.4, -2.0);
    let ball = AnchorBall { visible: true, position: anchor, distance: 0.5, armed: false };
    sim.set_up()
        .controller_pose(Pose::looking_at(Vec3::new(0.3, 1.2, 1.5), hit))
        .hit_marker(HitMarker {
            visible: true,
            position: hit,
            normal: Vec3::Y,
            distance: Vec3::new(0.3, 1.2, 1.5).distance(hit),
            target: HitTarget::Tree(tree.to_bits().get()),
        })
        .anchor_ball(ball)
        .selection(Selection {
            tree: Some(tree.to_bits().get()),
            center: (info.bounds_min + info.bounds_max) * 0.5 + pos,
            half_extents: (info.bounds_max - info.bounds_min) * 0.5,
            yaw: 0.0,
        })
        .task(Some(TaskState::new(TaskDef::builtin("ray-casting-7").unwrap(), 0)));
    let green = render(&sim, true);
    // The anchor ball is green while not armed, white when armed.
    let (ax, ay) = project(&sim, anchor);
    let p = green.get_pixel(ax, ay).0;
    assert!(
        p[1] > 120 && p[1] as i32 - p[0] as i32 > 60 && p[1] as i32 - p[2] as i32 > 60,
        "anchor ball not green: {p:?}"
    );
    sim.set_up().anchor_ball(AnchorBall { armed: true, ..ball });
    let white = render(&sim, true);
    let q = white.get_pixel(ax, ay).0;
    assert!(q[0] > 140 && q[1] > 140 && q[2] > 140, "armed anchor ball not white: {q:?}");
    compare("interaction-visuals", &green, Tolerance { mean_abs: 3.0, percent_over: 2.5 });
}

fn study_at(utc: &str) -> RgbaImage {
    let mut sim = study();
    set_sun(&mut sim, utc);
    render(&sim, true)
}

#[test]
fn study_scene_morning_and_evening() {
    let morning = study_at("2026-06-21T09:30:00Z");
    // 19:00 UTC is 21:00 in Zurich: the sun is a few degrees up in the north-west.
    let evening = study_at("2026-06-21T18:45:00Z");
    let warmth = |img: &RgbaImage| {
        let (mut r, mut b) = (0.0, 0.0);
        for y in H / 2..H {
            for x in 0..W {
                let p = img.get_pixel(x, y).0;
                r += p[0] as f64;
                b += p[2] as f64;
            }
        }
        r / b.max(1.0)
    };
    let (lm, le) = (luminance(&morning, (0, H / 2, W, H)), luminance(&evening, (0, H / 2, W, H)));
    assert!(le < lm, "the evening ground should be darker ({lm:.1} vs {le:.1})");
    assert!(warmth(&evening) > warmth(&morning), "the evening light should be warmer");
    compare("study-morning", &morning, Tolerance { mean_abs: 3.0, percent_over: 2.5 });
    compare("study-evening", &evening, Tolerance { mean_abs: 3.0, percent_over: 2.5 });
}

#[test]
fn night_turns_the_sun_off() {
    let mut sim = study();
    set_sun(&mut sim, "2026-06-21T23:30:00Z");
    let elevation = sim.sun().unwrap().elevation_deg;
    assert!(elevation < 0.0);
    let img = render(&sim, true);
    assert!(luminance(&img, (0, 0, W, H)) < 40.0, "night should be dark");
}

/// Foliage level of detail: a row of broadleaf mesh trees from 40 to 160 m away, drawn with
/// every leaf and with the default leaf pixel budget. The simplified frame draws far fewer
/// triangles, yet the crowns cover about as many pixels, and the image stays close.
#[test]
fn leaf_simplification_keeps_the_crowns() {
    let mut sim = study();
    let mut planes: Vec<hecs::Entity> = Vec::new();
    sim.for_each_plane(|id, _| planes.extend(hecs::Entity::from_bits(id)));
    for e in planes {
        sim.set_up().despawn(e).unwrap();
    }
    let bl = sim.catalogue().by_name("broadleaf-mesh").unwrap().id;
    set_head(&mut sim, Vec3::new(0.0, 3.0, 0.0), Vec3::new(0.0, 3.0, -60.0), 40.0);
    // The sky alone, before the trees are planted.
    let sky = {
        let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        let g = gpu();
        let mut r = Renderer::new(&g.device, &g.queue, offscreen::FORMAT, W, H).unwrap();
        r.options.shadows = false;
        offscreen::render_image(g, &mut r, &sim).unwrap()
    };
    for k in 0..7 {
        sim.spawn_tree(bl, Vec3::new(-18.0 + k as f32 * 6.0, 0.0, -40.0 - k as f32 * 20.0), 0.4 * k as f32, 1.0, true);
    }
    let draw = |leaf_pixels: f32| {
        let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        let g = gpu();
        let mut r = Renderer::new(&g.device, &g.queue, offscreen::FORMAT, W, H).unwrap();
        r.options.impostor_pixels = impostor_pixels();
        r.options.shadows = false;
        r.options.leaf_pixels = leaf_pixels;
        let img = offscreen::render_image(g, &mut r, &sim).unwrap();
        (img, r.stats.triangles)
    };
    let (full, full_tris) = draw(0.0);
    let (lod, lod_tris) = draw(grove::render::RenderOptions::default().leaf_pixels);
    assert!(lod_tris * 3 < full_tris, "simplification should drop most triangles: {lod_tris} of {full_tris}");
    // Crown pixels: those far from the sky behind them (the far crowns fade into the haze, so
    // their colour alone does not tell them from the sky).
    let crown = |img: &RgbaImage| {
        img.pixels().zip(sky.pixels()).filter(|(p, q)| (0..3).any(|c| p.0[c].abs_diff(q.0[c]) > 12)).count() as f64
    };
    let (a, b) = (crown(&full), crown(&lod));
    assert!(a > 200.0, "the crowns should be visible ({a} pixels)");
    assert!((b - a).abs() / a < 0.2, "crown coverage changed from {a} to {b} pixels");
    compare("leaf-simplification", &lod, Tolerance { mean_abs: 3.0, percent_over: 2.5 });
}

/// The renderer builds its tree pipelines for one wind model at a time. A tree in a strong wind
/// must sway away from its calm pose under each model, and the two models must move it
/// differently, so a frame drawn with the wrong model's pipelines would fail here.
#[test]
fn each_wind_model_sways_the_trees() {
    use grove_systems::wind_model::WindModel;
    let mut sim = study();
    let bl = sim.catalogue().by_name("broadleaf-mesh").unwrap().id;
    sim.spawn_tree(bl, Vec3::new(0.0, 0.0, -6.0), 0.3, 1.0, true);
    set_head(&mut sim, Vec3::new(0.0, 2.5, 2.0), Vec3::new(0.0, 2.5, -6.0), 60.0);
    let mut frame = |model: WindModel, strength: f32| {
        let mut w = sim.wind().unwrap();
        w.model = model;
        w.strength = strength;
        w.current = 1.0;
        sim.set_up().wind(w);
        render(&sim, false)
    };
    let calm = frame(WindModel::Hierarchical, 0.0);
    let noise = frame(WindModel::Noise, 8.0);
    let hierarchical = frame(WindModel::Hierarchical, 8.0);
    let changed = |a: &RgbaImage, b: &RgbaImage| {
        a.pixels().zip(b.pixels()).filter(|(p, q)| (0..3).any(|c| p.0[c].abs_diff(q.0[c]) > PIXEL_THRESHOLD)).count()
    };
    for (name, img) in [("noise", &noise), ("hierarchical", &hierarchical)] {
        let n = changed(&calm, img);
        assert!(n > 50, "the {name} wind model moved only {n} pixels");
    }
    let n = changed(&noise, &hierarchical);
    assert!(n > 50, "the two wind models drew nearly the same frame ({n} pixels apart)");
}
