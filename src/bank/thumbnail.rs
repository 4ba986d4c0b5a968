//! A model's thumbnail for the bank, drawn on the CPU so that `grove models add` needs no GPU:
//! an orthographic view from the south (+Z towards −Z), framed from the bounds, with each
//! triangle's albedo texture sampled (alpha-clipped where the material is) times its vertex
//! colours, and lit by one
//! directional light. Deterministic: the same model gives the same PNG bytes.

use glam::{Vec2, Vec3, Vec4};

use crate::models::{ImageData, ModelData};

/// Thumbnail edge, pixels.
pub const SIZE: u32 = 96;

/// Draws the thumbnail as RGBA8 texels (transparent background), `SIZE`×`SIZE`.
pub fn draw(data: &ModelData) -> Vec<u8> {
    let n = SIZE as usize;
    let mut rgba = vec![0u8; n * n * 4];
    let mut depth = vec![f32::NEG_INFINITY; n * n];
    let (lo, hi) = data.bounds;
    let extent = (hi.x - lo.x).max(hi.y - lo.y).max(1e-6) * 1.08;
    let centre = Vec2::new((lo.x + hi.x) * 0.5, (lo.y + hi.y) * 0.5);
    // Model point to pixel coordinates (x right, y down).
    let to_px =
        |p: Vec3| Vec2::new(((p.x - centre.x) / extent + 0.5) * n as f32, (0.5 - (p.y - centre.y) / extent) * n as f32);
    let light = Vec3::new(0.4, 0.8, 0.45).normalize();
    for prim in &data.primitives {
        let mat = data.materials.get(prim.material).cloned().unwrap_or_default();
        let tex = mat.albedo.and_then(|i| data.images.get(i));
        for t in prim.indices.chunks_exact(3) {
            let v = [t[0], t[1], t[2]].map(|i| prim.vertices[i as usize]);
            let p = v.map(|x| Vec3::from(x.position));
            let s = p.map(to_px);
            let area = (s[1] - s[0]).perp_dot(s[2] - s[0]);
            if area.abs() < 1e-9 {
                continue;
            }
            let nrm = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or(Vec3::Z);
            // Both sides lit alike: foliage cards are seen from either side.
            let shade = 0.35 + 0.65 * nrm.dot(light).abs();
            let min = s[0].min(s[1]).min(s[2]).max(Vec2::ZERO);
            let max = s[0].max(s[1]).max(s[2]).min(Vec2::splat(n as f32 - 1.0));
            for y in min.y.floor() as usize..=max.y.ceil().max(0.0) as usize {
                for x in min.x.floor() as usize..=max.x.ceil().max(0.0) as usize {
                    if x >= n || y >= n {
                        continue;
                    }
                    let q = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                    let w0 = (s[2] - s[1]).perp_dot(q - s[1]) / area;
                    let w1 = (s[0] - s[2]).perp_dot(q - s[2]) / area;
                    let w2 = 1.0 - w0 - w1;
                    if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                        continue;
                    }
                    let z = w0 * p[0].z + w1 * p[1].z + w2 * p[2].z;
                    let k = y * n + x;
                    if z <= depth[k] {
                        continue;
                    }
                    let uv = Vec2::from(v[0].uv) * w0 + Vec2::from(v[1].uv) * w1 + Vec2::from(v[2].uv) * w2;
                    let col = v.map(|x| Vec4::from(x.color.map(|c| f32::from(c) / 255.0)));
                    let vertex_colour = col[0] * w0 + col[1] * w1 + col[2] * w2;
                    let c = mat.base_color * vertex_colour * tex.map_or(Vec4::ONE, |img| sample(img, uv));
                    if mat.alpha_cutoff.is_some_and(|cut| c.w < cut) {
                        continue;
                    }
                    depth[k] = z;
                    let lit = (c.truncate() * shade).clamp(Vec3::ZERO, Vec3::ONE);
                    let srgb = lit.to_array().map(|l| (l.powf(1.0 / 2.2) * 255.0).round() as u8);
                    rgba[k * 4..k * 4 + 4].copy_from_slice(&[srgb[0], srgb[1], srgb[2], 255]);
                }
            }
        }
    }
    rgba
}

/// Nearest texel of an sRGB RGBA8 image at `uv` (repeating), in linear colour.
fn sample(img: &ImageData, uv: Vec2) -> Vec4 {
    let (w, h) = (img.width as i64, img.height as i64);
    let x = ((uv.x * w as f32).floor() as i64).rem_euclid(w) as usize;
    let y = ((uv.y * h as f32).floor() as i64).rem_euclid(h) as usize;
    let i = (y * img.width as usize + x) * 4;
    let t = &img.rgba[i..i + 4];
    let lin = |b: u8| (b as f32 / 255.0).powf(2.2);
    Vec4::new(lin(t[0]), lin(t[1]), lin(t[2]), t[3] as f32 / 255.0)
}

/// Encodes the thumbnail as PNG bytes.
pub fn png(data: &ModelData) -> Result<Vec<u8>, super::BankError> {
    let img = image::RgbaImage::from_raw(SIZE, SIZE, draw(data)).ok_or(super::BankError::ThumbnailSize)?;
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).map_err(super::BankError::Thumbnail)?;
    Ok(out.into_inner())
}
