//! Opening a scene's aerial photographs for the renderer: the summer and winter photographs
//! and the layer masks its `aerial` section names ([`grove_systems::aerial::AerialDef`]),
//! resolved against the scene file's folder, as clipmap sources.
//!
//! Image files (PNG or TIFF, up to [`ImageSource`]'s limit) are held whole in memory and served
//! by [`ImageSource`]; tile folders need the tiled clipmap, which reads them from disk as the
//! camera moves.

use std::path::{Path, PathBuf};

use glam::{DVec2, Vec2};
use grove_systems::scene::Scene;

use super::raster::RgbImage;
use crate::render::aerial_ground::AerialSources;
use crate::render::clipmap::image_source::{Downsample, ImageSource};
use crate::render::clipmap::{AerialPlacement, ClipmapConfig};

/// The clipmap of a photograph held in memory: 8 levels of at most 512 texels a side.
pub fn memory_config(width: u32, height: u32) -> ClipmapConfig {
    ClipmapConfig { levels: 8, size: width.max(height).next_power_of_two().clamp(16, 512) }
}

/// The path of a file a scene names: relative to the scene file's folder.
fn resolve(scene: &Scene, rel: &str) -> PathBuf {
    scene.dir.as_deref().unwrap_or(Path::new("")).join(rel)
}

/// Reads one photograph of the pair; a folder is refused with one line.
fn photo(path: &Path, what: &str) -> Result<RgbImage, String> {
    if path.is_dir() {
        return Err(format!("{}: the {what} is a tile folder; this build reads image files only (tile folders come with the tiled clipmap)", path.display()));
    }
    RgbImage::load(path, what)
}

/// The clipmap sources of `scene`'s aerial section, or `None` without one. Errors are one line
/// naming the file: missing or unreadable images, or images of different sizes.
pub fn open_sources(scene: &Scene, debug_lod: bool) -> Result<Option<AerialSources>, String> {
    let Some(a) = &scene.aerial else { return Ok(None) };
    let winter = photo(&resolve(scene, &a.winter), "winter photograph")?;
    let summer = photo(&resolve(scene, &a.summer), "summer photograph")?;
    let (w, h) = (winter.width, winter.height);
    if (summer.width, summer.height) != (w, h) {
        return Err(format!("aerial: the summer photograph is {}x{} but the winter one is {w}x{h}", summer.width, summer.height));
    }
    let placement = AerialPlacement { origin_m: DVec2::new(f64::from(a.origin.x), f64::from(a.origin.y)), gsd_m: f64::from(a.gsd_m) };
    let config = memory_config(w, h);
    let layers = match &a.layers {
        Some(rel) => {
            let path = resolve(scene, rel);
            let m = photo(&path, "layer mask")?;
            if (m.width, m.height) != (w, h) {
                return Err(format!("{}: the layer mask is {}x{} but the photographs are {w}x{h}", path.display(), m.width, m.height));
            }
            // The mask's bits in red, opaque; never blended between texels.
            let rgba = m.data.chunks_exact(3).flat_map(|t| [t[0], 0, 0, 255]).collect();
            Some(Box::new(ImageSource::with_downsample(w, h, rgba, config, placement, Downsample::Nearest)?) as _)
        }
        None => None,
    };
    Ok(Some(AerialSources {
        winter: Box::new(ImageSource::from_rgb(&winter, config, placement)?),
        summer: Box::new(ImageSource::from_rgb(&summer, config, placement)?),
        layers,
        size_m: Vec2::new(w as f32, h as f32) * a.gsd_m,
        elevation_m: a.elevation,
        layer_count: a.layer_count,
        debug_lod,
    }))
}
