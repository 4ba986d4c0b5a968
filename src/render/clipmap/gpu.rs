//! The GPU half of a clipmap: a texture array of `levels` layers of `size` × `size` RGBA8
//! texels (one layer per level, addressed toroidally), the uniform of the levels' placements,
//! and [`GpuClipmap::apply`], which writes a [`ClipmapFrame`]'s uploads and placements. The WGSL
//! side is `clipmap.wgsl` ([`WGSL`]): `clipmap_sample` (bilinear, the finest loaded level that
//! holds the point), `clipmap_load` (through a nearest sampler, for masks; see
//! [`GpuClipmap::with_filter`]) and `clipmap_min_level`.
//!
//! Bindings: a feature puts a clipmap's three bindings (uniform, texture array, repeating
//! sampler) into its own group with [`GpuClipmap::layout_entries`] and
//! [`GpuClipmap::bind_entries`].

use super::{AerialPlacement, ClipmapConfig, ClipmapFrame};
use crate::render::error::ClipmapError;

/// The most levels the uniform holds (matches `array<ClipLevel, 16>` in clipmap.wgsl).
pub const MAX_LEVELS: usize = 16;

/// One level in the uniform (matches `ClipLevel` in clipmap.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct LevelUniform {
    /// The window's top-left texel in its mip's texels, x.
    origin_x: f32,
    /// The same, y.
    origin_y: f32,
    /// The mip's texel size, metres.
    texel_m: f32,
    /// The mip number.
    mip: f32,
}

/// The clipmap's uniform (matches `Clipmap` in clipmap.wgsl): 288 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct ClipmapUniform {
    photo_origin: [f32; 2],
    size: f32,
    levels: u32,
    debug_lod: u32,
    pad: [u32; 3],
    level: [LevelUniform; MAX_LEVELS],
}

/// Checks a configuration: 1..=16 levels, a power-of-two size in 16..=4096 that the device's
/// texture limits allow.
pub fn check_config(config: ClipmapConfig, limits: &wgpu::Limits) -> Result<(), ClipmapError> {
    if !(1..=MAX_LEVELS as u32).contains(&config.levels) {
        return Err(ClipmapError::GpuLevels { levels: config.levels, max: MAX_LEVELS });
    }
    if !config.size.is_power_of_two() || !(16..=4096).contains(&config.size) {
        return Err(ClipmapError::GpuSide(config.size));
    }
    if config.size > limits.max_texture_dimension_2d || config.levels > limits.max_texture_array_layers {
        return Err(ClipmapError::TextureLimits {
            max_side: limits.max_texture_dimension_2d,
            max_layers: limits.max_texture_array_layers,
        });
    }
    Ok(())
}

/// A clipmap on the GPU.
pub struct GpuClipmap {
    config: ClipmapConfig,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    sampler: wgpu::Sampler,
    uniform_buffer: wgpu::Buffer,
    uniform: ClipmapUniform,
    /// Bytes of texels written by the last [`GpuClipmap::apply`].
    pub bytes_last: u64,
    /// Bytes of texels written since the clipmap was made.
    pub bytes_total: u64,
}

impl GpuClipmap {
    /// An empty (transparent) clipmap of `config` for a photograph at `placement`; `label` names
    /// its texture ("summer clipmap", say) in GPU captures and errors.
    pub fn new(
        device: &wgpu::Device,
        config: ClipmapConfig,
        placement: AerialPlacement,
        label: &str,
    ) -> Result<GpuClipmap, ClipmapError> {
        GpuClipmap::with_filter(device, config, placement, label, wgpu::FilterMode::Linear)
    }

    /// [`GpuClipmap::new`] with a sampler of `filter`: `Nearest` for data that must not be
    /// blended between texels (the layer masks, read with `clipmap_load`).
    pub fn with_filter(
        device: &wgpu::Device,
        config: ClipmapConfig,
        placement: AerialPlacement,
        label: &str,
        filter: wgpu::FilterMode,
    ) -> Result<GpuClipmap, ClipmapError> {
        check_config(config, &device.limits())?;
        if !(placement.gsd_m.is_finite() && placement.gsd_m > 0.0) || !placement.origin_m.is_finite() {
            return Err(ClipmapError::GpuPlacement { label: label.to_string() });
        }
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width: config.size, height: config.size, depth_or_array_layers: config.levels },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(label),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        // Repeating in both directions: the toroidal addressing.
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some(label),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: filter,
            min_filter: filter,
            ..Default::default()
        });
        let mut uniform = ClipmapUniform {
            photo_origin: [placement.origin_m.x as f32, placement.origin_m.y as f32],
            size: config.size as f32,
            levels: config.levels,
            debug_lod: 0,
            pad: [0; 3],
            level: [LevelUniform::default(); MAX_LEVELS],
        };
        for (i, l) in uniform.level.iter_mut().enumerate() {
            // Until the first frame, level i shows mip i far away from everything.
            l.texel_m = (placement.gsd_m * f64::from(1u32 << i)) as f32;
            l.mip = i as f32;
            l.origin_x = -1.0e7;
            l.origin_y = -1.0e7;
        }
        let uniform_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: std::mem::size_of::<ClipmapUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut c =
            GpuClipmap { config, texture, view, sampler, uniform_buffer, uniform, bytes_last: 0, bytes_total: 0 };
        c.uniform.debug_lod = 0;
        Ok(c)
    }

    /// The levels and their size.
    pub fn config(&self) -> ClipmapConfig {
        self.config
    }

    /// Colours the levels (`--debug-lod`) from the next [`GpuClipmap::apply`].
    pub fn set_debug_lod(&mut self, on: bool) {
        self.uniform.debug_lod = u32::from(on);
    }

    /// Writes the frame's uploads into their layers and the placements into the uniform;
    /// returns the texel bytes written (also kept in [`GpuClipmap::bytes_last`]). An upload that
    /// does not fit its level, or a frame with another number of levels, is an error and
    /// nothing of the frame is written.
    pub fn apply(&mut self, queue: &wgpu::Queue, frame: &ClipmapFrame) -> Result<u64, ClipmapError> {
        let n = self.config.size;
        if !frame.placements.is_empty() && frame.placements.len() != self.config.levels as usize {
            return Err(ClipmapError::FramePlacements {
                placements: frame.placements.len(),
                levels: self.config.levels,
            });
        }
        for u in &frame.uploads {
            let fits = u.level < self.config.levels
                && u.x.checked_add(u.w).is_some_and(|e| e <= n)
                && u.y.checked_add(u.h).is_some_and(|e| e <= n);
            if !fits || u.rgba.len() as u64 != u64::from(u.w) * u64::from(u.h) * 4 {
                return Err(ClipmapError::UploadOutside { w: u.w, h: u.h, x: u.x, y: u.y, level: u.level, side: n });
            }
        }
        let mut bytes = 0u64;
        for u in frame.uploads.iter().filter(|u| u.w > 0 && u.h > 0) {
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &self.texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d { x: u.x, y: u.y, z: u.level },
                    aspect: wgpu::TextureAspect::All,
                },
                &u.rgba,
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(u.w * 4), rows_per_image: Some(u.h) },
                wgpu::Extent3d { width: u.w, height: u.h, depth_or_array_layers: 1 },
            );
            bytes += u.rgba.len() as u64;
        }
        let gsd0 = self.uniform.level[0].texel_m / (1u32 << self.uniform.level[0].mip as u32) as f32;
        for (l, p) in self.uniform.level.iter_mut().zip(&frame.placements) {
            l.origin_x = p.origin.x as f32;
            l.origin_y = p.origin.y as f32;
            l.mip = p.mip.min(31) as f32;
            l.texel_m = gsd0 * (2.0f32).powi(p.mip.min(31) as i32);
        }
        queue.write_buffer(&self.uniform_buffer, 0, bytemuck::bytes_of(&self.uniform));
        self.bytes_last = bytes;
        self.bytes_total += bytes;
        Ok(bytes)
    }

    /// The three layout entries of a clipmap from `first` on: the uniform (vertex and fragment),
    /// the texture array and the sampler (fragment).
    pub fn layout_entries(first: u32) -> [wgpu::BindGroupLayoutEntry; 3] {
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        [
            wgpu::BindGroupLayoutEntry {
                binding: first,
                visibility: vf,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: first + 1,
                visibility: vf,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: first + 2,
                visibility: vf,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ]
    }

    /// The three bind group entries matching [`GpuClipmap::layout_entries`] from `first` on.
    pub fn bind_entries(&self, first: u32) -> [wgpu::BindGroupEntry<'_>; 3] {
        [
            wgpu::BindGroupEntry { binding: first, resource: self.uniform_buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: first + 1, resource: wgpu::BindingResource::TextureView(&self.view) },
            wgpu::BindGroupEntry { binding: first + 2, resource: wgpu::BindingResource::Sampler(&self.sampler) },
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uniform_matches_the_wgsl_layout() {
        // 32 bytes of header, then 16 levels of 16 bytes.
        assert_eq!(std::mem::size_of::<ClipmapUniform>(), 32 + 16 * 16);
    }

    #[test]
    fn configurations_are_checked() {
        let limits = wgpu::Limits::downlevel_defaults();
        assert!(check_config(ClipmapConfig { levels: 8, size: 256 }, &limits).is_ok());
        assert!(check_config(ClipmapConfig { levels: 0, size: 256 }, &limits).is_err());
        assert!(check_config(ClipmapConfig { levels: 17, size: 256 }, &limits).is_err());
        assert!(check_config(ClipmapConfig { levels: 8, size: 300 }, &limits).is_err());
        assert!(check_config(ClipmapConfig { levels: 8, size: 8 }, &limits).is_err());
    }
}
