//! Opening a scene's aerial photographs for the renderer: the summer and winter photographs
//! and the layer masks its `aerial` section names ([`grove_systems::aerial::AerialDef`]),
//! resolved against the scene file's folder, as clipmap sources.
//!
//! Image files (PNG or TIFF, up to [`ImageSource`]'s limit) are held whole in memory and served
//! by [`ImageSource`]; tile folders (`grove aerial tile`) are streamed from disk by
//! [`Clipmap`] as the camera moves. The layer masks must be an image file: a tile pyramid
//! averages texels, which would mix their bits.

use std::path::{Path, PathBuf};

use glam::{DVec2, Vec2};
use grove_systems::scene::Scene;

use crate::aerial::{AerialError, RgbImage};
use crate::render::canopy::extents::LayerBits;
use crate::render::clipmap::image_source::{Downsample, ImageSource};
use crate::render::clipmap::{AerialPlacement, Clipmap, ClipmapConfig, ClipmapSource};
use crate::render::error::ClipmapError;

use super::AerialSources;

/// The clipmap of a photograph held in memory: 8 levels of at most 512 texels a side.
pub fn memory_config(width: u32, height: u32) -> ClipmapConfig {
    ClipmapConfig { levels: 8, size: width.max(height).next_power_of_two().clamp(16, 512) }
}

/// The path of a file a scene names: relative to the scene file's folder.
fn resolve(scene: &Scene, rel: &str) -> PathBuf {
    scene.dir.as_deref().unwrap_or(Path::new("")).join(rel)
}

/// The clipmap of a tile folder: 8 levels of 1024 texels.
pub const TILED: ClipmapConfig = ClipmapConfig { levels: 8, size: 1024 };

/// One photograph of the pair as a clipmap source and its size in texels: a tile folder
/// streamed from disk, or an image file held in memory.
fn photo(
    path: &Path,
    what: &str,
    placement: AerialPlacement,
) -> Result<(Box<dyn ClipmapSource>, u32, u32), ClipmapError> {
    if path.is_dir() {
        let c = Clipmap::open(path, TILED, placement).map_err(|e| e.named(what))?;
        let (w, h) = (c.meta().width, c.meta().height);
        return Ok((Box::new(c), w, h));
    }
    let img = RgbImage::load(path, what)?;
    let (w, h) = (img.width, img.height);
    Ok((Box::new(ImageSource::from_rgb(&img, memory_config(w, h), placement)?), w, h))
}

/// The clipmap sources of `scene`'s aerial section, or `None` without one. Errors are one line
/// naming the file: missing or unreadable images, or images of different sizes.
pub fn open_sources(scene: &Scene, debug_lod: bool) -> Result<Option<AerialSources>, ClipmapError> {
    let Some(a) = &scene.aerial else { return Ok(None) };
    let placement = AerialPlacement {
        origin_m: DVec2::new(f64::from(a.origin.x), f64::from(a.origin.y)),
        gsd_m: f64::from(a.gsd_m),
    };
    let (winter, w, h) = photo(&resolve(scene, &a.winter), "winter photograph", placement)?;
    let (summer, sw, sh) = photo(&resolve(scene, &a.summer), "summer photograph", placement)?;
    if (sw, sh) != (w, h) {
        return Err(AerialError::PhotographSizes { summer: (sw, sh), winter: (w, h) }.into());
    }
    let mut layer_bits = None;
    let layers = match &a.layers {
        Some(rel) => {
            let path = resolve(scene, rel);
            if path.is_dir() {
                return Err(AerialError::LayersAreFolder(path).into());
            }
            let m = RgbImage::load(&path, "layer mask")?;
            if (m.width, m.height) != (w, h) {
                return Err(AerialError::LayerMaskSize { path, mask: (m.width, m.height), photos: (w, h) }.into());
            }
            // The bits once more, a byte a texel, for the canopy's quad sizes.
            layer_bits = Some(LayerBits {
                width: w,
                height: h,
                bits: m.data.chunks_exact(3).map(|t| t[0]).collect(),
                origin_m: placement.origin_m.as_vec2(),
                gsd_m: a.gsd_m,
            });
            // The mask's bits in red, opaque; never blended between texels.
            let rgba = m.data.chunks_exact(3).flat_map(|t| [t[0], 0, 0, 255]).collect();
            Some(Box::new(ImageSource::with_downsample(
                w,
                h,
                rgba,
                memory_config(w, h),
                placement,
                Downsample::Nearest,
            )?) as _)
        }
        None => None,
    };
    Ok(Some(AerialSources {
        winter,
        summer,
        layers,
        layer_bits,
        size_m: Vec2::new(w as f32, h as f32) * a.gsd_m,
        elevation_m: a.elevation,
        layer_count: a.layer_count,
        debug_lod,
    }))
}
