//! Impostors against the meshes they stand for, on whatever adapter wgpu finds (lavapipe in CI).
//!
//! - An atlas view must match the mesh drawn from the same direction: the tree's silhouettes
//!   overlap (intersection over union at least 0.5 per pixel, where leaves a pixel wide need
//!   not land on the same pixels, and at least 0.8 over 4×4-pixel blocks), cover the same area within 15 %, and the colours of the pixels both cover
//!   differ by at most 24 of 255 per channel on average.
//! - A tree crossing the cross-fade band must not pop: with the band crossed in 20 frames, no
//!   frame changes more than a third of the tree's pixels, while the mesh and the impostor alone
//!   differ in more pixels than any one step changes.

use glam::Vec3;
use grove::models::{ModelData, load_model};
use grove::render::Renderer;
use grove::render::offscreen::{self, Gpu};
use grove::render::trees::impostor::{self, BAND, cell_dir};
use grove_systems::Sim;
use grove_systems::catalogue::ModelId;
use grove_systems::components::{Head, Pose};
use image::RgbaImage;

const SIZE: u32 = 192;

use crate::shared_gpu;
use shared_gpu::LOCK;

fn gpu() -> &'static Gpu {
    shared_gpu::shared_gpu("impostor tests")
}

fn model_path(name: &str) -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/trees").join(format!("{name}.gltf"))
}

use crate::sky_stage;
use sky_stage::stage;

/// Renders `sim` with the model loaded (or not), no shadows, every leaf drawn, and impostors
/// below `impostor_pixels`.
fn draw(data: &ModelData, sim: &Sim, with_model: bool, impostor_pixels: f32) -> RgbaImage {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    sky_stage::draw(gpu(), data, sim, with_model, SIZE, impostor_pixels).0
}

/// Whether each pixel shows the tree: it differs from the background render by more than 30
/// in some channel.
fn mask(img: &RgbaImage, background: &RgbaImage) -> Vec<bool> {
    img.pixels().zip(background.pixels()).map(|(a, b)| (0..3).any(|c| a.0[c].abs_diff(b.0[c]) > 30)).collect()
}

/// The mask at 4×4-pixel blocks: a block is the tree's where at least a quarter of it is.
fn blocks(mask: &[bool]) -> Vec<bool> {
    let n = SIZE as usize / 4;
    (0..n * n)
        .map(|b| {
            let (bx, by) = (b % n * 4, b / n * 4);
            (0..16).filter(|k| mask[(by + k / 4) * SIZE as usize + bx + k % 4]).count() >= 4
        })
        .collect()
}

fn channel_mae(a: &RgbaImage, b: &RgbaImage, pixels: &[bool]) -> f64 {
    let (mut sum, mut n) = (0u64, 0u64);
    for ((p, q), &m) in a.pixels().zip(b.pixels()).zip(pixels) {
        if m {
            sum += (0..3).map(|c| u64::from(p.0[c].abs_diff(q.0[c]))).sum::<u64>();
            n += 3;
        }
    }
    sum as f64 / n.max(1) as f64
}

#[test]
fn atlas_views_match_the_mesh_from_their_direction() {
    let data = load_model(&model_path("broadleaf-mesh")).unwrap();
    // A side view, a view from 45° up, and one near the zenith, each exactly an atlas view.
    for (c, r) in [(7, 4), (5, 6), (4, 4)] {
        let dir = cell_dir(glam::UVec2::new(c, r));
        assert_eq!(impostor::cell(dir), glam::UVec2::new(c, r));
        // Far away with a narrow field of view, so the perspective is close to the bake's
        // orthographic view.
        let (sim, _) = stage(&data, dir, 400.0);
        let background = draw(&data, &sim, false, 0.0);
        let mesh = draw(&data, &sim, true, 0.0);
        let imp = draw(&data, &sim, true, 1.0e6);
        let (m, i) = (mask(&mesh, &background), mask(&imp, &background));
        let both: Vec<bool> = m.iter().zip(&i).map(|(a, b)| *a && *b).collect();
        let inter = both.iter().filter(|&&x| x).count() as f64;
        let union = m.iter().zip(&i).filter(|(a, b)| **a || **b).count() as f64;
        let mesh_pixels = m.iter().filter(|&&x| x).count();
        assert!(mesh_pixels > 2000, "view ({c}, {r}): the tree should fill the frame ({mesh_pixels} px)");
        let iou = inter / union;
        let cover = i.iter().filter(|&&x| x).count() as f64 / mesh_pixels as f64;
        let mae = channel_mae(&mesh, &imp, &both);
        eprintln!(
            "view ({c}, {r}): silhouette IoU {iou:.3}, coverage ratio {cover:.3}, colour MAE {mae:.2} over {inter} px"
        );
        let (bm, bi) = (blocks(&m), blocks(&i));
        let block_iou = bm.iter().zip(&bi).filter(|(a, b)| **a && **b).count() as f64
            / bm.iter().zip(&bi).filter(|(a, b)| **a || **b).count() as f64;
        eprintln!("view ({c}, {r}): 4×4-block silhouette IoU {block_iou:.3}");
        assert!(iou >= 0.5, "view ({c}, {r}): silhouettes overlap by {iou:.3}");
        assert!(block_iou >= 0.8, "view ({c}, {r}): block silhouettes overlap by {block_iou:.3}");
        assert!((cover - 1.0).abs() <= 0.15, "view ({c}, {r}): the impostor covers {cover:.3} of the mesh's pixels");
        assert!(mae <= 24.0, "view ({c}, {r}): colours differ by {mae:.2} per channel");
    }
}

#[test]
fn crossing_the_band_changes_little_per_frame() {
    let data = load_model(&model_path("conifer-mesh")).unwrap();
    let dir = Vec3::new(0.0, 0.25, 1.0).normalize();
    let (sim, radius) = stage(&data, dir, 60.0);
    // The tree's bounding sphere on screen: its diameter over the view's extent.
    let head = sim.head();
    let pixels = 2.0 * radius * (SIZE as f32 * 0.5 / (head.fov_y * 0.5).tan()) / 60.0;
    let background = draw(&data, &sim, false, 0.0);
    // The threshold swept so that the tree's fade goes from 0 to 1 in 20 equal steps: the
    // same frames as the tree receding through the band.
    let threshold = |k: usize| {
        let fade = k as f32 / 20.0;
        // fade = (BAND t - pixels) / ((BAND - 1) t)  =>  t = pixels / (BAND - fade (BAND - 1)).
        pixels / (BAND - fade * (BAND - 1.0)) * if k == 20 { 1.01 } else { 1.0 }
    };
    // One renderer for every frame (the atlas baked once), its threshold set per frame; its
    // middle frame is checked against a fresh renderer's below.
    let mut renderer = {
        let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        sky_stage::renderer(gpu(), &data, true, SIZE, 0.0)
    };
    let frames: Vec<RgbaImage> = (0..=20)
        .map(|k| {
            let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
            renderer.options.impostor_pixels = threshold(k);
            offscreen::render_image(gpu(), &mut renderer, &sim).unwrap()
        })
        .collect();
    assert!(frames[10] == draw(&data, &sim, true, threshold(10)), "a reused renderer draws what a fresh one draws");
    let tree: Vec<bool> = {
        let (a, b) = (mask(&frames[0], &background), mask(&frames[20], &background));
        a.iter().zip(&b).map(|(x, y)| *x || *y).collect()
    };
    let tree_pixels = tree.iter().filter(|&&x| x).count() as f64;
    assert!(tree_pixels > 1500.0, "the tree should be visible ({tree_pixels} px)");
    let changed = |a: &RgbaImage, b: &RgbaImage| {
        a.pixels().zip(b.pixels()).filter(|(p, q)| (0..3).any(|c| p.0[c].abs_diff(q.0[c]) > 40)).count() as f64
            / tree_pixels
    };
    let whole = changed(&frames[0], &frames[20]);
    let worst = frames.windows(2).map(|w| changed(&w[0], &w[1])).fold(0.0, f64::max);
    eprintln!("mesh to impostor: {:.1} % of the tree's pixels; worst step {:.1} %", whole * 100.0, worst * 100.0);
    assert!(worst <= 1.0 / 3.0, "one frame changed {:.1} % of the tree", worst * 100.0);
    assert!(worst < whole, "the steps ({worst:.3}) should be smaller than the whole change ({whole:.3})");
}

/// The forest scene validates, loads quickly and holds about 10,000 trees of every model of the
/// shipped species bank over 1 km².
#[test]
fn the_forest_scene_holds_ten_thousand_trees() {
    use grove_systems::scene::Scene;
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/forest.ron");
    let t = std::time::Instant::now();
    let scene = Scene::load(&path).unwrap();
    let sim = Sim::from_scene(&scene, scene.seed).unwrap();
    let seconds = t.elapsed().as_secs_f64();
    let mut models = std::collections::BTreeSet::new();
    let (mut n, mut lo, mut hi) = (0usize, Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    sim.for_each_tree(|t| {
        n += 1;
        models.insert(t.model.0);
        lo = lo.min(t.transform.translation);
        hi = hi.max(t.transform.translation);
    });
    assert!((9_500..=10_500).contains(&n), "{n} trees");
    let species: Vec<_> = sim.catalogue().models.iter().filter(|m| m.id.0 >= 8).map(|m| m.id.0).collect();
    assert_eq!(species.len(), 12, "the species bank's twelve models");
    assert_eq!(models.into_iter().collect::<Vec<_>>(), species, "every model of the species bank, and no classic one");
    assert!(hi.x - lo.x > 980.0 && hi.z - lo.z > 980.0 && hi.x - lo.x <= 1000.0, "{lo:?}..{hi:?}");
    assert!(seconds < 20.0, "loading took {seconds:.1} s (debug build)");
}

/// Golden images, 160×120, with impostors below 20 pixels (120 pixels at 720 lines): compared
/// with `tests/snapshots/<name>.png` (regenerate with `UPDATE_SNAPSHOTS=1 cargo test --test
/// impostor goldens`) within a mean absolute difference of 3 per channel and 3 % of pixels
/// over 40; and, whatever the snapshot says, the level of detail (simplified foliage and
/// impostors) at most 1.5 per channel further than full detail (every leaf, no impostors) from
/// the truth: full detail rendered at four times the size and scaled down, which the full-detail
/// image at 160×120 itself misses by 5 to 8 per channel (thin leaves alias and flicker at that
/// size).
#[test]
fn goldens_of_the_reference_scene_and_the_forest() {
    use grove_systems::scene::Scene;
    let (w, h) = (160u32, 120u32);
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let load = || {
        let scene = Scene::load(&root.join("assets/scenes/forest.ron")).unwrap();
        (Sim::from_scene(&scene, scene.seed).unwrap(), scene)
    };
    let (forest, forest_scene) = load();
    // The reference scene (after Fukuda et al. 2007, as `grove bench render-reference` builds
    // it): 100 trees of the eight models 10 m apart, seen from the south at 14 m, sun at 45°.
    let (_, mut scene) = load();
    scene.scatter.clear();
    let mut reference = Sim::from_scene(&scene, scene.seed).unwrap();
    for i in 0..100u32 {
        let (x, z) = ((i % 10) as f32 * 10.0 - 45.0, (i / 10) as f32 * 10.0 - 45.0);
        reference.spawn_tree(ModelId((i % 8) as u8), Vec3::new(x, 0.0, z), i as f32 * 0.7, 1.0, true);
    }
    reference
        .set_up()
        .camera(Head { pose: Pose::looking_at(Vec3::new(0.0, 14.0, 62.0), Vec3::ZERO), fov_y: 60f32.to_radians() })
        .sun_angles(45.0, 135.0);
    for (name, sim) in [("impostor-reference", &reference), ("impostor-forest", &forest)] {
        let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        let g = gpu();
        let mut r = Renderer::new(&g.device, &g.queue, offscreen::FORMAT, w, h).unwrap();
        grove::bank::load_for_scene(&mut r, &forest_scene, &[], sim.catalogue()).unwrap();
        r.options.impostor_pixels = 20.0;
        let img = offscreen::render_image(g, &mut r, sim).unwrap();
        r.options.impostor_pixels = 0.0;
        r.options.far_pixels = 0.0;
        r.options.leaf_pixels = 0.0;
        let full = offscreen::render_image(g, &mut r, sim).unwrap();
        r.resize(4 * w, 4 * h);
        let big = offscreen::render_image(g, &mut r, sim).unwrap();
        let truth = image::imageops::resize(&big, w, h, image::imageops::FilterType::Triangle);
        let all = vec![true; (w * h) as usize];
        let (lod_err, full_err) = (channel_mae(&img, &truth, &all), channel_mae(&full, &truth, &all));
        eprintln!(
            "{name}: from the truth, {lod_err:.2} per channel with the level of detail, {full_err:.2} at full detail"
        );
        assert!(
            lod_err <= full_err + 1.5,
            "{name}: {lod_err:.2} per channel from the truth, full detail {full_err:.2}"
        );
        let path = root.join("tests/snapshots").join(format!("{name}.png"));
        if std::env::var("UPDATE_SNAPSHOTS").is_ok_and(|v| v == "1") {
            img.save(&path).unwrap();
            continue;
        }
        let want = image::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e}; create it with UPDATE_SNAPSHOTS=1", path.display()))
            .to_rgba8();
        assert_eq!(want.dimensions(), img.dimensions());
        let mae = channel_mae(&want, &img, &all);
        let over = want.pixels().zip(img.pixels()).filter(|(a, b)| (0..3).any(|c| a.0[c].abs_diff(b.0[c]) > 40)).count()
            as f64
            / all.len() as f64
            * 100.0;
        if mae > 3.0 || over > 3.0 {
            let dir = root.join("target/snapshot-failures");
            let _ = std::fs::create_dir_all(&dir);
            let _ = img.save(dir.join(format!("{name}.png")));
        }
        assert!(
            mae <= 3.0 && over <= 3.0,
            "{name}: {mae:.2} per channel, {over:.2} % of pixels over 40 from the snapshot"
        );
    }
}

/// A negative or non-finite impostor threshold is bad input: one line, exit 2, no file.
#[test]
fn a_bad_impostor_threshold_is_refused() {
    let dir = std::env::temp_dir().join(format!("grove-impostor-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out_png = dir.join("x.png");
    for bad in ["-1", "nan", "inf", "many"] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_grove"))
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .args(["render", "--scene", "assets/scenes/forest.ron", "--out"])
            .arg(&out_png)
            .arg(format!("--impostor-pixels={bad}"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad}: {err}");
        assert!(err.contains("at least 0"), "{bad}: {err}");
        assert!(!out_png.exists(), "{bad}: no file is written");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A tree turning slowly, drawn as an impostor, must not jump when its nearest atlas view
/// changes: the three nearest views are blended, so with the tree turned 1° a frame through
/// more than two views' spacing (about 13° around the horizon), no frame changes more than
/// three times the typical (median) frame, and none more than a quarter of the tree's pixels.
#[test]
fn a_slowly_turning_impostor_changes_smoothly() {
    use grove_systems::components::Transform;
    let data = load_model(&model_path("broadleaf-mesh")).unwrap();
    let dir = Vec3::new(0.0, 0.2, 1.0).normalize();
    let (mut sim, _) = stage(&data, dir, 200.0);
    let background = draw(&data, &sim, false, 0.0);
    // One renderer for every frame (its impostor atlas baked once); its first frame is checked
    // against a fresh renderer's below, so reusing it changes nothing drawn.
    let mut renderer = {
        let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        sky_stage::renderer(gpu(), &data, true, SIZE, 1.0e6)
    };
    let frames: Vec<RgbaImage> = (0..=30)
        .map(|k| {
            let mut all: Vec<(hecs::Entity, Transform)> = Vec::new();
            sim.for_each_tree(|t| all.extend(hecs::Entity::from_bits(t.id).map(|e| (e, t.transform))));
            for (e, t) in all {
                sim.set_up().transform(e, Transform { yaw: (k as f32).to_radians(), ..t }).unwrap();
            }
            let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
            offscreen::render_image(gpu(), &mut renderer, &sim).unwrap()
        })
        .collect();
    assert!(frames[30] == draw(&data, &sim, true, 1.0e6), "a reused renderer draws what a fresh one draws");
    let tree: Vec<bool> = frames.iter().fold(vec![false; (SIZE * SIZE) as usize], |acc, f| {
        acc.iter().zip(mask(f, &background)).map(|(a, b)| *a || b).collect()
    });
    let tree_pixels = tree.iter().filter(|&&x| x).count() as f64;
    assert!(tree_pixels > 2000.0, "the tree should fill the frame ({tree_pixels} px)");
    let changed = |a: &RgbaImage, b: &RgbaImage| {
        a.pixels().zip(b.pixels()).filter(|(p, q)| (0..3).any(|c| p.0[c].abs_diff(q.0[c]) > 40)).count() as f64
            / tree_pixels
    };
    let mut steps: Vec<f64> = frames.windows(2).map(|w| changed(&w[0], &w[1])).collect();
    let worst = steps.iter().copied().fold(0.0, f64::max);
    steps.sort_by(|a, b| a.total_cmp(b));
    let median = steps[steps.len() / 2];
    eprintln!(
        "turning impostor: median step {:.1} %, worst {:.1} % of the tree's pixels",
        median * 100.0,
        worst * 100.0
    );
    assert!(worst <= 3.0 * median.max(0.01), "a jump: worst step {worst:.3} against a median of {median:.3}");
    assert!(worst <= 0.25, "one frame changed {:.1} % of the tree", worst * 100.0);
}
