//! The impostor atlas cache on disk (src/render/trees/impostor/cache.rs), on whatever adapter
//! wgpu finds (lavapipe in CI): a model loaded a second time reads its atlases from the cache
//! instead of baking them, and draws the same image; a damaged or cut-short cache file is baked
//! again and replaced, without a panic.

use glam::Vec3;
use grove::models::{ModelData, load_model};
use grove::render::Renderer;
use grove::render::offscreen::{self, Gpu};
use grove_systems::Sim;
use grove_systems::catalogue::ModelId;
use grove_systems::components::{Head, Pose};
use grove_systems::stage::model_stage;
use image::RgbaImage;

const SIZE: u32 = 128;

fn model() -> ModelData {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/trees/conifer-mesh.gltf");
    load_model(&path).unwrap()
}

/// A renderer with the model loaded through the cache in `dir`, and how many atlases it baked.
fn load(gpu: &Gpu, data: &ModelData, dir: &std::path::Path) -> (Renderer, usize) {
    let mut r =
        Renderer::empty(&gpu.device, &gpu.queue, offscreen::FORMAT, SIZE, SIZE, &grove::render::default_assets_dir())
            .unwrap();
    r.features.trees.set_impostor_cache(Some(dir.to_path_buf()));
    r.features.trees.set_model(ModelId(0), data);
    let bakes = r.features.trees.impostor_bakes();
    (r, bakes)
}

/// The model's stage seen from 80 m away at 20° up, drawn as an impostor.
fn draw(gpu: &Gpu, r: &mut Renderer, data: &ModelData) -> RgbaImage {
    let mut sim: Sim = model_stage(data.bounds, 1.0, false, ModelId(0)).unwrap();
    let (lo, hi) = data.bounds;
    let centre = (lo + hi) * 0.5;
    let eye = centre + Vec3::new(0.0, 20f32.to_radians().sin(), 20f32.to_radians().cos()) * 80.0;
    sim.set_up().camera(Head { pose: Pose::looking_at(eye, centre), fov_y: 20f32.to_radians() });
    r.options.shadows = false;
    r.options.impostor_pixels = 1.0e6;
    offscreen::render_image(gpu, r, &sim).unwrap()
}

/// The cache files in `dir`.
fn files(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut v: Vec<_> =
        std::fs::read_dir(dir.join("impostors")).map(|d| d.flatten().map(|e| e.path()).collect()).unwrap_or_default();
    v.sort();
    v
}

#[test]
fn the_second_load_reads_the_cache_and_a_damaged_file_is_baked_again() {
    let gpu = Gpu::new().unwrap_or_else(|e| panic!("impostor tests need a GPU adapter (CI installs lavapipe): {e}"));
    let data = model();
    let tmp = tempfile::tempdir().unwrap();

    // First load: baked, and one file written (no temporary file left beside it).
    let (mut r, bakes) = load(&gpu, &data, tmp.path());
    assert_eq!(bakes, 1, "the first load bakes");
    let written = files(tmp.path());
    assert_eq!(written.len(), 1, "{written:?}");
    assert!(written[0].extension().is_some_and(|e| e == "atlas"), "{written:?}");
    let baked = draw(&gpu, &mut r, &data);
    let tree_pixels = baked.pixels().filter(|p| p.0 != baked.get_pixel(0, 0).0).count();
    assert!(tree_pixels > 500, "the impostor should be visible ({tree_pixels} px)");
    let bytes = std::fs::read(&written[0]).unwrap();

    // Second load: read from the cache, no bake, the same image.
    let (mut r, bakes) = load(&gpu, &data, tmp.path());
    assert_eq!(bakes, 0, "the second load reads the cache");
    assert!(draw(&gpu, &mut r, &data) == baked, "the cached atlas draws the same image");

    // A flipped byte in the texels: baked again, and the file replaced by a good one.
    let mut damaged = bytes.clone();
    let mid = damaged.len() / 2;
    damaged[mid] ^= 0x5a;
    std::fs::write(&written[0], &damaged).unwrap();
    let (mut r, bakes) = load(&gpu, &data, tmp.path());
    assert_eq!(bakes, 1, "a damaged file is baked again");
    assert!(draw(&gpu, &mut r, &data) == baked);
    let (_, bakes) = load(&gpu, &data, tmp.path());
    assert_eq!(bakes, 0, "the damaged file was replaced");

    // A file cut short, and one that is not an atlas at all: baked again.
    std::fs::write(&written[0], &bytes[..bytes.len() / 3]).unwrap();
    assert_eq!(load(&gpu, &data, tmp.path()).1, 1);
    std::fs::write(&written[0], b"not an atlas").unwrap();
    assert_eq!(load(&gpu, &data, tmp.path()).1, 1);
    assert_eq!(files(tmp.path()), written, "one file, no temporary ones left behind");
}

#[test]
fn no_cache_folder_bakes_every_time_and_writes_nothing() {
    let gpu = Gpu::new().unwrap_or_else(|e| panic!("impostor tests need a GPU adapter: {e}"));
    let data = model();
    for _ in 0..2 {
        let mut r = Renderer::empty(
            &gpu.device,
            &gpu.queue,
            offscreen::FORMAT,
            SIZE,
            SIZE,
            &grove::render::default_assets_dir(),
        )
        .unwrap();
        r.features.trees.set_impostor_cache(None);
        r.features.trees.set_model(ModelId(0), &data);
        assert_eq!(r.features.trees.impostor_bakes(), 1);
    }
}
