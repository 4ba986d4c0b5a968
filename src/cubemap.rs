//! The cube map's layout, shared by the asset generator that writes the sky's faces and the
//! renderer that reads them back: the faces' names and the world direction of a texel.

use glam::Vec3;

/// Names of the cube faces in wgpu's layer order (+X, −X, +Y, −Y, +Z, −Z): face `i` is the
/// file `FACES[i].png`.
pub const FACES: [&str; 6] = ["px", "nx", "py", "ny", "pz", "nz"];

/// The world direction of texel `(x, y)` of cube face `face` (order +X, −X, +Y, −Y, +Z, −Z, as
/// wgpu and Vulkan lay out cube textures).
pub fn cube_dir(face: usize, x: u32, y: u32, size: u32) -> Vec3 {
    let s = 2.0 * (x as f32 + 0.5) / size as f32 - 1.0;
    let t = 2.0 * (y as f32 + 0.5) / size as f32 - 1.0;
    let d = match face {
        0 => Vec3::new(1.0, -t, -s),
        1 => Vec3::new(-1.0, -t, s),
        2 => Vec3::new(s, 1.0, t),
        3 => Vec3::new(s, -1.0, -t),
        4 => Vec3::new(s, -t, 1.0),
        _ => Vec3::new(-s, -t, -1.0),
    };
    d.normalize()
}
