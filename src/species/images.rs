//! The bark texture of a species: tileable (the pattern of `assetgen::textures::bark`, tinted to
//! the preset's colour), with a height field for its normal and specular maps, which `maps` also
//! makes for the leaf atlas (`atlas`). Pure functions of the preset: the same bytes on every run.

use glam::Vec3;
use image::{Rgb, RgbImage, RgbaImage};

use super::preset::{BarkStyle, Preset};
use crate::assetgen::species::Species;
use crate::assetgen::textures;

/// Bark texture size, texels.
pub const BARK_SIZE: u32 = 128;

/// A colour channel in 0..1 as a byte.
pub(super) fn to8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// The bark texture's mean colour: `bark_colour`, or where the bark changes colour with height
/// (`upper_bark_colour`), the larger of the two in each channel, which the wood's vertex colours
/// then darken to each one's colour.
pub fn bark_texture_colour(p: &Preset) -> Vec3 {
    let low = Vec3::from(p.bark_colour);
    p.upper_bark_colour.map_or(low, |up| low.max(Vec3::from(up)))
}

/// The bark albedo (tinted to [`bark_texture_colour`]) and its height field.
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
    let gain = bark_texture_colour(p) / mean.max(Vec3::splat(1e-3));
    let out = RgbImage::from_fn(BARK_SIZE, BARK_SIZE, |x, y| {
        let px = img.get_pixel(x, y);
        let c = Vec3::new(px[0] as f32, px[1] as f32, px[2] as f32) / 255.0 * gain;
        Rgb([to8(c.x), to8(c.y), to8(c.z)])
    });
    (out, h)
}

/// Normal and specular maps of a height field.
pub fn maps(h: &[f32], size: u32, strength: f32, specular: f32) -> (RgbImage, RgbaImage) {
    (textures::normal_from_height(h, size, strength), textures::specular(h, size, specular, 0.3))
}
