//! The renderer's aerial methods: the photographs set, settled for a still and their streaming
//! read back. They live with the feature; `Renderer`'s fields stay private to `render`.

use grove_systems::Sim;

use super::super::{canopy, extract, Renderer};

impl Renderer {
    /// Drapes aerial photographs over the ground from the next frame: the winter photograph as
    /// the ground where it lies, and, with layer masks, the photographed crowns as canopy layers
    /// (see the `aerial_ground` and `canopy` modules). Fails with one line for a clipmap the device cannot
    /// hold.
    pub fn set_aerial(&mut self, sources: super::AerialSources) -> Result<(), String> {
        let debug = sources.debug_lod;
        let winter = super::FedClipmap::new(&self.shared, sources.winter, "winter clipmap", debug, wgpu::FilterMode::Linear)?;
        self.aerial_ground = Some(super::AerialGround::new(&self.shared, winter, sources.size_m, sources.elevation_m));
        self.canopy = match sources.layers {
            Some(layers) => {
                let summer = super::FedClipmap::new(&self.shared, sources.summer, "summer clipmap", debug, wgpu::FilterMode::Linear)?;
                let masks = super::FedClipmap::new(&self.shared, layers, "layer mask clipmap", false, wgpu::FilterMode::Nearest)?;
                Some(canopy::Canopy::new(&self.shared, summer, masks, sources.layer_count.clamp(1, 8), sources.layer_bits))
            }
            None => None,
        };
        Ok(())
    }

    /// Streams the aerial clipmaps for `sim`'s camera until ten updates in a row, 15 ms apart,
    /// write nothing (the tiles the view needs have arrived), for at most `timeout`: for still
    /// images, whose one frame would otherwise show only the levels loaded by then.
    pub fn settle_aerial(&mut self, sim: &Sim, timeout: std::time::Duration) -> Result<(), String> {
        if self.aerial_ground.is_none() {
            return Ok(());
        }
        let data = extract::FrameData::extract(sim, &self.ground.key);
        let camera = super::clip_camera(&data, (self.width, self.height));
        let start = std::time::Instant::now();
        let mut quiet = 0;
        while quiet < 10 && start.elapsed() < timeout {
            let mut bytes = 0;
            if let Some(a) = &mut self.aerial_ground {
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
    pub fn aerial_upload_bytes(&self) -> u64 {
        let ground = self.aerial_ground.as_ref().map_or(0, |a| a.winter.gpu.bytes_last);
        let canopy = self.canopy.as_ref().map_or(0, |c| c.summer.gpu.bytes_last + c.masks.gpu.bytes_last);
        ground + canopy
    }

    /// The aerial clipmaps' streaming in the last frame: the tiles their windows need that have
    /// not arrived (a coarser level shows there), and the longest of their updates,
    /// milliseconds (the frame's own work; tiles are read by the loader threads).
    pub fn aerial_streaming(&self) -> (usize, f64) {
        let mut fed: Vec<&super::FedClipmap> = self.aerial_ground.iter().map(|a| &a.winter).collect();
        fed.extend(self.canopy.iter().flat_map(|c| [&c.summer, &c.masks]));
        (fed.iter().map(|f| f.source.missing_tiles()).sum(), fed.iter().map(|f| f.update_ms).fold(0.0, f64::max))
    }
}
