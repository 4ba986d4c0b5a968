//! What the last frame's cull pass left on the GPU, read back for benchmarks and tests: the
//! blades drawn at each level of detail, and the order of the near and middle lists.
//!
//! Reads: the grass's indirect draws and lists. Waits for the GPU.

use super::{Grass, data};
use crate::render::error::RenderError;

/// The blades a frame drew at each level of detail.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BladeCounts {
    /// With 7 segments (13 triangles).
    pub near: u32,
    /// With 3 segments (5 triangles).
    pub mid: u32,
    /// Rasterised by the cull pass (narrower than a pixel).
    pub far: u32,
}

impl BladeCounts {
    /// All the blades drawn.
    pub fn total(&self) -> u32 {
        self.near + self.mid + self.far
    }
}

/// The near and middle blades the last frame drew, by their index in the uploaded order, in
/// the order they were drawn.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BladeLists {
    /// The near blades' list.
    pub near: Vec<u32>,
    /// The middle blades' list.
    pub mid: Vec<u32>,
}

/// `words` words of `buffer` from word `first` (waits for the GPU).
fn read_words(
    shared: &crate::render::gpu::Shared,
    buffer: &wgpu::Buffer,
    first: u64,
    words: u64,
) -> Result<Vec<u32>, RenderError> {
    if words == 0 {
        return Ok(Vec::new());
    }
    let bytes = 4 * words;
    let read = shared.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("grass readback"),
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder =
        shared.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("grass readback") });
    encoder.copy_buffer_to_buffer(buffer, 4 * first, &read, 0, bytes);
    shared.queue.submit([encoder.finish()]);
    let slice = read.slice(..);
    slice.map_async(wgpu::MapMode::Read, |_| {});
    shared.device.poll(wgpu::PollType::wait_indefinitely()).map_err(RenderError::GrassCountsPoll)?;
    let words: Vec<u32> =
        bytemuck::cast_slice(&slice.get_mapped_range().map_err(RenderError::GrassCountsRange)?).to_vec();
    Ok(words)
}

impl Grass {
    /// The numbers of blades the last frame drew at each level of detail, read back from the
    /// indirect draws (waits for the GPU); all zero without blades.
    pub fn visible_blades(&self) -> Result<BladeCounts, RenderError> {
        let Some(b) = self.blades.as_ref().filter(|_| self.enabled) else { return Ok(BladeCounts::default()) };
        let words = read_words(&self.shared, &b.args, 0, data::ARGS_WORDS as u64)?;
        let [n, m] = data::LOD_INDICES;
        Ok(BladeCounts { near: words[0] / n, mid: words[5] / m, far: words[10] })
    }

    /// The near and middle lists the last frame drew (waits for the GPU); empty without blades.
    pub fn listed_blades(&self) -> Result<BladeLists, RenderError> {
        let Some(b) = self.blades.as_ref().filter(|_| self.enabled) else { return Ok(BladeLists::default()) };
        let counts = self.visible_blades()?;
        Ok(BladeLists {
            near: read_words(&self.shared, &b.lists, 0, counts.near.into())?,
            mid: read_words(&self.shared, &b.lists, b.count.into(), counts.mid.into())?,
        })
    }
}
