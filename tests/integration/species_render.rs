//! Golden images of the species presets (`grove trees generate`, docs/species.md) through the
//! renderer, on whatever adapter wgpu finds (lavapipe in CI): each species at seed 1 seen from
//! 10 m (the full model) and from 50 m (its first level of detail), 160×120, compared with
//! `tests/snapshots/species-<name>-<d>m.png` with the tolerance of `tests/integration/render_golden.rs`.
//! Regenerate with `UPDATE_SNAPSHOTS=1 cargo test --test integration species_render::`, which also writes the
//! sheet of all species side by side, `docs/species.png`. A failing comparison writes the actual
//! image to `target/snapshot-failures/`.

use std::path::{Path, PathBuf};

use grove::models::{ModelData, load_model};
use grove::render::offscreen;
use grove::render::{RenderOptions, Renderer};
use grove_systems::catalogue::ModelId;
use image::RgbaImage;

use crate::shared_gpu;
use shared_gpu::LOCK;

const W: u32 = 160;
const H: u32 = 120;
const PIXEL_THRESHOLD: u8 = 40;
const SPECIES: [&str; 6] = ["oak", "birch", "beech", "scots_pine", "norway_spruce", "shrub"];

pub(crate) fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub(crate) fn update() -> bool {
    std::env::var("UPDATE_SNAPSHOTS").is_ok_and(|v| v == "1")
}

fn compare(name: &str, img: &RgbaImage) {
    let path = root().join("tests/snapshots").join(format!("{name}.png"));
    if update() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        img.save(&path).unwrap();
        return;
    }
    let want = image::open(&path)
        .unwrap_or_else(|e| {
            panic!("{}: cannot read the snapshot ({e}); create it with UPDATE_SNAPSHOTS=1", path.display())
        })
        .to_rgba8();
    assert_eq!(want.dimensions(), img.dimensions(), "{name}: size differs from the snapshot");
    let (mut sum, mut over) = (0u64, 0u64);
    for (a, b) in want.pixels().zip(img.pixels()) {
        let worst = (0..3).map(|c| a.0[c].abs_diff(b.0[c])).max().unwrap();
        sum += (0..3).map(|c| a.0[c].abs_diff(b.0[c]) as u64).sum::<u64>();
        over += u64::from(worst > PIXEL_THRESHOLD);
    }
    let n = (img.width() * img.height()) as f64;
    let (mean, percent) = (sum as f64 / (n * 3.0), over as f64 * 100.0 / n);
    if mean > 3.0 || percent > 2.0 {
        let dir = root().join("target/snapshot-failures");
        let _ = std::fs::create_dir_all(&dir);
        let _ = img.save(dir.join(format!("{name}.png")));
        panic!(
            "{name}: differs from {} (mean abs diff {mean:.2} > 3 or {percent:.2}% pixels over {PIXEL_THRESHOLD} > 2%)",
            path.display()
        );
    }
}

/// The species' model files, written once per test into `dir`.
pub(crate) fn generate(species: &str, dir: &Path) -> (ModelData, ModelData) {
    grove::species::output::write(species, 1, dir).unwrap_or_else(|e| panic!("{species}: {e}"));
    let full = load_model(&dir.join(format!("{species}.gltf"))).unwrap();
    let lod1 = load_model(&dir.join(format!("{species}-lod1.gltf"))).unwrap();
    (full, lod1)
}

/// The model alone on its stage (or, without `tree`, the stage alone), seen from `distance`
/// metres as a walker sees it (`grove_systems::stage::walker_view`).
fn view(data: &ModelData, distance: f32, tree: bool) -> RgbaImage {
    view_sized(data, distance, tree, W, H, RenderOptions::default().leaf_pixels)
}

/// [`view`] at `w` × `h` pixels, leaves simplified below `leaf_pixels` (0: every leaf drawn).
pub(crate) fn view_sized(data: &ModelData, distance: f32, tree: bool, w: u32, h: u32, leaf_pixels: f32) -> RgbaImage {
    view_lit(data, distance, tree, (w, h), leaf_pixels, 40.0)
}

/// [`view_sized`] with the sun `sun_elevation_deg` above the horizon (from behind the camera's
/// left shoulder).
pub(crate) fn view_lit(
    data: &ModelData,
    distance: f32,
    tree: bool,
    (w, h): (u32, u32),
    leaf_pixels: f32,
    sun_elevation_deg: f64,
) -> RgbaImage {
    let g = shared_gpu::shared_gpu("species renders");
    let mut sim = grove_systems::stage::model_stage(data.bounds, w as f32 / h as f32, false, ModelId(0)).unwrap();
    if !tree {
        let mut trees: Vec<hecs::Entity> = Vec::new();
        sim.for_each_tree(|t| trees.extend(hecs::Entity::from_bits(t.id)));
        for e in trees {
            sim.set_up().despawn(e).unwrap();
        }
    }
    grove_systems::stage::walker_view(&mut sim, data.bounds.1.y, distance);
    sim.set_up().sun_angles(sun_elevation_deg, grove_systems::stage::WALKER_SUN_DEG.1);
    let mut r = Renderer::empty(&g.device, &g.queue, offscreen::FORMAT, w, h, &root().join("assets")).unwrap();
    r.options.impostor_pixels = 0.0;
    r.options.leaf_pixels = leaf_pixels;
    r.features.trees.set_model(ModelId(0), data);
    offscreen::render_image(g, &mut r, &sim).unwrap()
}

/// Pixels where the image with the tree differs from the stage without it.
fn tree_pixels(img: &RgbaImage, stage: &RgbaImage) -> usize {
    img.pixels()
        .zip(stage.pixels())
        .filter(|(p, q)| (0..3).map(|c| p.0[c].abs_diff(q.0[c])).max().unwrap() > 30)
        .count()
}

fn species_test(species: &str) {
    let dir = tempfile::tempdir().unwrap();
    let (full, lod1) = generate(species, dir.path());
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let near = view(&full, 10.0, true);
    let far = view(&lod1, 50.0, true);
    // The tree is there, and it takes more of the frame from 10 m than from 50 m.
    let (a, b) = (tree_pixels(&near, &view(&full, 10.0, false)), tree_pixels(&far, &view(&lod1, 50.0, false)));
    assert!(b > 5, "{species}: the tree at 50 m covers {b} pixels");
    assert!(a > 4 * b, "{species}: the tree covers {a} pixels at 10 m, {b} at 50 m");
    compare(&format!("species-{species}-10m"), &near);
    compare(&format!("species-{species}-50m"), &far);
}

#[test]
fn oak() {
    species_test("oak");
}

#[test]
fn birch() {
    species_test("birch");
}

#[test]
fn beech() {
    species_test("beech");
}

#[test]
fn scots_pine() {
    species_test("scots_pine");
}

#[test]
fn norway_spruce() {
    species_test("norway_spruce");
}

#[test]
fn shrub() {
    species_test("shrub");
}

/// Relative luminance of a pixel's bytes (Rec. 709 weights on the sRGB values).
pub(crate) fn luma(p: &image::Rgba<u8>) -> f32 {
    0.2126 * f32::from(p.0[0]) + 0.7152 * f32::from(p.0[1]) + 0.0722 * f32::from(p.0[2])
}

/// With `UPDATE_SNAPSHOTS=1`, writes `docs/species.png`: every species framed whole, side by
/// side, each 200×260; otherwise checks that the committed sheet has that layout.
#[test]
fn species_sheet() {
    let (w, h) = (200u32, 260u32);
    let path = root().join("docs/species.png");
    if !update() {
        let sheet =
            image::open(&path).unwrap_or_else(|e| panic!("{}: {e}; write it with UPDATE_SNAPSHOTS=1", path.display()));
        assert_eq!((sheet.width(), sheet.height()), (w * SPECIES.len() as u32, h));
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut sheet = RgbaImage::new(w * SPECIES.len() as u32, h);
    for (i, s) in SPECIES.iter().enumerate() {
        let (full, _) = generate(s, &dir.path().join(s));
        let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        let g = shared_gpu::shared_gpu("the species sheet");
        let img = offscreen::render_model_data(g, &full, w, h, RenderOptions::default(), None).unwrap();
        image::imageops::replace(&mut sheet, &img, (i as u32 * w) as i64, 0);
    }
    grove::atomic_write::write_via_temp(&path, |tmp| Ok(sheet.save(tmp)?)).unwrap();
}
