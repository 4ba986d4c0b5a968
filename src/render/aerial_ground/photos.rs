//! The aerial photographs of a scene, as the renderer holds them (`renderer.features.aerial`):
//! the aerial ground and the canopy, set together, settled for a still and their streaming
//! read back. Without photographs both are absent and nothing of this is drawn.

use grove_systems::Sim;

use super::super::canopy::Canopy;
use super::super::clipmap::{FedClipmap, clip_camera};
use super::super::extract;
use super::super::gpu::Shared;
use super::super::options::RenderOptions;
use super::{AerialGround, AerialSources};
use crate::render::error::RenderError;

/// The photographs' two drawn features, each absent until [`AerialPhotos::set`].
pub struct AerialPhotos {
    shared: Shared,
    /// The winter photograph draped over the ground.
    pub(crate) ground: Option<AerialGround>,
    /// The photographed crowns as canopy layers (only with layer masks).
    pub(crate) canopy: Option<Canopy>,
}

impl AerialPhotos {
    /// No photographs.
    pub(crate) fn new(shared: &Shared) -> AerialPhotos {
        AerialPhotos { shared: shared.clone(), ground: None, canopy: None }
    }

    /// Drapes aerial photographs over the ground from the next frame: the winter photograph as
    /// the ground where it lies, and, with layer masks, the photographed crowns as canopy layers
    /// (see the `aerial_ground` and `canopy` modules). Fails with one line for a clipmap the
    /// device cannot hold.
    pub fn set(&mut self, sources: AerialSources) -> Result<(), RenderError> {
        let debug = sources.debug_lod;
        let shared = &self.shared;
        let winter = FedClipmap::new(shared, sources.winter, "winter clipmap", debug, wgpu::FilterMode::Linear)?;
        self.ground = Some(AerialGround::new(shared, winter, sources.size_m, sources.elevation_m));
        self.canopy = match sources.layers {
            Some(layers) => {
                let summer =
                    FedClipmap::new(shared, sources.summer, "summer clipmap", debug, wgpu::FilterMode::Linear)?;
                let masks = FedClipmap::new(shared, layers, "layer mask clipmap", false, wgpu::FilterMode::Nearest)?;
                Some(Canopy::new(shared, summer, masks, sources.layer_count.clamp(1, 8), sources.layer_bits))
            }
            None => None,
        };
        Ok(())
    }

    /// Streams the clipmaps for the head's camera of `sim`, in a target of `size` pixels, until
    /// ten updates in a row, 15 ms apart, write nothing (the tiles the view needs have arrived),
    /// for at most `timeout`: for still images, whose one frame would otherwise show only the
    /// levels loaded by then.
    pub fn settle(&mut self, sim: &Sim, size: (u32, u32), timeout: std::time::Duration) -> Result<(), RenderError> {
        if self.ground.is_none() {
            return Ok(());
        }
        let camera = clip_camera(&extract::common(sim, &RenderOptions::default()).camera, size);
        let start = std::time::Instant::now();
        let mut quiet = 0;
        while quiet < 10 && start.elapsed() < timeout {
            let mut bytes = 0;
            if let Some(a) = &mut self.ground {
                bytes += a.winter.update(&self.shared.queue, &camera)?;
            }
            if let Some(c) = &mut self.canopy {
                bytes += c.summer.update(&self.shared.queue, &camera)? + c.masks.update(&self.shared.queue, &camera)?;
            }
            quiet = if bytes == 0 { quiet + 1 } else { 0 };
            std::thread::sleep(std::time::Duration::from_millis(15));
        }
        Ok(())
    }

    /// The bytes of clipmap texels the last frame uploaded (winter, summer and layer masks).
    pub fn upload_bytes(&self) -> u64 {
        let ground = self.ground.as_ref().map_or(0, |a| a.winter.gpu.bytes_last);
        let canopy = self.canopy.as_ref().map_or(0, |c| c.summer.gpu.bytes_last + c.masks.gpu.bytes_last);
        ground + canopy
    }

    /// The clipmaps' streaming in the last frame: the tiles their windows need that have not
    /// arrived (a coarser level shows there), and the longest of their updates, milliseconds
    /// (the frame's own work; tiles are read by the loader threads).
    pub fn streaming(&self) -> (usize, f64) {
        let mut fed: Vec<&FedClipmap> = self.ground.iter().map(|a| &a.winter).collect();
        fed.extend(self.canopy.iter().flat_map(|c| [&c.summer, &c.masks]));
        (fed.iter().map(|f| f.source.missing_tiles()).sum(), fed.iter().map(|f| f.update_ms).fold(0.0, f64::max))
    }
}
