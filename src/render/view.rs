//! Views: a camera's uniforms and bind group (group 0). The frame has two, the head's camera
//! (the main pass) and the sun (the shadow map); the water feature makes two more with
//! [`Views::extra`] (its reflection and refraction cameras).
//!
//! Units: metres, radians; right-handed, +Y up; wgpu clip depth 0..1.

use glam::{Mat4, Quat, Vec3};
use grove_systems::wind_model::WindParams;

use super::gpu::Shared;

/// A camera: a pose and a vertical field of view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The eye, world metres.
    pub position: Vec3,
    /// The orientation; the camera looks along its −Z axis.
    pub rotation: Quat,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

/// The camera's view-projection matrix (wgpu depth 0..1, near 0.05 m, far 600 m).
pub fn camera_matrix(camera: &Camera, aspect: f32) -> Mat4 {
    let view = Mat4::from_rotation_translation(camera.rotation, camera.position).inverse();
    let fov = camera.fov_y.clamp(0.01, 3.1);
    let proj = glam::camera::rh::proj::directx::perspective(fov, aspect.max(1e-3), 0.05, 600.0);
    proj * view
}

/// A camera straight above a rectangle of ground, looking down with an orthographic projection:
/// north (−Z) up and east (+X) right in the image, so world X and Z map linearly to pixels.
/// Set as [`crate::render::RenderOptions::top_view`] (the study report's map of the task area).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TopView {
    /// The western and northern edge of the rectangle, world X and Z, metres.
    pub min: glam::Vec2,
    /// The eastern and southern edge, world X and Z, metres.
    pub max: glam::Vec2,
    /// The height the camera looks down from, metres (everything between it and 200 m below is
    /// drawn).
    pub eye_height: f32,
}

impl TopView {
    /// The perspective camera at the same eye whose field of view covers the rectangle at the
    /// ground: what level of detail, culling and shadow fitting use.
    pub fn camera(&self) -> Camera {
        let c = (self.min + self.max) * 0.5;
        let half = (self.max.y - self.min.y).abs() * 0.5;
        Camera {
            position: Vec3::new(c.x, self.eye_height, c.y),
            rotation: Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2),
            fov_y: 2.0 * (half / self.eye_height.max(1.0)).atan(),
        }
    }

    /// The orthographic view-projection matrix (wgpu depth 0..1).
    pub fn matrix(&self) -> Mat4 {
        let cam = self.camera();
        let view = Mat4::from_rotation_translation(cam.rotation, cam.position).inverse();
        let (hw, hh) = ((self.max.x - self.min.x).abs() * 0.5, (self.max.y - self.min.y).abs() * 0.5);
        glam::camera::rh::proj::directx::orthographic(-hw, hw, -hh, hh, 0.1, 200.0) * view
    }
}

/// The uniforms of one view (matches `Frame` in lighting.wgsl; 16-byte rows, the padding named).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct ViewUniform {
    /// World to clip space of this view.
    pub view_proj: [[f32; 4]; 4],
    /// The inverse of the main camera's `view_proj` (the sky's view rays).
    pub inv_view_proj: [[f32; 4]; 4],
    /// World to the sun's clip space (the shadow map lookups).
    pub light_view_proj: [[f32; 4]; 4],
    /// The main camera's position, metres.
    pub camera_pos: [f32; 3],
    /// Simulated time, seconds, modulo an hour.
    pub time: f32,
    /// Unit vector towards the sun.
    pub sun_dir: [f32; 3],
    /// Padding.
    pub pad0: f32,
    /// Direct sunlight, linear RGB times intensity (zero below the horizon).
    pub sun_color: [f32; 3],
    /// Padding.
    pub pad1: f32,
    /// Ambient tint times strength, linear RGB.
    pub ambient: [f32; 3],
    /// Brightness of the sky, 0..1.
    pub sky: f32,
    /// One shadow-map texel in uv.
    pub shadow_texel: f32,
    /// The normal offset of shadow lookups, metres.
    pub shadow_normal_offset: f32,
    /// The depth bias of shadow lookups, in clip depth.
    pub shadow_depth_bias: f32,
    /// Padding.
    pub pad2: f32,
}

/// One view: its uniform buffer and its group-0 bind group (the uniforms and the wind).
pub(crate) struct View {
    buffer: wgpu::Buffer,
    /// Group 0 of every pipeline drawing from this view.
    pub bind_group: wgpu::BindGroup,
}

impl View {
    /// Writes this view's uniforms.
    pub fn write(&self, queue: &wgpu::Queue, uniform: &ViewUniform) {
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(uniform));
    }
}

/// The frame's views and the wind parameters they share.
pub(crate) struct Views {
    /// The head's camera.
    pub main: View,
    /// The sun.
    pub sun: View,
    wind: wgpu::Buffer,
}

impl Views {
    /// Both views' buffers and bind groups.
    pub fn new(shared: &Shared) -> Views {
        let device = &shared.device;
        let wind = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("wind parameters"),
            size: WindParams::SIZE as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let view = |label: &str| {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: std::mem::size_of::<ViewUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &shared.view_layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: wind.as_entire_binding() },
                ],
            });
            View { buffer, bind_group }
        };
        Views { main: view("main view"), sun: view("sun view"), wind }
    }

    /// One more view sharing the wind parameters (the water's reflection and refraction views);
    /// its owner writes it with [`View::write`].
    pub fn extra(&self, shared: &Shared, label: &str) -> View {
        let buffer = shared.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: std::mem::size_of::<ViewUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &shared.view_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: self.wind.as_entire_binding() },
            ],
        });
        View { buffer, bind_group }
    }

    /// Writes this frame's uniforms: `main` for the camera; the sun's view is the same with the
    /// light's matrix as its `view_proj`.
    pub fn write(&self, queue: &wgpu::Queue, main: &ViewUniform, light_view_proj: [[f32; 4]; 4], wind: &WindParams) {
        queue.write_buffer(&self.main.buffer, 0, bytemuck::bytes_of(main));
        let sun = ViewUniform { view_proj: light_view_proj, ..*main };
        queue.write_buffer(&self.sun.buffer, 0, bytemuck::bytes_of(&sun));
        queue.write_buffer(&self.wind, 0, &wind.to_le_bytes());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use grove_systems::stage::frame_bounds;

    #[test]
    fn framing_keeps_the_box_in_view() {
        let (min, max) = (Vec3::new(-2.0, 0.0, -2.0), Vec3::new(2.0, 8.0, 2.0));
        let (eye, target) = frame_bounds(min, max, 0.8, 4.0 / 3.0);
        // A camera at the eye looking at the target, +Y up: its −Z axis is the view direction.
        let back = (eye - target).normalize();
        let right = Vec3::Y.cross(back).normalize();
        let rotation = Quat::from_mat3(&glam::Mat3::from_cols(right, back.cross(right), back));
        let camera = Camera { position: eye, rotation, fov_y: 0.8 };
        let m = camera_matrix(&camera, 4.0 / 3.0);
        for c in crate::render::lighting::box_corners(min, max) {
            let p = m.project_point3(c);
            assert!(p.x.abs() <= 1.0 && p.y.abs() <= 1.0, "{p:?}");
        }
    }

    #[test]
    fn the_top_view_maps_the_rectangle_onto_the_image_north_up() {
        let top = TopView { min: glam::Vec2::new(-10.0, -20.0), max: glam::Vec2::new(30.0, 0.0), eye_height: 50.0 };
        let m = top.matrix();
        // The north-west corner at the top left, the south-east corner at the bottom right,
        // whatever the height of the ground.
        for y in [0.0, 3.0] {
            let nw = m.project_point3(Vec3::new(-10.0, y, -20.0));
            let se = m.project_point3(Vec3::new(30.0, y, 0.0));
            assert!((nw.x + 1.0).abs() < 1e-5 && (nw.y - 1.0).abs() < 1e-5, "{nw:?}");
            assert!((se.x - 1.0).abs() < 1e-5 && (se.y + 1.0).abs() < 1e-5, "{se:?}");
            assert!((0.0..1.0).contains(&nw.z));
        }
    }

    #[test]
    fn view_uniform_matches_the_wgsl_layout() {
        // lighting.wgsl's `Frame`: three 64-byte matrices, then five 16-byte rows.
        assert_eq!(std::mem::size_of::<ViewUniform>(), 3 * 64 + 5 * 16);
        assert_eq!(std::mem::offset_of!(ViewUniform, time), 3 * 64 + 12);
        assert_eq!(std::mem::offset_of!(ViewUniform, sky), 3 * 64 + 3 * 16 + 12);
        assert_eq!(std::mem::offset_of!(ViewUniform, shadow_texel), 3 * 64 + 4 * 16);
    }
}
