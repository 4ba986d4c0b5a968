//! Procedural textures: bark, leaves, leaf-cluster cards, normal and specular maps, the ground
//! and the sky cubemap. Every function is a pure function of its arguments (seeded noise), so the
//! PNG bytes are the same on every run.

use glam::{Vec2, Vec3};
use image::{Rgb, RgbImage, Rgba, RgbaImage};
use noise::{NoiseFn, Perlin};

use super::geometry::Rng;
use super::species::Species;
use crate::cubemap::cube_dir;

/// Fractal noise in about [−1, 1].
fn fbm(p: &Perlin, x: f64, y: f64, octaves: u32) -> f64 {
    let (mut sum, mut amp, mut freq, mut norm) = (0.0, 1.0, 1.0, 0.0);
    for _ in 0..octaves {
        sum += amp * p.get([x * freq, y * freq]);
        norm += amp;
        amp *= 0.5;
        freq *= 2.0;
    }
    sum / norm
}

/// Tileable fractal noise over the unit square, by sampling on a torus.
fn tile_fbm(p: &Perlin, u: f64, v: f64, fu: f64, fv: f64, octaves: u32) -> f64 {
    use std::f64::consts::TAU;
    let (a, b) = (u * TAU, v * TAU);
    let (ru, rv) = (fu / TAU, fv / TAU);
    let (mut sum, mut amp, mut freq, mut norm) = (0.0, 1.0, 1.0, 0.0);
    for _ in 0..octaves {
        sum += amp * p.get([a.cos() * ru * freq, a.sin() * ru * freq, b.cos() * rv * freq, b.sin() * rv * freq]);
        norm += amp;
        amp *= 0.5;
        freq *= 2.0;
    }
    sum / norm
}

fn to8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

fn rgb(c: Vec3) -> Rgb<u8> {
    Rgb([to8(c.x), to8(c.y), to8(c.z)])
}

/// A tangent-space normal map from a height field (tileable, central differences).
pub fn normal_from_height(h: &[f32], size: u32, strength: f32) -> RgbImage {
    let at = |x: i64, y: i64| h[(y.rem_euclid(size as i64) * size as i64 + x.rem_euclid(size as i64)) as usize];
    RgbImage::from_fn(size, size, |x, y| {
        let (x, y) = (x as i64, y as i64);
        let dx = (at(x + 1, y) - at(x - 1, y)) * strength;
        // Image rows grow downwards while the bitangent points to decreasing v, so +y is up.
        let dy = (at(x, y - 1) - at(x, y + 1)) * strength;
        let n = Vec3::new(-dx, -dy, 1.0).normalize();
        rgb(n * 0.5 + Vec3::splat(0.5))
    })
}

/// Bark albedo and height for a species (tileable).
pub fn bark(species: Species, size: u32) -> (RgbImage, Vec<f32>) {
    let p = Perlin::new(11 + species as u32);
    let mut h = vec![0.0f32; (size * size) as usize];
    let img = RgbImage::from_fn(size, size, |x, y| {
        let (u, v) = (x as f64 / size as f64, y as f64 / size as f64);
        let (col, height) = match species {
            Species::Birch => {
                // White bark with dark horizontal lenticels.
                let n = tile_fbm(&p, u, v, 3.0, 3.0, 3) as f32;
                let len = tile_fbm(&p, u * 1.0 + 0.3, v, 2.0, 24.0, 2) as f32;
                let dark = ((len - 0.35) * 6.0).clamp(0.0, 1.0);
                let base = Vec3::new(0.86, 0.84, 0.78) * (0.92 + 0.08 * n);
                (base.lerp(Vec3::new(0.12, 0.11, 0.1), dark), 0.5 + 0.2 * n - 0.4 * dark)
            }
            _ => {
                // Vertical ridges: noise stretched along v.
                let ridges = tile_fbm(&p, u, v, 10.0, 1.5, 4) as f32;
                let fine = tile_fbm(&p, u + 0.5, v + 0.5, 20.0, 20.0, 2) as f32;
                let r = (ridges * 2.5).abs().min(1.0);
                let base = match species {
                    Species::Broadleaf => Vec3::new(0.33, 0.25, 0.19),
                    Species::Conifer => Vec3::new(0.38, 0.22, 0.15),
                    _ => Vec3::new(0.35, 0.31, 0.26),
                };
                (base * (0.6 + 0.5 * r + 0.1 * fine), r + 0.2 * fine)
            }
        };
        h[(y * size + x) as usize] = height;
        rgb(col)
    });
    (img, h)
}

/// The leaf colour of a species.
fn leaf_colour(species: Species) -> Vec3 {
    match species {
        Species::Broadleaf => Vec3::new(0.2, 0.36, 0.1),
        Species::Conifer => Vec3::new(0.1, 0.25, 0.12),
        Species::Birch => Vec3::new(0.36, 0.5, 0.16),
        Species::Shrub => Vec3::new(0.24, 0.4, 0.14),
    }
}

/// A single leaf for mesh foliage: u across (0..1), v from the tip (0) to the stem (1). Returns
/// the albedo with alpha and a height field (midrib and veins).
pub fn leaf(species: Species, size: u32) -> (RgbaImage, Vec<f32>) {
    let p = Perlin::new(21 + species as u32);
    let col = leaf_colour(species);
    let mut h = vec![0.0f32; (size * size) as usize];
    let img = RgbaImage::from_fn(size, size, |x, y| {
        let (u, v) = ((x as f32 + 0.5) / size as f32, (y as f32 + 0.5) / size as f32);
        let across = (u - 0.5).abs() * 2.0;
        let (inside, vein) = if species == Species::Conifer {
            (across < 0.8, 0.0)
        } else {
            // Leaf outline: a pointed ellipse between tip and stem.
            let profile = (std::f32::consts::PI * v).sin().powf(0.8);
            let vein = ((v * 9.0 + across * 3.0).fract() - 0.5).abs() < 0.06;
            (across < profile * 0.98, if vein { 0.5 } else { 0.0 })
        };
        let mid = (1.0 - across / 0.06).max(0.0);
        let n = fbm(&p, u as f64 * 8.0, v as f64 * 8.0, 3) as f32;
        let c = col * (0.9 + 0.15 * n + 0.12 * (1.0 - across)) + Vec3::splat(0.12 * mid.max(vein * 0.4));
        h[(y * size + x) as usize] = 0.6 * mid + 0.25 * vein + 0.1 * (1.0 - across);
        Rgba([to8(c.x), to8(c.y), to8(c.z), if inside { 255 } else { 0 }])
    });
    (img, h)
}

/// A leaf-cluster card: many small leaves (or needle sprays) on a transparent background, with a
/// height field whose slopes give each leaf its own tilt in the normal map.
pub fn card(species: Species, size: u32) -> (RgbaImage, Vec<f32>) {
    let mut rng = Rng::new(31 + species as u64);
    let col = leaf_colour(species);
    let mut img = RgbaImage::from_pixel(
        size,
        size,
        Rgba([(col.x * 255.0) as u8, (col.y * 255.0) as u8, (col.z * 255.0) as u8, 0]),
    );
    let mut h = vec![0.0f32; (size * size) as usize];
    let s = size as f32;
    let stamp = |img: &mut RgbaImage, h: &mut [f32], c: Vec2, dir: Vec2, len: f32, wid: f32, shade: f32, tilt: Vec2| {
        let side = Vec2::new(-dir.y, dir.x);
        let r = len.max(wid) * s;
        let (x0, x1) = (((c.x * s - r).floor().max(0.0)) as u32, ((c.x * s + r).ceil().min(s - 1.0)) as u32);
        let (y0, y1) = (((c.y * s - r).floor().max(0.0)) as u32, ((c.y * s + r).ceil().min(s - 1.0)) as u32);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let q = Vec2::new((x as f32 + 0.5) / s, (y as f32 + 0.5) / s) - c;
                let a = q.dot(dir) / len;
                let b = q.dot(side) / wid;
                if !(0.0..=1.0).contains(&a) {
                    continue;
                }
                let profile = (std::f32::consts::PI * a).sin().powf(0.7) * 0.5;
                if b.abs() < profile {
                    let k = (y * size + x) as usize;
                    let c = col * shade * (0.85 + 0.3 * (1.0 - b.abs() / profile.max(1e-3)) * 0.5);
                    img.put_pixel(x, y, Rgba([to8(c.x), to8(c.y), to8(c.z), 255]));
                    h[k] = 0.5 + tilt.dot(q) * 8.0 + 0.2 * (1.0 - (b / profile).abs());
                }
            }
        }
    };
    let centre = Vec2::splat(0.5);
    match species {
        Species::Conifer => {
            // Needle sprays: a twig along the card's vertical axis with needles on both sides.
            for t in 0..9 {
                let base = Vec2::new(0.5 + rng.range(-0.15, 0.15), 0.95 - 0.1 * t as f32);
                for k in 0..26 {
                    let along = Vec2::new(rng.range(-1.0, 1.0), -rng.range(0.2, 1.0)).normalize();
                    let c = base + Vec2::new(rng.range(-0.25, 0.25), -rng.range(0.0, 0.1));
                    let shade = rng.range(0.7, 1.15);
                    let tilt = Vec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 0.5;
                    if c.distance(centre) < 0.46 {
                        stamp(&mut img, &mut h, c, along, 0.09 + 0.02 * (k % 3) as f32, 0.02, shade, tilt);
                    }
                }
            }
        }
        _ => {
            let (count, len) = match species {
                Species::Broadleaf => (260, 0.09),
                Species::Birch => (200, 0.065),
                _ => (320, 0.06),
            };
            for _ in 0..count {
                // Leaves fill a disc, denser towards the middle.
                let r = 0.42 * rng.f().sqrt();
                let a = rng.range(0.0, std::f32::consts::TAU);
                let c = centre + Vec2::new(a.cos(), a.sin()) * r;
                let dir = Vec2::new(rng.range(-1.0, 1.0), rng.range(-0.2, 1.0)).normalize_or(Vec2::Y);
                let shade = rng.range(0.7, 1.2) * (1.05 - 0.4 * r);
                let tilt = Vec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 0.5;
                stamp(&mut img, &mut h, c, dir, len * rng.range(0.8, 1.2), len * 0.6, shade, tilt);
            }
        }
    }
    (img, h)
}

/// A specular map for `KHR_materials_specular`: RGB white (the specular colour texture is not
/// used), A the specular strength from `base` with some variation from a height field.
pub fn specular(h: &[f32], size: u32, base: f32, vary: f32) -> RgbaImage {
    RgbaImage::from_fn(size, size, |x, y| {
        let k = h[(y * size + x) as usize];
        Rgba([255, 255, 255, to8(base + vary * (k - 0.5))])
    })
}

/// The ground: grass with patches of soil (tileable).
pub fn ground(size: u32) -> RgbImage {
    let p = Perlin::new(41);
    RgbImage::from_fn(size, size, |x, y| {
        let (u, v) = (x as f64 / size as f64, y as f64 / size as f64);
        let patch = tile_fbm(&p, u, v, 3.0, 3.0, 4) as f32;
        let blade = tile_fbm(&p, u + 0.3, v + 0.7, 48.0, 48.0, 2) as f32;
        let grass = Vec3::new(0.24, 0.36, 0.12) * (0.85 + 0.35 * blade);
        let soil = Vec3::new(0.36, 0.29, 0.2) * (0.9 + 0.2 * blade);
        rgb(grass.lerp(soil, ((patch - 0.15) * 4.0).clamp(0.0, 1.0)))
    })
}

/// The sky colour in direction `d` (unit, +Y up): a clear-sky gradient from a pale horizon to a
/// deeper zenith, and a darker ground colour below the horizon.
pub fn sky_colour(d: Vec3) -> Vec3 {
    let y = d.y;
    if y >= 0.0 {
        let horizon = Vec3::new(0.78, 0.85, 0.93);
        let zenith = Vec3::new(0.28, 0.48, 0.82);
        let t = y.powf(0.5);
        horizon.lerp(zenith, t)
    } else {
        let horizon = Vec3::new(0.55, 0.56, 0.52);
        let ground = Vec3::new(0.2, 0.2, 0.16);
        horizon.lerp(ground, (-y).powf(0.4))
    }
}

/// One face of the sky cubemap, with a little noise as high cloud.
pub fn sky_face(face: usize, size: u32) -> RgbImage {
    let p = Perlin::new(51);
    RgbImage::from_fn(size, size, |x, y| {
        let d = cube_dir(face, x, y, size);
        let mut c = sky_colour(d);
        if d.y > 0.05 {
            // Thin clouds, projected onto a plane above the viewer.
            let q = Vec2::new(d.x, d.z) / d.y;
            let n = fbm(&p, q.x as f64 * 0.8, q.y as f64 * 0.8, 4) as f32;
            let cloud = ((n - 0.1) * 2.5).clamp(0.0, 1.0) * (d.y * 4.0).min(1.0);
            c = c.lerp(Vec3::splat(0.95), cloud * 0.6);
        }
        rgb(c)
    })
}
