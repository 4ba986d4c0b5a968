//! The grass feature's plain data: the patches as extract copies them, the GPU layouts of a
//! blade and of the uniforms (matching cull.wgsl, blades.wgsl and shells.wgsl), and the two
//! noise textures (strand heights for shells, wind for both kinds).
//!
//! Units: metres, radians; colours linear RGB.

use glam::{Mat4, Vec3, Vec4};
use grove_systems::grass::Blade;
use noise::{NoiseFn, Perlin};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wgpu::util::DeviceExt;

/// The most patches the blade pass colours (the size of `colours` in blades.wgsl, halved).
pub const MAX_PATCHES: usize = 64;

/// The edge of the strand texture, texels; one texel is one strand.
pub const STRAND_TEXELS: u32 = 128;

/// The edge of the wind noise texture, texels; it tiles.
pub const WIND_TEXELS: u32 = 64;

/// One patch as the frame draws it.
#[derive(Clone, Debug)]
pub(crate) struct GrassPatch {
    /// Shells (true) or blades.
    pub shells: bool,
    /// The patch's ground triangles, world metres (shells).
    pub triangles: Vec<[Vec3; 3]>,
    /// The blades (blades).
    pub blades: Vec<Blade>,
    /// The root colour, linear RGB.
    pub root: Vec3,
    /// The tip colour, linear RGB.
    pub tip: Vec3,
    /// The shortest and tallest grass, metres.
    pub height: (f32, f32),
    /// Strands (shells) or blades per square metre.
    pub density: f32,
    /// Shell layers.
    pub layers: u32,
}

/// A blade on the GPU (matches `Blade` in cull.wgsl and blades.wgsl): 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuBlade {
    /// The root, metres.
    pub position: [f32; 3],
    /// Length, metres.
    pub height: f32,
    /// Facing, radians about +Y.
    pub yaw: f32,
    /// Gravity bend at the tip, radians.
    pub bend: f32,
    /// Root width, metres.
    pub width: f32,
    /// Bits 0..7 the patch index, bits 8..31 the variation as a 24-bit fraction.
    pub packed: u32,
}

impl GpuBlade {
    /// A blade of patch `patch` (below [`MAX_PATCHES`]).
    pub fn new(b: &Blade, patch: usize) -> GpuBlade {
        let frac = ((b.variation.clamp(0.0, 1.0) * 16_777_215.0) as u32) << 8;
        GpuBlade {
            position: b.position.to_array(),
            height: b.height,
            yaw: b.yaw,
            bend: b.bend,
            width: b.width,
            packed: frac | (patch as u32 & 255),
        }
    }
}

/// The cull pass's uniforms (matches `Cull` in cull.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct CullParams {
    /// The frustum planes, normal inwards, normalised.
    pub planes: [[f32; 4]; 6],
    /// The camera, metres, and the far distance.
    pub camera: [f32; 4],
    /// The distance within which blades get 7 segments, metres.
    pub lod_near: f32,
    /// The distance within which blades get 3 segments (beyond it, one triangle), metres.
    pub lod_mid: f32,
    /// The number of blades.
    pub count: u32,
    /// Where the far cull pipeline's blocks begin in this frame's list of blocks (blocks.rs).
    pub far_base: u32,
    /// Wind direction (x, z), bend at the tip (radians), time (seconds).
    pub wind: [f32; 4],
    /// Noise scroll speed (m/s), noise scale (per metre), unused, unused.
    pub wind_noise: [f32; 4],
    /// The eye and its push radius, metres.
    pub eye: [f32; 4],
    /// The hit point and its push radius (0: none), metres.
    pub hit: [f32; 4],
    /// World to clip space of the main view, column by column (the far blades' rasteriser).
    pub view_proj: [[f32; 4]; 4],
}

/// The blade draw's uniforms (matches `BladeParams` in blades.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct BladeParams {
    /// Root and tip colour per patch.
    pub colours: [[f32; 4]; 2 * MAX_PATCHES],
    /// The image's width and height (pixels), the view depth the far blades' depth codes span
    /// ([`FAR_DEPTH_RANGE`], metres), unused.
    pub viewport: [f32; 4],
    /// The depth buffer's value at view depth w is `depth[0] + depth[1] / w` (see
    /// [`depth_of_view_depth`]); unused, unused.
    pub depth: [f32; 4],
    /// The unit vector towards the sun, unused.
    pub sun_dir: [f32; 4],
    /// The sun's colour times its intensity, linear RGB, unused.
    pub sun_color: [f32; 4],
    /// The ambient tint times its strength, linear RGB, unused.
    pub ambient: [f32; 4],
}

/// The view depth the far blades' depth codes span, metres: beyond the farthest blade drawn
/// (`FAR_DISTANCE` in src/render/grass/mod.rs, plus a blade's height).
pub const FAR_DEPTH_RANGE: f32 = 64.0;

/// The words of the indirect buffer the cull pass writes: two indexed draws of five words
/// (near, middle), then the number of far blades it rasterised and the box of pixels they
/// cover (smallest x, y, then largest x, y).
pub const ARGS_WORDS: usize = 15;

/// The cull pass's workgroup size and the blades each of its invocations culls
/// (`CULL_WORKGROUP`, `BLADES_PER_INVOCATION` in cull.wgsl).
pub const CULL_WORKGROUP: u32 = 64;
/// See [`CULL_WORKGROUP`].
pub const BLADES_PER_INVOCATION: u32 = 16;

/// The word of the same buffer where the far blades' image begins, one word a pixel
/// (`RASTER_OFFSET` in cull.wgsl).
pub const RASTER_OFFSET: u64 = 16;

/// The constants `(a, b)` for which a point at view depth `w` (metres in front of the camera)
/// has the depth `a + b / w` in wgpu's 0..1 depth range, from a view-projection matrix
/// `view_proj` and the camera's world transform `camera` (rotation and position): the
/// projection's depth row.
pub fn depth_of_view_depth(view_proj: Mat4, camera: Mat4) -> (f32, f32) {
    let proj = view_proj * camera;
    // clip.z = p22 z + p32 and clip.w = −z for a point at view-space z = −w.
    (-proj.z_axis.z, proj.w_axis.z)
}

/// The size of a visible blade's shape, written by the cull pass for the vertex shader
/// (`Shape` in cull.wgsl and blades.wgsl), bytes.
pub const SHAPE_BYTES: u64 = 32;

/// The indices of a blade at the near and middle levels of detail: indexed triangle lists of
/// 13 and 5 triangles (`NEAR_INDICES`, `MID_INDICES` in cull.wgsl). Far blades are rasterised
/// by the cull pass.
pub const LOD_INDICES: [u32; 2] = [39, 15];

/// The segments of a near and of a middle blade; a blade of `s` segments has `2 s + 1`
/// vertices (blades.wgsl, `strip_vertex`).
pub const LOD_SEGMENTS: [u32; 2] = [7, 3];

/// The most near and middle blades a frame draws (`NEAR_CAP`, `MID_CAP` in cull.wgsl); further
/// ones, in the order the blades are listed, drop a level (near ones after the middle list's own
/// blades).
pub const LOD_CAPS: [u32; 2] = [65_536, 262_144];

/// The constants the grass shaders share with this file, as WGSL declarations written ahead of
/// `cull.wgsl` and `blades.wgsl`: the shaders define none of them themselves, so the two sides
/// cannot drift apart.
pub fn shader_constants() -> String {
    let u = |name: &str, v: u64| format!("const {name}: u32 = {v}u;\n");
    [
        u("NEAR_INDICES", LOD_INDICES[0] as u64),
        u("MID_INDICES", LOD_INDICES[1] as u64),
        u("NEAR_CAP", LOD_CAPS[0] as u64),
        u("MID_CAP", LOD_CAPS[1] as u64),
        u("NEAR_SEGMENTS", LOD_SEGMENTS[0] as u64),
        u("MID_SEGMENTS", LOD_SEGMENTS[1] as u64),
        u("NEAR_VERTICES", 2 * LOD_SEGMENTS[0] as u64 + 1),
        u("MID_VERTICES", 2 * LOD_SEGMENTS[1] as u64 + 1),
        u("RASTER_OFFSET", RASTER_OFFSET),
        u("CULL_WORKGROUP", CULL_WORKGROUP as u64),
        u("BLADES_PER_INVOCATION", BLADES_PER_INVOCATION as u64),
    ]
    .concat()
}

/// The index buffer of `blades` blades of `segments` segments: blade `k`'s vertices are
/// `k (2 s + 1) + c`, `c` the left (even) and right (odd) corners of its rows, then its tip;
/// quads between the rows (two triangles each) and the tip triangle.
pub fn blade_indices(segments: u32, blades: u32) -> Vec<u32> {
    let per = 2 * segments + 1;
    let mut one = Vec::with_capacity(3 * (2 * segments as usize - 1));
    for j in 0..segments - 1 {
        let (l, r) = (2 * j, 2 * j + 1);
        one.extend([l, r, l + 2, l + 2, r, r + 2]);
    }
    one.extend([2 * segments - 2, 2 * segments - 1, 2 * segments]);
    (0..blades).flat_map(|k| one.iter().map(move |c| k * per + c)).collect()
}

/// The distances within which blades get 7 and 3 segments (beyond: a line), metres, for an
/// image `height_px` pixels high with a vertical field of view `fov_y` (radians): where one
/// metre covers 156 and 30 pixels, so that a 0.3 m blade is drawn with 7 segments while it is
/// at least 47 pixels tall and as a line once it is under 9 pixels, when a blade 3 cm wide
/// covers less than a pixel (4 m and 21 m at 720 pixels and 60°). Between 4 and 8 m, 3 segments
/// (5 triangles instead of 13) change the park's image by half a level of 255 per channel and
/// save about a tenth of its frame on lavapipe, where triangles are dear.
pub fn lod_distances(height_px: u32, fov_y: f32) -> (f32, f32) {
    let k = pixels_per_metre(height_px, fov_y);
    (k / 156.0, k / 30.0)
}

/// The pixels one metre (across the view) covers at a distance of one metre, in an image
/// `height_px` pixels high with a vertical field of view `fov_y` (radians).
pub fn pixels_per_metre(height_px: u32, fov_y: f32) -> f32 {
    height_px as f32 / (2.0 * (0.5 * fov_y.clamp(0.01, 3.1)).tan())
}

/// One shell patch's uniforms (matches `ShellParams` in shells.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct ShellParams {
    /// Root colour and layer count.
    pub root: [f32; 4],
    /// Tip colour and height, metres.
    pub tip: [f32; 4],
    /// Wind direction (x, z), sway at the tip (metres), time (seconds).
    pub wind: [f32; 4],
    /// Strands per metre, wind noise scale (per metre), wind noise speed (m/s), shortest strand
    /// as a share of the height.
    pub strands: [f32; 4],
}

/// The six frustum planes of a view-projection matrix with wgpu's 0..1 depth (Gribb and
/// Hartmann), normals pointing inwards, normalised.
pub fn frustum_planes(m: Mat4) -> [[f32; 4]; 6] {
    let (r0, r1, r2, r3) = (m.row(0), m.row(1), m.row(2), m.row(3));
    let planes: [Vec4; 6] = [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2];
    planes.map(|p| (p / p.truncate().length().max(1e-12)).to_array())
}

/// The strand heights: a random value per texel (ChaCha8, fixed seed), R8.
pub fn strand_texture(device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::TextureView {
    let mut rng = ChaCha8Rng::seed_from_u64(0x6772_6173_73);
    let data: Vec<u8> = (0..STRAND_TEXELS * STRAND_TEXELS).map(|_| rng.random::<u8>()).collect();
    r8_texture(device, queue, "grass strand heights", STRAND_TEXELS, &data)
}

/// The wind noise: Perlin noise on a torus, so that it tiles, scaled to 0..1, R8.
pub fn wind_texture(device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::TextureView {
    let perlin = Perlin::new(19);
    let n = WIND_TEXELS as f64;
    let mut data = Vec::with_capacity((WIND_TEXELS * WIND_TEXELS) as usize);
    for y in 0..WIND_TEXELS {
        for x in 0..WIND_TEXELS {
            let (a, b) = (x as f64 / n * std::f64::consts::TAU, y as f64 / n * std::f64::consts::TAU);
            let r = 0.9;
            let v = perlin.get([a.cos() * r, a.sin() * r, b.cos() * r, b.sin() * r]);
            data.push(((v * 0.5 + 0.5).clamp(0.0, 1.0) * 255.0).round() as u8);
        }
    }
    r8_texture(device, queue, "grass wind noise", WIND_TEXELS, &data)
}

fn r8_texture(device: &wgpu::Device, queue: &wgpu::Queue, label: &str, size: u32, data: &[u8]) -> wgpu::TextureView {
    let tex = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        data,
    );
    tex.create_view(&wgpu::TextureViewDescriptor { label: Some(label), ..Default::default() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_layouts_match_the_wgsl() {
        // cull.wgsl: six vec4 planes, a vec4, two f32, two u32, four vec4, then a 4 × 4 matrix.
        assert_eq!(std::mem::size_of::<CullParams>(), 6 * 16 + 16 + 16 + 4 * 16 + 64);
        assert_eq!(std::mem::size_of::<GpuBlade>(), 32);
        // The colours, then five vec4.
        assert_eq!(std::mem::size_of::<BladeParams>(), 2 * MAX_PATCHES * 16 + 5 * 16);
        assert_eq!(std::mem::size_of::<ShellParams>(), 64);
    }

    #[test]
    fn frustum_planes_keep_what_the_camera_sees() {
        // A camera at the origin looking down −Z (its view matrix is the identity) with a 90°
        // field of view.
        let proj = glam::camera::rh::proj::directx::perspective(std::f32::consts::FRAC_PI_2, 1.0, 0.1, 100.0);
        let planes = frustum_planes(proj);
        let inside = |p: Vec3| planes.iter().all(|q| Vec3::new(q[0], q[1], q[2]).dot(p) + q[3] >= 0.0);
        assert!(inside(Vec3::new(0.0, 0.0, -10.0)));
        assert!(inside(Vec3::new(9.0, -9.0, -10.0)));
        assert!(!inside(Vec3::new(11.0, 0.0, -10.0)), "right of a 90° view at 10 m");
        assert!(!inside(Vec3::new(0.0, 0.0, 10.0)), "behind the camera");
        assert!(!inside(Vec3::new(0.0, 0.0, -150.0)), "beyond the far plane");
        // Distances are in metres: the left plane x = z runs at 45°, so the point 1 m to its left
        // at a depth of 10 m lies 1/√2 m outside it, along its normal.
        let left = planes[0];
        let d = Vec3::new(left[0], left[1], left[2]).dot(Vec3::new(-11.0, 0.0, -10.0)) + left[3];
        assert!((d + std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-3, "{d}");
    }

    #[test]
    fn levels_of_detail_follow_the_pixels_a_metre_covers() {
        // 720 pixels over a 60° field of view: one metre at distance d covers
        // 720 / (2 tan 30°) / d ≈ 623.5 / d pixels.
        let (near, mid) = lod_distances(720, 60f32.to_radians());
        assert!((near - 623.54 / 156.0).abs() < 0.01 && (mid - 623.54 / 30.0).abs() < 0.01, "{near} {mid}");
        // Half the pixels: half the distances.
        let (near2, mid2) = lod_distances(360, 60f32.to_radians());
        assert!((near2 - near / 2.0).abs() < 1e-4 && (mid2 - mid / 2.0).abs() < 1e-4);
        // A triangle list of s segments: s − 1 quads and the tip, three vertices a triangle.
        assert_eq!(LOD_INDICES, [3 * (2 * 6 + 1), 3 * (2 * 2 + 1)]);
    }

    #[test]
    fn the_shaders_take_the_shared_constants_from_rust_only() {
        let prelude = shader_constants();
        let names: Vec<&str> =
            prelude.lines().map(|l| l.trim_start_matches("const ").split(':').next().unwrap()).collect();
        assert_eq!(names.len(), 11);
        for (file, text) in [
            ("cull.wgsl", include_str!("cull.wgsl")),
            ("blades.wgsl", include_str!("blades.wgsl")),
            ("shapes.wgsl", include_str!("shapes.wgsl")),
        ] {
            for name in &names {
                assert!(!text.contains(&format!("const {name}")), "{file} defines {name} itself");
            }
            // No number stands where a shared constant belongs.
            for literal in ["@workgroup_size(64)", "raster[16u", "% 15u", "% 7u"] {
                assert!(!text.contains(literal), "{file} has `{literal}`");
            }
        }
        // Each constant once, with the value of its Rust twin.
        for line in [
            "const NEAR_INDICES: u32 = 39u;",
            "const MID_INDICES: u32 = 15u;",
            "const NEAR_VERTICES: u32 = 15u;",
            "const MID_VERTICES: u32 = 7u;",
            "const RASTER_OFFSET: u32 = 16u;",
            "const CULL_WORKGROUP: u32 = 64u;",
        ] {
            assert_eq!(prelude.matches(line).count(), 1, "{line}");
        }
        // The names the shaders use are all declared.
        let cull = include_str!("cull.wgsl");
        let blades = include_str!("blades.wgsl");
        for name in [
            "NEAR_INDICES",
            "MID_INDICES",
            "NEAR_CAP",
            "MID_CAP",
            "RASTER_OFFSET",
            "CULL_WORKGROUP",
            "BLADES_PER_INVOCATION",
        ] {
            assert!(cull.contains(name) && names.contains(&name), "{name}");
        }
        for name in ["NEAR_VERTICES", "NEAR_SEGMENTS", "MID_VERTICES", "MID_SEGMENTS", "RASTER_OFFSET"] {
            assert!(blades.contains(name) && names.contains(&name), "{name}");
        }
    }

    #[test]
    fn blade_indices_make_quads_and_a_tip() {
        // Three segments: rows 0, 1, 2 (vertices 0/1, 2/3, 4/5) and the tip 6.
        let one = blade_indices(3, 1);
        assert_eq!(one, vec![0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5, 4, 5, 6]);
        // The second blade's vertices follow the first's seven.
        let two = blade_indices(3, 2);
        assert_eq!(two.len(), 2 * 15);
        assert_eq!(&two[15..], &one.iter().map(|i| i + 7).collect::<Vec<_>>()[..]);
        // Seven segments: 13 triangles over 15 vertices, each used.
        let near = blade_indices(7, 1);
        assert_eq!(near.len() as u32, LOD_INDICES[0]);
        let mut used = near.clone();
        used.sort_unstable();
        used.dedup();
        assert_eq!(used, (0..15).collect::<Vec<u32>>());
    }

    #[test]
    fn the_far_blades_depth_follows_the_projection() {
        // A camera turned and moved away from the origin; a point at view depth w (metres in
        // front of it, off its axis) projected by the full matrix has the depth a + b / w.
        let rotation = glam::Quat::from_euler(glam::EulerRot::YXZ, 0.7, -0.4, 0.1);
        let position = Vec3::new(3.0, 1.7, -2.0);
        let camera = Mat4::from_rotation_translation(rotation, position);
        let proj = glam::camera::rh::proj::directx::perspective(1.0, 16.0 / 9.0, 0.05, 600.0);
        let view_proj = proj * camera.inverse();
        let (a, b) = depth_of_view_depth(view_proj, camera);
        for w in [0.5f32, 3.0, 20.0, 63.0] {
            let p = position + rotation * Vec3::new(0.3 * w, -0.2 * w, -w);
            let clip = view_proj * p.extend(1.0);
            assert!((clip.w - w).abs() < 1e-3 * w, "view depth {w}: clip w {}", clip.w);
            let z = clip.z / clip.w;
            assert!((a + b / w - z).abs() < 1e-5, "view depth {w}: {z} against {}", a + b / w);
        }
        // wgpu's depth: 0 at the near plane (0.05 m), 1 at the far one (600 m).
        assert!((a + b / 0.05).abs() < 1e-4 && (a + b / 600.0 - 1.0).abs() < 1e-4);
    }

    #[test]
    fn a_blade_keeps_its_patch_and_variation() {
        let b =
            Blade { position: Vec3::new(1.0, 2.0, 3.0), height: 0.2, yaw: 1.0, bend: 0.3, width: 0.01, variation: 0.5 };
        let g = GpuBlade::new(&b, 5);
        assert_eq!(g.packed & 255, 5);
        let v = (g.packed >> 8) as f32 / 16_777_216.0;
        assert!((v - 0.5).abs() < 1e-6, "{v}");
    }
}
