//! The aerial ground and the canopy (issue #22) on a small synthetic pair made in the test
//! (`Park` at 256 texels of 0.25 m: 64 m square): the crowns become tree entities, the winter
//! photograph is the ground, the crowns stand as canopy layers that cast shadows, and
//! `--debug-lod` colours the clipmap levels. Golden images are 160×120, compared with
//! `tests/snapshots/aerial-*.png` within a stated tolerance; regenerate them with
//! `UPDATE_SNAPSHOTS=1 cargo test --test integration aerial_canopy::`. Each golden test also checks a property
//! that holds whatever the snapshot says.

use std::path::PathBuf;

use glam::{Vec2, Vec3};
use grove::aerial::crowns::{self, Crown};
use grove::aerial::layers::{layer_ks, layer_masks};
use grove::aerial::raster::write_png;
use grove::aerial::scene::{SceneOptions, scene_from_crowns, scene_text};
use grove::aerial::synth::{Park, Season};
use grove::aerial::{MaskParams, Segmenter, label_crowns};
use grove::render::Renderer;
use grove::render::offscreen::{self, Gpu};
use grove_systems::Sim;
use grove_systems::aerial::{AerialCrown, AerialDef};
use grove_systems::catalogue::ModelKind;
use grove_systems::components::{Head, Pose, Transform};
use grove_systems::scene::Scene;
use image::RgbaImage;

const W: u32 = 160;
const H: u32 = 120;
const GSD: f64 = 0.25;
const SIZE: u32 = 256;

use crate::shared_gpu;
use shared_gpu::LOCK;

fn gpu() -> &'static Gpu {
    shared_gpu::shared_gpu("the aerial render tests")
}

/// The site: the pair, its layer masks and crowns in a temporary folder, and its scene.
struct Site {
    _dir: tempfile::TempDir,
    scene: Scene,
    crowns: Vec<Crown>,
}

fn site() -> Site {
    let dir = tempfile::tempdir().unwrap();
    let park = Park::layout(SIZE, GSD, 5);
    let (summer, winter) = (park.render(Season::Summer), park.render(Season::Winter));
    let seg = Segmenter::new(&summer, &winter, true).unwrap();
    let mask = seg.mask(&MaskParams::default());
    let found = label_crowns(&mask, SIZE, SIZE, GSD);
    let layers = layer_masks(&seg, &layer_ks(6, 3, 21).unwrap(), 0.5, 0.5);
    let p = |f: &str| dir.path().join(f);
    write_png(&p("summer.png"), SIZE, SIZE, 3, &summer.data).unwrap();
    write_png(&p("winter.png"), SIZE, SIZE, 3, &winter.data).unwrap();
    let rgb: Vec<u8> = layers.iter().flat_map(|&b| [b, b, b]).collect();
    write_png(&p("layers.png"), SIZE, SIZE, 3, &rgb).unwrap();
    crowns::write_csv(&p("crowns.csv"), &found).unwrap();
    let size_m = f64::from(SIZE) * GSD;
    let opts = SceneOptions {
        name: "aerial test".into(),
        size_m: (size_m, size_m),
        min_radius_m: 0.5,
        kind: ModelKind::Mesh,
        sun: (47.3769, 8.5417, "2026-06-21T10:00:00Z".into()),
    };
    let (mut scene, _) = scene_from_crowns(&found, &opts).unwrap();
    scene.trees.clear();
    scene.aerial = Some(AerialDef {
        summer: "summer.png".into(),
        winter: "winter.png".into(),
        layers: Some("layers.png".into()),
        gsd_m: GSD as f32,
        origin: Vec2::splat(-size_m as f32 / 2.0),
        elevation: 0.0,
        crowns: Some("crowns.csv".into()),
        model: "broadleaf-mesh".into(),
        min_radius_m: 0.5,
        height_per_radius: 3.0,
        layer_count: 6,
        crown_list: vec![],
    });
    std::fs::write(p("site.ron"), scene_text(&scene, "the test").unwrap()).unwrap();
    let scene = Scene::load(&p("site.ron")).unwrap();
    Site { _dir: dir, scene, crowns: found }
}

fn sim(site: &Site) -> Sim {
    Sim::from_scene(&site.scene, 0).unwrap()
}

/// The photographed crowns' trees: entity, transform and crown, in the world's order.
fn crown_trees(sim: &Sim) -> Vec<(hecs::Entity, Transform, AerialCrown)> {
    let mut v = Vec::new();
    sim.for_each_tree(|t| v.extend(t.crown.and_then(|c| Some((hecs::Entity::from_bits(t.id)?, t.transform, c)))));
    v
}

/// The tree of the largest photographed crown.
fn largest_crown(sim: &Sim) -> (hecs::Entity, Transform, AerialCrown) {
    crown_trees(sim).into_iter().max_by(|a, b| a.2.radius_m.total_cmp(&b.2.radius_m)).unwrap()
}

#[test]
fn crowns_become_tree_entities_on_their_photographed_centres() {
    let s = site();
    let sim = sim(&s);
    let big: Vec<&Crown> = s.crowns.iter().filter(|c| c.radius_m >= 0.5).collect();
    assert!(big.len() >= 3, "the synthetic park has crowns: {}", big.len());
    let mut found: Vec<(u32, Vec3)> = crown_trees(&sim).iter().map(|(_, t, c)| (c.id, t.translation)).collect();
    found.sort_by_key(|f| f.0);
    assert_eq!(found.len(), big.len());
    for (c, (id, pos)) in big.iter().zip(&found) {
        // The photograph's centre is the world origin: x = x_m − 32 m, z = y_m − 32 m.
        assert_eq!(c.id, *id);
        assert!(
            (pos.x - (c.x_m as f32 - 32.0)).abs() < 1e-3 && (pos.z - (c.y_m as f32 - 32.0)).abs() < 1e-3,
            "{c:?} at {pos}"
        );
    }
    // The crowns are hashed; a scene without them is not.
    let h = sim.hash();
    assert!(h.component("AerialCrown").is_some());
    let mut plain = s.scene.clone();
    plain.aerial = None;
    let plain = Sim::from_scene(&plain, 0).unwrap();
    assert!(plain.hash().component("AerialCrown").is_none());
}

#[test]
fn a_missing_photograph_or_bad_field_is_one_line() {
    let s = site();
    let mut scene = s.scene.clone();
    scene.aerial.as_mut().unwrap().winter = "nowhere.png".into();
    let e = grove::render::aerial_ground::open::open_sources(&scene, false)
        .err()
        .expect("a missing photograph is an error")
        .to_string();
    assert!(e.contains("nowhere.png") && !e.contains('\n'), "{e}");
    let text = std::fs::read_to_string(s.scene.dir.as_ref().unwrap().join("site.ron"))
        .unwrap()
        .replace("gsd_m: 0.25", "gsd_m: -1.0");
    let e = Scene::parse(&text, "bad.ron").unwrap_err().to_string();
    assert!(e.contains("gsd_m") && !e.contains('\n'), "{e}");
}

/// Renders the site from `eye` towards `target`.
fn render(site: &Site, eye: Vec3, target: Vec3, shadows: bool, debug_lod: bool) -> RgbaImage {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let g = gpu();
    let mut sim = sim(site);
    sim.set_up().camera(Head { pose: Pose::looking_at(eye, target), fov_y: 60f32.to_radians() });
    let mut r = Renderer::new(&g.device, &g.queue, offscreen::FORMAT, W, H).unwrap();
    r.options.shadows = shadows;
    r.options.overlay = false;
    r.features
        .aerial
        .set(grove::render::aerial_ground::open::open_sources(&site.scene, debug_lod).unwrap().unwrap())
        .unwrap();
    offscreen::render_image(g, &mut r, &sim).unwrap()
}

fn compare(name: &str, img: &RgbaImage, mean_abs: f64, percent_over: f64) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots").join(format!("{name}.png"));
    if std::env::var("UPDATE_SNAPSHOTS").is_ok_and(|v| v == "1") {
        img.save(&path).unwrap();
        return;
    }
    let want = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; create it with UPDATE_SNAPSHOTS=1", path.display()))
        .to_rgba8();
    assert_eq!(want.dimensions(), img.dimensions());
    let (mut sum, mut over) = (0u64, 0u64);
    for (a, b) in want.pixels().zip(img.pixels()) {
        let worst = (0..3).map(|c| a.0[c].abs_diff(b.0[c])).max().unwrap();
        sum += (0..3).map(|c| u64::from(a.0[c].abs_diff(b.0[c]))).sum::<u64>();
        over += u64::from(worst > 40);
    }
    let n = f64::from(W * H);
    let (mean, percent) = (sum as f64 / (3.0 * n), over as f64 * 100.0 / n);
    if mean > mean_abs || percent > percent_over {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/snapshot-failures");
        let _ = std::fs::create_dir_all(&dir);
        let _ = img.save(dir.join(format!("{name}.png")));
        panic!(
            "{name}: mean abs diff {mean:.2} (limit {mean_abs}) or {percent:.2} % pixels over 40 (limit {percent_over} %)"
        );
    }
}

fn mean_luminance(img: &RgbaImage) -> f64 {
    img.pixels()
        .map(|p| 0.2126 * f64::from(p.0[0]) + 0.7152 * f64::from(p.0[1]) + 0.0722 * f64::from(p.0[2]))
        .sum::<f64>()
        / f64::from(W * H)
}

/// The pixel a world point projects to with the test's camera (60° vertical field of view).
fn project(eye: Vec3, target: Vec3, p: Vec3) -> (u32, u32) {
    let m = grove::render::camera_matrix(
        &grove::render::Camera {
            position: eye,
            rotation: Pose::looking_at(eye, target).rotation,
            fov_y: 60f32.to_radians(),
        },
        W as f32 / H as f32,
    );
    let ndc = m.project_point3(p);
    (((ndc.x * 0.5 + 0.5) * W as f32) as u32, ((0.5 - ndc.y * 0.5) * H as f32) as u32)
}

#[test]
fn from_above_the_crowns_show_the_summer_canopy() {
    let s = site();
    let (eye, target) = (Vec3::new(0.0, 60.0, 0.01), Vec3::ZERO);
    let img = render(&s, eye, target, true, false);
    compare("aerial-canopy-above", &img, 6.0, 4.0);
    // The largest crown's top is summer green: the winter photograph below it is not (the
    // segmentation found it because its window is not green in winter).
    let c = s.crowns.iter().max_by(|a, b| a.radius_m.total_cmp(&b.radius_m)).unwrap();
    let top = 3.0 * c.radius_m as f32;
    let (x, y) = project(eye, target, Vec3::new(c.x_m as f32 - 32.0, top, c.y_m as f32 - 32.0));
    let p = img.get_pixel(x.min(W - 1), y.min(H - 1)).0;
    assert!(p[1] > p[0] && p[1] > p[2], "the crown's top at ({x}, {y}) is {p:?}");
}

#[test]
fn oblique_the_canopy_casts_shadows_on_the_photographed_ground() {
    let s = site();
    let (eye, target) = (Vec3::new(0.0, 25.0, 45.0), Vec3::ZERO);
    let lit = render(&s, eye, target, true, false);
    compare("aerial-canopy-oblique", &lit, 6.0, 4.0);
    // The only shadow casters are the canopy layers: with shadows the image is darker.
    let unshadowed = render(&s, eye, target, false, false);
    let (a, b) = (mean_luminance(&lit), mean_luminance(&unshadowed));
    assert!(a < b - 1.0, "with shadows {a:.1}, without {b:.1}");
}

#[test]
fn debug_lod_colours_the_levels() {
    let s = site();
    let (eye, target) = (Vec3::new(0.0, 12.0, 30.0), Vec3::new(0.0, 0.0, -20.0));
    let img = render(&s, eye, target, false, true);
    compare("aerial-debug-lod", &img, 6.0, 4.0);
    // Level 0 is red and level 1 yellow (clipmap.wgsl): the ground just ahead of the camera is
    // red, the ground far ahead is not.
    let red = |p: [u8; 4]| u16::from(p[0]) > 2 * u16::from(p[2]) && u16::from(p[0]) > u16::from(p[1]) + 20;
    let near = img.get_pixel(W / 2, H - 3).0;
    assert!(red(near), "near ground {near:?}");
    let (x, y) = project(eye, target, Vec3::new(0.0, 0.0, -30.0));
    let far = img.get_pixel(x, y).0;
    assert!(!red(far), "far ground {far:?} at ({x}, {y})");
}

/// A source that serves `inner` with every texel of level 0 not loaded (alpha 0), as a level
/// whose tiles have not arrived yet.
struct Level0Missing(grove::render::clipmap::ImageSource);

impl grove::render::clipmap::ClipmapSource for Level0Missing {
    fn config(&self) -> grove::render::clipmap::ClipmapConfig {
        self.0.config()
    }
    fn placement(&self) -> grove::render::clipmap::AerialPlacement {
        self.0.placement()
    }
    fn update(&mut self, camera: &grove::render::clipmap::ClipCamera) -> grove::render::clipmap::ClipmapFrame {
        let mut f = self.0.update(camera);
        for u in f.uploads.iter_mut().filter(|u| u.level == 0) {
            u.rgba.chunks_exact_mut(4).for_each(|t| t[3] = 0);
        }
        f
    }
}

#[test]
fn a_level_not_loaded_falls_back_to_the_coarser_one() {
    use grove::render::clipmap::{AerialPlacement, ClipmapConfig, ImageSource};
    let s = site();
    let (eye, target) = (Vec3::new(0.0, 12.0, 30.0), Vec3::new(0.0, 0.0, -20.0));
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let g = gpu();
    let mut sim = sim(&s);
    sim.set_up().camera(Head { pose: Pose::looking_at(eye, target), fov_y: 60f32.to_radians() });
    let mut sources = grove::render::aerial_ground::open::open_sources(&s.scene, true).unwrap().unwrap();
    let winter = grove::aerial::RgbImage::load(&s.scene.dir.as_ref().unwrap().join("winter.png"), "winter").unwrap();
    let placement = AerialPlacement { origin_m: glam::DVec2::splat(-32.0), gsd_m: GSD };
    let inner = ImageSource::from_rgb(&winter, ClipmapConfig { levels: 8, size: 256 }, placement).unwrap();
    sources.winter = Box::new(Level0Missing(inner));
    sources.layers = None;
    let mut r = Renderer::new(&g.device, &g.queue, offscreen::FORMAT, W, H).unwrap();
    r.options.overlay = false;
    r.features.aerial.set(sources).unwrap();
    let img = offscreen::render_image(g, &mut r, &sim).unwrap();
    // Just ahead of the camera level 0 would be red; it is not loaded, so level 1 (yellow: red
    // and green both high) shows there.
    let p = img.get_pixel(W / 2, H - 3).0;
    assert!(
        p[0] > 60 && p[1] > 60 && u16::from(p[1]) * 10 > u16::from(p[0]) * 6 && p[2] < p[1] / 2,
        "near ground {p:?} is not level 1's yellow"
    );
}

#[test]
fn apply_counts_the_bytes_it_uploads_and_refuses_uploads_that_do_not_fit() {
    use grove::render::clipmap::{AerialPlacement, ClipmapConfig, ClipmapFrame, GpuClipmap, LevelPlacement, Upload};
    let g = gpu();
    let config = ClipmapConfig { levels: 2, size: 16 };
    let mut c =
        GpuClipmap::new(&g.device, config, AerialPlacement { origin_m: glam::DVec2::ZERO, gsd_m: 1.0 }, "test clipmap")
            .unwrap();
    let placements = vec![
        LevelPlacement { mip: 0, origin: glam::IVec2::ZERO },
        LevelPlacement { mip: 1, origin: glam::IVec2::ZERO },
    ];
    // A 16 × 3 strip and a 2 × 16 one: (48 + 32) texels of 4 bytes.
    let uploads = vec![
        Upload { level: 0, x: 0, y: 13, w: 16, h: 3, rgba: vec![255; 16 * 3 * 4] },
        Upload { level: 1, x: 14, y: 0, w: 2, h: 16, rgba: vec![255; 2 * 16 * 4] },
    ];
    assert_eq!(c.apply(&g.queue, &ClipmapFrame { placements: placements.clone(), uploads }).unwrap(), 320);
    assert_eq!((c.bytes_last, c.bytes_total), (320, 320));
    let past_the_edge = vec![Upload { level: 0, x: 15, y: 0, w: 2, h: 1, rgba: vec![0; 8] }];
    assert!(c.apply(&g.queue, &ClipmapFrame { placements: placements.clone(), uploads: past_the_edge }).is_err());
    let no_such_level = vec![Upload { level: 2, x: 0, y: 0, w: 1, h: 1, rgba: vec![0; 4] }];
    assert!(c.apply(&g.queue, &ClipmapFrame { placements, uploads: no_such_level }).is_err());
    assert_eq!(c.bytes_total, 320);
}

/// Runs the grove binary; its exit code and stderr.
fn grove(args: &[&str]) -> (i32, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_grove"))
        .args(args)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn the_cli_refuses_bad_aerial_input_with_one_line_and_exit_2() {
    let s = site();
    let dir = s.scene.dir.clone().unwrap();
    let text = std::fs::read_to_string(dir.join("site.ron")).unwrap();
    let out = dir.join("out.png");
    let cases = [
        ("missing winter photograph", text.replace("winter: \"winter.png\"", "winter: \"gone.png\""), "gone.png"),
        (
            "truncated crowns file",
            text.replace("crowns: Some(\"crowns.csv\")", "crowns: Some(\"short.csv\")"),
            "short.csv",
        ),
        ("bad layer count", text.replace("layer_count: 6", "layer_count: 12"), "layer_count"),
        ("absolute path", text.replace("summer: \"summer.png\"", "summer: \"/etc/hostname\""), "summer"),
    ];
    std::fs::write(dir.join("short.csv"), "id,x_m,y_m,radius_m\n1,2.0,3").unwrap();
    for (what, scene, needle) in cases {
        let path = dir.join("bad.ron");
        std::fs::write(&path, scene).unwrap();
        let (code, err) = grove(&[
            "render",
            "--scene",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--width",
            "32",
            "--height",
            "24",
        ]);
        let lines: Vec<&str> = err.lines().filter(|l| !l.contains("XDG_RUNTIME_DIR")).collect();
        assert_eq!(code, 2, "{what}: {err}");
        assert!(lines.len() == 1 && lines[0].contains(needle), "{what}: {err}");
        assert!(!out.exists(), "{what}: no image is written");
    }
    // grove aerial layers: a count past 8 layers and a missing photograph.
    let summer = dir.join("summer.png");
    let (code, err) = grove(&[
        "aerial",
        "layers",
        summer.to_str().unwrap(),
        summer.to_str().unwrap(),
        "--out",
        dir.join("l.png").to_str().unwrap(),
        "--layers",
        "9",
    ]);
    assert!(code == 2 && err.trim().lines().count() == 1 && err.contains("--layers 9"), "{err}");
    let (code, err) = grove(&[
        "aerial",
        "layers",
        "nowhere.png",
        summer.to_str().unwrap(),
        "--out",
        dir.join("l.png").to_str().unwrap(),
    ]);
    assert!(code == 2 && err.trim().lines().count() == 1 && err.contains("nowhere.png"), "{err}");
}

#[test]
fn a_moved_crown_tree_takes_its_canopy_along() {
    let s = site();
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let g = gpu();
    let mut sim = sim(&s);
    let (eye, target) = (Vec3::new(0.0, 60.0, 0.01), Vec3::ZERO);
    sim.set_up().camera(Head { pose: Pose::looking_at(eye, target), fov_y: 60f32.to_radians() });
    // The largest crown's tree, moved 12 m towards the centre along X; another crown removed.
    let (big, mut moved, crown) = largest_crown(&sim);
    let dx = if crown.photo_centre.x > 0.0 { -12.0 } else { 12.0 };
    moved.translation.x += dx;
    sim.set_up().transform(big, moved).unwrap();
    let other = crown_trees(&sim).iter().map(|(e, _, _)| *e).find(|e| *e != big).unwrap();
    let before = crown_trees(&sim).len();
    sim.set_up().despawn(other).unwrap();
    assert_eq!(crown_trees(&sim).len(), before - 1);
    let mut r = Renderer::new(&g.device, &g.queue, offscreen::FORMAT, W, H).unwrap();
    r.options.overlay = false;
    r.features.aerial.set(grove::render::aerial_ground::open::open_sources(&s.scene, false).unwrap().unwrap()).unwrap();
    let img = offscreen::render_image(g, &mut r, &sim).unwrap();
    // The crown's top is green at its new place.
    let foot = sim.tree(big.to_bits().get()).unwrap().transform.translation;
    let (x, y) = project(eye, target, foot + Vec3::Y * crown.top_m);
    let p = img.get_pixel(x.min(W - 1), y.min(H - 1)).0;
    assert!(p[1] > p[0] && p[1] > p[2], "the moved crown's top at ({x}, {y}) is {p:?}");
}

#[test]
fn the_commands_make_and_render_an_aerial_scene() {
    let dir = tempfile::tempdir().unwrap();
    let p = |f: &str| dir.path().join(f).to_str().unwrap().to_string();
    let ok = |args: &[&str]| {
        let (code, err) = grove(args);
        assert_eq!(code, 0, "grove {args:?}: {err}");
    };
    ok(&["aerial", "synth", "--size", "128", "--gsd", "0.25", "--seed", "4", "--out", &p("")]);
    ok(&[
        "aerial",
        "segment",
        "--summer",
        &p("summer.png"),
        "--winter",
        &p("winter.png"),
        "--gsd",
        "0.25",
        "--out",
        &p("seg"),
    ]);
    ok(&[
        "aerial",
        "layers",
        &p("summer.png"),
        &p("winter.png"),
        "--out",
        &p("layers.png"),
        "--layers",
        "4",
        "--k-top",
        "9",
    ]);
    ok(&[
        "aerial",
        "scene",
        "--crowns",
        &p("seg/crowns.csv"),
        "--out",
        &p("site.ron"),
        "--aerial",
        "--summer",
        &p("summer.png"),
        "--winter",
        &p("winter.png"),
        "--layers",
        &p("layers.png"),
    ]);
    let scene = Scene::load(&dir.path().join("site.ron")).unwrap();
    let a = scene.aerial.as_ref().unwrap();
    // The paths are relative to the scene's folder; the photograph's centre is the origin.
    assert_eq!(
        (a.summer.as_str(), a.layers.as_deref(), a.crowns.as_deref()),
        ("summer.png", Some("layers.png"), Some("seg/crowns.csv"))
    );
    assert_eq!(a.origin, Vec2::splat(-16.0));
    assert!(scene.trees.is_empty() && !a.crown_list.is_empty());
    // The layer masks hold 4 bits at most.
    let masks = image::open(dir.path().join("layers.png")).unwrap().to_rgb8();
    assert!(masks.pixels().all(|t| t.0[0] < 16) && masks.pixels().any(|t| t.0[0] != 0));
    ok(&["render", "--scene", &p("site.ron"), "--out", &p("a.png"), "--width", "64", "--height", "48", "--debug-lod"]);
    assert!(dir.path().join("a.png").is_file());
}

#[test]
fn trunks_stand_under_the_crowns() {
    let s = site();
    let sim0 = sim(&s);
    // The largest crown's tree, seen from 1.5 m above the ground, three crown radii away on the
    // side away from the park's centre (so no other crown stands between), looking at its
    // trunk's middle.
    let (big, transform, crown) = largest_crown(&sim0);
    let foot = transform.translation;
    let away = Vec3::new(foot.x, 0.0, foot.z).normalize_or(Vec3::Z);
    let mid = foot + Vec3::Y * (0.5 * crown.base_m);
    let eye = foot + away * (3.0 * crown.radius_m) + Vec3::Y * 1.5;
    let shot = |remove: bool| {
        let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        let g = gpu();
        let mut sim = sim(&s);
        if remove {
            sim.set_up().despawn(big).unwrap();
        }
        sim.set_up().camera(Head { pose: Pose::looking_at(eye, mid), fov_y: 60f32.to_radians() });
        let mut r = Renderer::new(&g.device, &g.queue, offscreen::FORMAT, W, H).unwrap();
        r.options.overlay = false;
        r.features
            .aerial
            .set(grove::render::aerial_ground::open::open_sources(&s.scene, false).unwrap().unwrap())
            .unwrap();
        offscreen::render_image(g, &mut r, &sim).unwrap()
    };
    let with = shot(false);
    compare("aerial-trunks", &with, 6.0, 4.0);
    // The trunk's middle is at the image's centre: dark bark (in the crown's shadow, so lit by
    // the bluish sky alone: darker than mid grey whatever its hue), and it is gone with the tree
    // (the sky or the far ground behind it is brighter).
    let (x, y) = project(eye, mid, mid);
    assert!((x as i32 - W as i32 / 2).abs() <= 1 && (y as i32 - H as i32 / 2).abs() <= 1, "({x}, {y})");
    let p = with.get_pixel(x, y).0;
    assert!(u16::from(p[0]) + u16::from(p[1]) + u16::from(p[2]) < 3 * 110, "the trunk at ({x}, {y}) is {p:?}");
    let without = shot(true);
    let q = without.get_pixel(x, y).0;
    let diff: u16 = (0..3).map(|c| u16::from(p[c].abs_diff(q[c]))).sum();
    assert!(diff > 30, "with the tree {p:?}, without {q:?}");
}

#[test]
fn the_flight_benchmark_flies_with_the_canopy_and_with_models() {
    let s = site();
    let flight = grove::bench::aerial::Flight {
        width: 160,
        height: 120,
        frames: 3,
        fly_height: 30.0,
        pitch: 35.0,
        speed: 20.0,
        shadows: true,
    };
    let canopy = grove::bench::aerial::fly(gpu(), &flight, &s.scene, true).unwrap();
    let models = grove::bench::aerial::fly(gpu(), &flight, &s.scene, false).unwrap();
    for run in [&canopy, &models] {
        assert!(run.median_ms > 0.0 && run.p95_ms >= run.median_ms && run.cpu_ms > 0.0, "{}", run.json());
        // The clipmaps were filled before the timed frames began or as they flew.
        assert!(run.upload_max_kib >= run.upload_mean_kib, "{}", run.json());
    }
    assert_eq!(canopy.json()["frames_waiting_on_disk"], 0);
    // Without an aerial section there is nothing to fly over.
    let mut bare = s.scene.clone();
    bare.aerial = None;
    let e = grove::bench::aerial::fly(gpu(), &flight, &bare, true).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("no aerial section"), "{e}");
}
