//! The textures of a species: its tileable bark (the pattern of `assetgen::textures::bark`,
//! tinted to the preset's colour) and its leaf image with alpha, each with a height field for the
//! normal and specular maps. Pure functions of the preset: the same bytes on every run.

use glam::Vec3;
use image::{Rgb, RgbImage, Rgba, RgbaImage};

use super::preset::{BarkStyle, LeafShape, Preset};
use crate::assetgen::species::Species;
use crate::assetgen::textures;

/// Bark texture size, texels.
pub const BARK_SIZE: u32 = 128;
/// Leaf texture size, texels.
pub const LEAF_SIZE: u32 = 128;

fn to8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// The bark albedo (tinted to `bark_colour`) and its height field.
pub fn bark(p: &Preset) -> (RgbImage, Vec<f32>) {
    let pattern = match p.bark_style {
        BarkStyle::Ridged => Species::Broadleaf,
        BarkStyle::Plated => Species::Conifer,
        BarkStyle::Birch => Species::Birch,
        BarkStyle::Smooth => Species::Shrub,
    };
    let (img, h) = textures::bark(pattern, BARK_SIZE);
    let n = (BARK_SIZE * BARK_SIZE) as f32;
    let mean =
        img.pixels().fold(Vec3::ZERO, |m, px| m + Vec3::new(px[0] as f32, px[1] as f32, px[2] as f32) / 255.0) / n;
    let gain = Vec3::from(p.bark_colour) / mean.max(Vec3::splat(1e-3));
    let out = RgbImage::from_fn(BARK_SIZE, BARK_SIZE, |x, y| {
        let px = img.get_pixel(x, y);
        let c = Vec3::new(px[0] as f32, px[1] as f32, px[2] as f32) / 255.0 * gain;
        Rgb([to8(c.x), to8(c.y), to8(c.z)])
    });
    (out, h)
}

/// Whether `(u, v)` (u across, v from the tip 0 to the stalk 1) is on the leaf, and its height
/// (midrib and veins raised).
fn leaf_at(shape: LeafShape, u: f32, v: f32) -> Option<f32> {
    let across = (u - 0.5).abs() * 2.0;
    let pi = std::f32::consts::PI;
    match shape {
        LeafShape::Oval | LeafShape::Lobed => {
            if v > 0.9 {
                // The stalk.
                return (across < 0.06).then_some(0.8);
            }
            let t = v / 0.9;
            let mut profile = (pi * t).sin().powf(0.75);
            if shape == LeafShape::Lobed {
                profile *= 0.72 + 0.28 * (t * pi * 7.0).sin().abs();
            }
            if across >= profile * 0.96 {
                return None;
            }
            let mid = (1.0 - across / 0.05).max(0.0);
            let vein = if ((t * 8.0 + across * 2.5).fract() - 0.5).abs() < 0.07 { 0.35 } else { 0.0 };
            Some(0.3 + 0.5 * mid + vein + 0.15 * (1.0 - across / profile.max(1e-3)))
        }
        LeafShape::Needles => {
            if across < 0.045 {
                return Some(0.9);
            }
            let reach = 0.95 * (pi * v.clamp(0.0, 1.0)).sin().powf(0.4);
            if across > reach {
                return None;
            }
            // Needles lean towards the tip in a herringbone.
            let phase = (v + across * 0.35) * 30.0;
            let f = phase.fract();
            (f < 0.3).then(|| 0.4 + 0.5 * (1.0 - (f / 0.15 - 1.0).abs()))
        }
    }
}

/// The leaf albedo with alpha (colour `leaf_colour`) and its height field.
pub fn leaf(p: &Preset) -> (RgbaImage, Vec<f32>) {
    let col = Vec3::from(p.leaf_colour);
    let s = LEAF_SIZE;
    let mut h = vec![0.0f32; (s * s) as usize];
    let img = RgbaImage::from_fn(s, s, |x, y| {
        let (u, v) = ((x as f32 + 0.5) / s as f32, (y as f32 + 0.5) / s as f32);
        match leaf_at(p.leaf_shape, u, v) {
            Some(height) => {
                h[(y * s + x) as usize] = height;
                let c = col * (0.85 + 0.3 * height);
                Rgba([to8(c.x), to8(c.y), to8(c.z), 255])
            }
            // The colour continues under the cut-out so that filtering does not darken the edge.
            None => Rgba([to8(col.x), to8(col.y), to8(col.z), 0]),
        }
    });
    (img, h)
}

/// Normal and specular maps of a height field.
pub fn maps(h: &[f32], size: u32, strength: f32, specular: f32) -> (RgbImage, RgbaImage) {
    (textures::normal_from_height(h, size, strength), textures::specular(h, size, specular, 0.3))
}
