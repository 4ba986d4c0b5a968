//! The render benchmarks that combine several others: only the reference scene (with the
//! impostors' image error), and the whole set on a real GPU. A module of its own, above the
//! benchmarks it calls, so that none of them imports another's caller.

use serde_json::Value;

use super::BenchError;
use super::render::{
    RenderBenchOptions, WALL_TIMING, forest, forest_figures, header, reference_scene, setup, species_forest,
};

/// Runs only the reference scene and returns its figures.
pub fn bench_reference(options: RenderBenchOptions) -> Result<Value, BenchError> {
    let (gpu, mut renderer, adapter) = setup(options, false)?;
    let reference = reference_scene(&gpu, &mut renderer)?;
    let mut out = header(adapter, &renderer, WALL_TIMING);
    out.insert("reference_100_trees".into(), reference);
    if options.impostor_pixels > 0.0 || options.leaf_pixels > 0.0 {
        let sim = forest(10, Some(&|i| (i % 8) as u8))?;
        out.insert("reference_image_vs_full_detail".into(), super::impostor::image_error(&gpu, &mut renderer, &sim)?);
        let sim = species_forest(&mut renderer, 10)?;
        out.insert(
            "reference_species_image_vs_full_detail".into(),
            super::impostor::image_error(&gpu, &mut renderer, &sim)?,
        );
    }
    Ok(Value::Object(out))
}

/// The reference scene grown to 10k trees (100 × 100, 10 m apart) on a real GPU, timed with
/// timestamp queries. Fails on a software adapter or a device without timestamp queries.
pub fn bench_gpu(options: RenderBenchOptions) -> Result<Value, BenchError> {
    let (gpu, mut renderer, adapter) = setup(options, true)?;
    let reference = reference_scene(&gpu, &mut renderer)?;
    let forest = forest_figures(&gpu, &mut renderer, 100, 30)?;
    let mut out = header(
        adapter,
        &renderer,
        "median of frames: GPU time of the shadow and main passes from timestamp queries; wall time of render + device.poll(wait)",
    );
    out.insert("reference_100_trees".into(), reference);
    out.insert("forest_10k_trees".into(), forest);
    out.insert("water_test".into(), super::water::water_figures(&gpu, &mut renderer, 30)?);
    out.insert("grass".into(), super::grass::bench_grass_gpu(&gpu)?);
    let park = super::park::park_scene();
    out.insert("park".into(), super::park::park_figures(&gpu, &mut renderer, 30, &super::load_scene(&park)?, &park)?);
    super::impostor::forest_gpu_figures(&gpu, &mut renderer, &mut out)?;
    Ok(Value::Object(out))
}
