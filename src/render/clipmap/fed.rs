//! A clipmap fed by its source, as the drawn features that read photographs hold it (the aerial
//! ground's winter photograph, the canopy's summer photograph and layer masks), and the
//! clipmap camera of a frame's view.

use glam::DVec3;

use super::{ClipCamera, ClipmapSource, GpuClipmap};
use crate::render::error::RenderError;
use crate::render::gpu::Shared;
use crate::render::view::Camera;

/// The clipmap camera of a frame's view: its eye, view direction and frustum.
pub(crate) fn clip_camera(c: &Camera, size: (u32, u32)) -> ClipCamera {
    ClipCamera {
        eye: c.position.as_dvec3(),
        forward: (c.rotation * glam::Vec3::NEG_Z).as_dvec3().normalize_or(DVec3::NEG_Y),
        fov_y: f64::from(c.fov_y),
        aspect: f64::from(size.0.max(1)) / f64::from(size.1.max(1)),
    }
}

/// A clipmap fed by its source: the pair the ground and the canopy read.
pub(crate) struct FedClipmap {
    /// The CPU half.
    pub source: Box<dyn ClipmapSource>,
    /// The GPU half.
    pub gpu: GpuClipmap,
    /// How long the last [`FedClipmap::update`] took, milliseconds (placing the levels, copying
    /// the texels of tiles that have arrived, writing them; never reading a tile).
    pub update_ms: f64,
}

impl FedClipmap {
    /// The GPU half for `source`, labelled.
    pub fn new(
        shared: &Shared,
        source: Box<dyn ClipmapSource>,
        label: &str,
        debug_lod: bool,
        filter: wgpu::FilterMode,
    ) -> Result<FedClipmap, RenderError> {
        let mut gpu = GpuClipmap::with_filter(&shared.device, source.config(), source.placement(), label, filter)?;
        gpu.set_debug_lod(debug_lod);
        Ok(FedClipmap { source, gpu, update_ms: 0.0 })
    }

    /// Moves the levels for `camera` and writes what changed; the bytes written.
    pub fn update(&mut self, queue: &wgpu::Queue, camera: &ClipCamera) -> Result<u64, RenderError> {
        let start = std::time::Instant::now();
        let frame = self.source.update(camera);
        let bytes = self.gpu.apply(queue, &frame).map_err(RenderError::from);
        self.update_ms = start.elapsed().as_secs_f64() * 1e3;
        bytes
    }
}
