//! The sun's light and the lighting bind group (group 1): the shadow map fitted to the scene,
//! its comparison sampler, the environment cubemap and its irradiance.
//!
//! The sun's direction comes from the `Sun` component (through [`super::extract`]); its colour
//! and intensity from its elevation ([`sun_light`]): warmer and dimmer near the horizon, off
//! below it. Units: metres, degrees where a name ends in `_deg`.

use glam::{Mat4, Vec3};

use super::assets::textures::{self, Environment};
use super::gpu::{Shared, SHADOW_FORMAT};

pub use grove_systems::light::{sun_light, SunLight};

/// The eight corners of the axis-aligned box `min..max`.
pub fn box_corners(min: Vec3, max: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 != 0 { max.x } else { min.x },
            if i & 2 != 0 { max.y } else { min.y },
            if i & 4 != 0 { max.z } else { min.z },
        )
    })
}

/// An orthographic light matrix looking along `-sun_dir` that contains the box `min..max`.
/// Returns the matrix and the width of the box in light space (metres).
pub fn light_matrix(sun_dir: Vec3, min: Vec3, max: Vec3) -> (Mat4, f32) {
    let d = sun_dir.normalize_or(Vec3::Y);
    let centre = (min + max) * 0.5;
    let radius = (max - min).length() * 0.5 + 1.0;
    let up = if d.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    let view = glam::camera::rh::view::look_to_mat4(centre + d * radius * 2.0, -d, up);
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for c in box_corners(min, max) {
        let p = view.transform_point3(c);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let proj = glam::camera::rh::proj::directx::orthographic(lo.x, hi.x, lo.y, hi.y, (-hi.z - 1.0).max(0.01), -lo.z + 1.0);
    (proj * view, (hi.x - lo.x).max(hi.y - lo.y))
}

/// The box the shadow map covers: everything drawn (`scene`, or 10 m around the origin when
/// there is nothing), cut to 80 m around the camera horizontally.
pub fn shadow_bounds(scene: Option<(Vec3, Vec3)>, camera: Vec3) -> (Vec3, Vec3) {
    let (smin, smax) = scene.unwrap_or((Vec3::splat(-10.0), Vec3::splat(10.0)));
    let reach = Vec3::new(80.0, 1000.0, 80.0);
    let (smin, smax) = (smin.max(camera - reach), smax.min(camera + reach));
    (smin.min(smax), smax.max(smin))
}

/// The shadow map's edges allowed, texels.
pub const SHADOW_SIZES: std::ops::RangeInclusive<u32> = 256..=8192;

/// The shadow map and the lighting bind group that samples it.
pub(crate) struct Lighting {
    env: Environment,
    env_sampler: wgpu::Sampler,
    shadow_sampler: wgpu::Sampler,
    /// The shadow map's depth view (the shadow pass's attachment).
    pub shadow_view: wgpu::TextureView,
    /// The shadow map's edge, texels.
    pub shadow_size: u32,
    /// Group 1 of the lit pipelines.
    pub bind_group: wgpu::BindGroup,
}

impl Lighting {
    /// The sky's irradiance cube (group 1, binding 3).
    pub fn irradiance(&self) -> &wgpu::TextureView {
        &self.env.irradiance
    }

    /// The lighting of an environment (six cube faces of `face_size`²) with a shadow map of
    /// `shadow_size`² texels (clamped to [`SHADOW_SIZES`]).
    pub fn new(shared: &Shared, face_size: u32, faces: &[Vec<u8>], shadow_size: u32) -> Lighting {
        let device = &shared.device;
        let env = textures::upload_environment(device, &shared.queue, face_size, faces);
        let env_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("environment sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow comparison sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let shadow_size = shadow_size.clamp(*SHADOW_SIZES.start(), *SHADOW_SIZES.end());
        let shadow_view = shadow_texture(device, shadow_size);
        let bind_group = bind_group(shared, &shadow_view, &shadow_sampler, &env, &env_sampler);
        Lighting { env, env_sampler, shadow_sampler, shadow_view, shadow_size, bind_group }
    }

    /// Makes the shadow map `size`² texels (clamped to [`SHADOW_SIZES`]) if it is not already.
    pub fn set_shadow_size(&mut self, shared: &Shared, size: u32) {
        let size = size.clamp(*SHADOW_SIZES.start(), *SHADOW_SIZES.end());
        if size == self.shadow_size {
            return;
        }
        self.shadow_size = size;
        self.shadow_view = shadow_texture(&shared.device, size);
        self.bind_group = bind_group(shared, &self.shadow_view, &self.shadow_sampler, &self.env, &self.env_sampler);
    }
}

fn shadow_texture(device: &wgpu::Device, size: u32) -> wgpu::TextureView {
    let tex = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("shadow map"),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: SHADOW_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    tex.create_view(&wgpu::TextureViewDescriptor { label: Some("shadow map view"), ..Default::default() })
}

fn bind_group(shared: &Shared, shadow: &wgpu::TextureView, shadow_sampler: &wgpu::Sampler, env: &Environment, env_sampler: &wgpu::Sampler) -> wgpu::BindGroup {
    shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("lighting bind group"),
        layout: &shared.lighting_layout,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(shadow) },
            wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(shadow_sampler) },
            wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&env.env) },
            wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&env.irradiance) },
            wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::Sampler(env_sampler) },
        ],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_matrix_contains_the_box() {
        let (min, max) = (Vec3::new(-50.0, 0.0, -50.0), Vec3::new(50.0, 10.0, 50.0));
        let (m, _) = light_matrix(Vec3::new(0.5, 0.7, -0.3).normalize(), min, max);
        for c in box_corners(min, max) {
            let p = m.project_point3(c);
            assert!(p.x.abs() <= 1.0001 && p.y.abs() <= 1.0001 && (0.0..=1.0).contains(&p.z), "{p:?}");
        }
    }

    #[test]
    fn shadow_bounds_stay_within_80_m_of_the_camera() {
        let scene = Some((Vec3::new(-500.0, 0.0, -500.0), Vec3::new(500.0, 20.0, 500.0)));
        let (lo, hi) = shadow_bounds(scene, Vec3::new(10.0, 1.7, 0.0));
        assert_eq!((lo.x, hi.x), (-70.0, 90.0));
        assert_eq!((lo.z, hi.z), (-80.0, 80.0));
        assert_eq!((lo.y, hi.y), (0.0, 20.0));
    }
}
