//! The gradient noise and the integer hash behind it, shared bit for bit with
//! `src/render/trees/wind.wgsl`, and the per-tree gain built from it.

use glam::{Vec2, Vec3};

use super::{NOISE_SEED, TAU};

/// A 32-bit integer hash with good avalanche (Wellons' "lowbias32"). WGSL: `wind_hash`.
#[inline]
pub fn hash_u32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// The hash of an integer lattice point; it replaces Perlin's permutation table.
/// WGSL: `wind_lattice_hash`.
#[inline]
pub fn lattice_hash(x: i32, y: i32, z: i32) -> u32 {
    hash_u32((x as u32).wrapping_add(hash_u32((y as u32).wrapping_add(hash_u32((z as u32).wrapping_add(NOISE_SEED))))))
}

/// Perlin's improved-noise gradient: the dot product of one of 12 edge directions (chosen by
/// the low 4 bits of `h`) with the offset `(x, y, z)`. WGSL: `wind_grad`.
#[inline]
pub fn grad(h: u32, x: f32, y: f32, z: f32) -> f32 {
    let h = h & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    let a = if h & 1 == 0 { u } else { -u };
    let b = if h & 2 == 0 { v } else { -v };
    a + b
}

/// Perlin's fade curve `6t⁵ − 15t⁴ + 10t³`. WGSL: `wind_fade`.
#[inline]
pub fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

#[inline]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + t * (b - a)
}

/// Classic 3D gradient noise at `p`, roughly in [−1, 1], 0 at every lattice point.
/// WGSL: `wind_perlin3`.
pub fn perlin3(p: Vec3) -> f32 {
    use super::exact::floor;
    let (fx, fy, fz) = (floor(p.x), floor(p.y), floor(p.z));
    let (ix, iy, iz) = (fx as i32, fy as i32, fz as i32);
    let (x, y, z) = (p.x - fx, p.y - fy, p.z - fz);
    let (u, v, w) = (fade(x), fade(y), fade(z));
    let n000 = grad(lattice_hash(ix, iy, iz), x, y, z);
    let n100 = grad(lattice_hash(ix.wrapping_add(1), iy, iz), x - 1.0, y, z);
    let n010 = grad(lattice_hash(ix, iy.wrapping_add(1), iz), x, y - 1.0, z);
    let n110 = grad(lattice_hash(ix.wrapping_add(1), iy.wrapping_add(1), iz), x - 1.0, y - 1.0, z);
    let n001 = grad(lattice_hash(ix, iy, iz.wrapping_add(1)), x, y, z - 1.0);
    let n101 = grad(lattice_hash(ix.wrapping_add(1), iy, iz.wrapping_add(1)), x - 1.0, y, z - 1.0);
    let n011 = grad(lattice_hash(ix, iy.wrapping_add(1), iz.wrapping_add(1)), x, y - 1.0, z - 1.0);
    let n111 =
        grad(lattice_hash(ix.wrapping_add(1), iy.wrapping_add(1), iz.wrapping_add(1)), x - 1.0, y - 1.0, z - 1.0);
    let x00 = lerp(n000, n100, u);
    let x10 = lerp(n010, n110, u);
    let x01 = lerp(n001, n101, u);
    let x11 = lerp(n011, n111, u);
    let y0 = lerp(x00, x10, v);
    let y1 = lerp(x01, x11, v);
    lerp(y0, y1, w)
}

/// Gradient noise mapped to [0, 1]: `clamp(0.5 + 0.5 × perlin3(p), 0, 1)`. WGSL: `wind_noise01`.
pub fn noise01(p: Vec3) -> f32 {
    (0.5 + 0.5 * perlin3(p)).clamp(0.0, 1.0)
}

/// The model's `noise(density · v0, t)`: the noise field at world point `v0`, drifting downwind
/// along `dir` at `speed` metres per second. WGSL: `wind_noise_at`.
pub fn noise_at(v0: Vec3, dir: Vec2, density: f32, speed: f32, t: f32) -> f32 {
    let drift = speed * t;
    let p = Vec3::new(v0.x - dir.x * drift, v0.y, v0.z - dir.y * drift);
    noise01(Vec3::new(density * p.x, density * p.y, density * p.z))
}

/// A sine of `cycles` full turns, with the argument reduced to [−π, π) first so that the GPU's
/// `sin` is used where it is accurate: `sin(2π × (fract(cycles + 0.5) − 0.5))`. WGSL: `wind_wave`.
#[inline]
pub fn wave(cycles: f32) -> f32 {
    let u = cycles + 0.5;
    let f = u - u.floor();
    libm::sinf(TAU * (f - 0.5))
}
