//! Texture uploads: 2D textures with CPU-built mip chains, the environment cubemap and the
//! irradiance cubemap computed from it, and neutral 1×1 fallbacks.

use std::path::Path;

use glam::Vec3;
use wgpu::util::DeviceExt;

// The direction of texel (x, y) of cube face `face` (wgpu/Vulkan layout): the mapping the
// generator used to write the faces.
use crate::cubemap::{FACES, cube_dir};
use crate::render::error::RenderError;

/// Builds a box-filtered mip chain of an RGBA8 image; with `srgb`, averaging happens in linear
/// space. Returns the concatenated levels and the level count.
///
/// Written for unoptimised builds too (the tests' renderer builds every model's chains): a byte's
/// linear value comes from a table of the same function, and each source texel's alpha weight is
/// worked out once; the sums are taken in the same order, so the bytes are those of the plain
/// per-channel loop (`tests::the_chain_is_the_plain_loop_s_bytes`).
pub fn mip_chain(width: u32, height: u32, rgba: &[u8], srgb: bool) -> (Vec<u8>, u32) {
    let mut to_lin = [0f32; 256];
    for (i, v) in to_lin.iter_mut().enumerate() {
        let c = i as f32 / 255.0;
        *v = if srgb { srgb_to_linear(c) } else { c };
    }
    let to_u8 = |v: f32| ((if srgb { linear_to_srgb(v) } else { v }).clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    let mut out = rgba.to_vec();
    let mut levels = 1;
    let (mut w, mut h) = (width as usize, height as usize);
    let mut cur: Vec<u8> = rgba.to_vec();
    while w > 1 || h > 1 {
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let mut next = vec![0u8; nw * nh * 4];
        for y in 0..nh {
            let (y0, y1) = (y * 2, if y * 2 + 1 < h { y * 2 + 1 } else { h - 1 });
            for x in 0..nw {
                let (x0, x1) = (x * 2, if x * 2 + 1 < w { x * 2 + 1 } else { w - 1 });
                // The four source texels in the order (0, 0), (1, 0), (0, 1), (1, 1).
                let src = [(y0 * w + x0) * 4, (y0 * w + x1) * 4, (y1 * w + x0) * 4, (y1 * w + x1) * 4];
                // Colours weighted by alpha so transparent texels do not darken edges.
                let mut weight = [0f32; 4];
                for k in 0..4 {
                    weight[k] = cur[src[k] + 3] as f32 / 255.0 + 1e-3;
                }
                let o = (y * nw + x) * 4;
                for c in 0..3 {
                    let mut sum = 0.0;
                    let mut wsum = 0.0;
                    for k in 0..4 {
                        sum += to_lin[cur[src[k] + c] as usize] * weight[k];
                        wsum += weight[k];
                    }
                    next[o + c] = to_u8(sum / wsum);
                }
                let mut alpha = 0.0;
                for i in src {
                    alpha += cur[i + 3] as f32 / 255.0;
                }
                // Keep alpha-tested coverage from fading away in small mips.
                next[o + 3] = ((alpha / 4.0 * 1.15f32).min(1.0) * 255.0 + 0.5) as u8;
            }
        }
        out.extend_from_slice(&next);
        cur = next;
        w = nw;
        h = nh;
        levels += 1;
    }
    (out, levels)
}

/// sRGB transfer function to linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// Linear to the sRGB transfer function.
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

/// Uploads an RGBA8 image with mips as a 2D texture and returns its view.
pub fn upload_2d(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    width: u32,
    height: u32,
    rgba: &[u8],
    srgb: bool,
) -> wgpu::TextureView {
    let format = if srgb { wgpu::TextureFormat::Rgba8UnormSrgb } else { wgpu::TextureFormat::Rgba8Unorm };
    upload_2d_as(device, queue, label, width, height, rgba, srgb, format)
}

/// [`upload_2d`] of an sRGB-encoded image into [`ENCODED_FORMAT`]: its mips averaged in linear
/// light, its bytes kept encoded, for shaders that decode after filtering.
pub fn upload_2d_encoded(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    width: u32,
    height: u32,
    rgba: &[u8],
) -> wgpu::TextureView {
    upload_2d_as(device, queue, label, width, height, rgba, true, ENCODED_FORMAT)
}

/// Uploads `rgba` with mips (averaged in linear light where `srgb`) as a 2D texture of `format`.
#[allow(clippy::too_many_arguments)]
fn upload_2d_as(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    width: u32,
    height: u32,
    rgba: &[u8],
    srgb: bool,
    format: wgpu::TextureFormat,
) -> wgpu::TextureView {
    let (data, levels) = mip_chain(width, height, rgba, srgb);
    upload_chain(device, queue, label, (width, height), (&data, levels), format)
}

/// The texel of a flat tangent-space normal map: the normal (0, 0, 1), full alpha.
pub const FLAT_NORMAL: [u8; 4] = [128, 128, 255, 255];

/// An RGBA8 image: its size in texels and its texels, row by row.
pub type Rgba<'a> = (u32, u32, &'a [u8]);

/// A material's normal map and specular map packed into one image's mip chain: RGB of each
/// level are the normal map's as [`mip_chain`] builds them (linear), A the specular map's alpha
/// as it builds those, so one sample gives what two did, texel for texel. A missing normal map
/// stands as the flat normal (128, 128, 255), a missing specular map as full strength (255); a
/// specular map of another size is resampled (nearest texel) to the normal map's. Returns the
/// size, the concatenated levels and the level count.
pub fn normal_specular_chain(normal: Option<Rgba<'_>>, specular: Option<Rgba<'_>>) -> ((u32, u32), Vec<u8>, u32) {
    let flat = FLAT_NORMAL;
    let white = [255u8; 4];
    let (w, h) = normal.or(specular).map_or((1, 1), |(w, h, _)| (w, h));
    let fill = |c: [u8; 4]| c.repeat((w * h) as usize);
    let normal_rgba = normal.map_or_else(|| fill(flat), |(_, _, t)| t.to_vec());
    let spec_rgba = match specular {
        None => fill(white),
        Some((sw, sh, t)) if (sw, sh) == (w, h) => t.to_vec(),
        Some((sw, sh, t)) => resample_nearest((sw, sh, t), w, h),
    };
    let (mut data, levels) = mip_chain(w, h, &normal_rgba, false);
    let (spec, _) = mip_chain(w, h, &spec_rgba, false);
    for (texel, s) in data.chunks_exact_mut(4).zip(spec.chunks_exact(4)) {
        texel[3] = s[3];
    }
    ((w, h), data, levels)
}

/// `image` resampled to `width` × `height` by the nearest texel.
fn resample_nearest((sw, sh, t): Rgba<'_>, width: u32, height: u32) -> Vec<u8> {
    let mut out = Vec::with_capacity((width * height * 4) as usize);
    for y in 0..height {
        let sy = (u64::from(y) * u64::from(sh) / u64::from(height)) as u32;
        for x in 0..width {
            let sx = (u64::from(x) * u64::from(sw) / u64::from(width)) as u32;
            let i = ((sy * sw + sx) * 4) as usize;
            out.extend_from_slice(&t[i..i + 4]);
        }
    }
    out
}

/// [`normal_specular_chain`] uploaded as a linear 2D texture (`Rgba8Unorm`).
pub fn upload_normal_specular(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    normal: Option<Rgba<'_>>,
    specular: Option<Rgba<'_>>,
) -> wgpu::TextureView {
    let (size, data, levels) = normal_specular_chain(normal, specular);
    upload_chain(device, queue, label, size, (&data, levels), wgpu::TextureFormat::Rgba8Unorm)
}

/// Uploads a mip chain (`levels` levels concatenated, from `size` down) as a 2D texture of
/// `format`.
fn upload_chain(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    (width, height): (u32, u32),
    (data, levels): (&[u8], u32),
    format: wgpu::TextureFormat,
) -> wgpu::TextureView {
    let tex = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        data,
    );
    tex.create_view(&wgpu::TextureViewDescriptor { label: Some(label), ..Default::default() })
}

/// A 1×1 texture of one colour.
pub fn solid(device: &wgpu::Device, queue: &wgpu::Queue, label: &str, rgba: [u8; 4], srgb: bool) -> wgpu::TextureView {
    upload_2d(device, queue, label, 1, 1, &rgba, srgb)
}

/// The environment: a sky cubemap and its irradiance (diffuse) convolution, both as cube views.
pub struct Environment {
    /// The sky, with mips (for rough reflections): sRGB-encoded bytes in a linear format
    /// ([`ENCODED_FORMAT`]), so shaders decode what they sample (`srgb_decode` in
    /// lighting.wgsl).
    pub env: wgpu::TextureView,
    /// The cosine-weighted irradiance, 8×8 per face, linear RGB in half floats.
    pub irradiance: wgpu::TextureView,
}

/// The format of textures that hold sRGB-encoded bytes which the shaders decode themselves,
/// after filtering: a software rasteriser filters these several times faster than
/// `Rgba8UnormSrgb` texels, which it decodes one by one before filtering. Filtering the encoded
/// values rather than linear ones darkens mixed texels slightly; for smooth images (the sky, the
/// ground's noise) it does not show.
pub const ENCODED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Reads and decodes an image file (the format from its content) through
/// `grove_systems::files`: a regular file within the image size limit. The error is one line
/// naming the file.
pub fn read_image(path: &Path) -> Result<image::DynamicImage, RenderError> {
    let bytes = grove_systems::files::read(path, grove_systems::files::Kind::Image).map_err(RenderError::File)?;
    image::load_from_memory(&bytes).map_err(|error| RenderError::Image { path: path.to_path_buf(), error })
}

/// Loads the 6 faces `px.png` … `nz.png` from `dir`. The error names the file.
pub fn load_faces(dir: &Path) -> Result<(u32, Vec<Vec<u8>>), RenderError> {
    let mut size = 0;
    let mut faces = Vec::new();
    for f in FACES {
        let p = dir.join(format!("{f}.png"));
        let img = read_image(&p)?.to_rgba8();
        if img.width() != img.height() || (size != 0 && img.width() != size) {
            return Err(RenderError::CubeFaces(p));
        }
        size = img.width();
        faces.push(img.into_raw());
    }
    Ok((size, faces))
}

pub use crate::render::error::one_line_image_error;

/// The cosine-weighted irradiance of a cubemap (linear RGB), for `out` texels per face edge,
/// sampling the input at up to 16 texels per face edge.
pub fn irradiance(size: u32, faces: &[Vec<u8>], out: u32) -> Vec<Vec<[f32; 3]>> {
    let step = (size / 16).max(1);
    let mut samples = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        let mut y = 0;
        while y < size {
            let mut x = 0;
            while x < size {
                let d = cube_dir(f, x, y, size);
                let s = 2.0 * (x as f32 + 0.5) / size as f32 - 1.0;
                let t = 2.0 * (y as f32 + 0.5) / size as f32 - 1.0;
                let solid = 1.0 / (1.0 + s * s + t * t).powf(1.5);
                let i = ((y * size + x) * 4) as usize;
                let c = Vec3::new(
                    srgb_to_linear(face[i] as f32 / 255.0),
                    srgb_to_linear(face[i + 1] as f32 / 255.0),
                    srgb_to_linear(face[i + 2] as f32 / 255.0),
                );
                samples.push((d, c * solid, solid));
                x += step;
            }
            y += step;
        }
    }
    (0..6)
        .map(|f| {
            (0..out * out)
                .map(|k| {
                    let n = cube_dir(f, k % out, k / out, out);
                    let (mut sum, mut w) = (Vec3::ZERO, 0.0);
                    for (d, c, solid) in &samples {
                        let cos = n.dot(*d).max(0.0);
                        sum += *c * cos;
                        w += solid * cos;
                    }
                    (sum / w.max(1e-6)).to_array()
                })
                .collect()
        })
        .collect()
}

/// Uploads the environment cubemap and its irradiance.
pub fn upload_environment(device: &wgpu::Device, queue: &wgpu::Queue, size: u32, faces: &[Vec<u8>]) -> Environment {
    // Layer-major data: each face with its mips.
    let mut data = Vec::new();
    let mut levels = 1;
    for f in faces {
        let (d, l) = mip_chain(size, size, f, true);
        data.extend_from_slice(&d);
        levels = l;
    }
    let cube = |label: &str, size: u32, levels: u32, format: wgpu::TextureFormat, data: &[u8]| {
        let tex = device.create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 6 },
                mip_level_count: levels,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            data,
        );
        tex.create_view(&wgpu::TextureViewDescriptor {
            label: Some(label),
            dimension: Some(wgpu::TextureViewDimension::Cube),
            ..Default::default()
        })
    };
    let env = cube("environment cubemap", size, levels, ENCODED_FORMAT, &data);
    const IRR: u32 = 8;
    let irr = irradiance(size, faces, IRR);
    // Linear half floats: no decoding per texel, and finer than 8 bits in the dark.
    let mut irr_data = Vec::new();
    for face in &irr {
        for c in face {
            for v in [c[0], c[1], c[2], 1.0] {
                irr_data.extend_from_slice(&half::f16::from_f32(v).to_le_bytes());
            }
        }
    }
    let irradiance = cube("irradiance cubemap", IRR, 1, wgpu::TextureFormat::Rgba16Float, &irr_data);
    Environment { env, irradiance }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chain as a plain per-channel loop over the four source texels: what [`mip_chain`]
    /// computes, written the obvious way.
    fn plain_chain(width: u32, height: u32, rgba: &[u8], srgb: bool) -> Vec<u8> {
        let to_lin = |c: u8| if srgb { srgb_to_linear(c as f32 / 255.0) } else { c as f32 / 255.0 };
        let to_u8 = |v: f32| ((if srgb { linear_to_srgb(v) } else { v }).clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
        let (mut out, mut cur, mut w, mut h) = (rgba.to_vec(), rgba.to_vec(), width, height);
        while w > 1 || h > 1 {
            let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
            let mut next = vec![0u8; (nw * nh * 4) as usize];
            for y in 0..nh {
                for x in 0..nw {
                    for c in 0..4 {
                        let (mut sum, mut wsum) = (0.0, 0.0);
                        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                            let i = (((y * 2 + dy).min(h - 1) * w + (x * 2 + dx).min(w - 1)) * 4) as usize;
                            if c == 3 {
                                sum += cur[i + 3] as f32 / 255.0;
                            } else {
                                let a = cur[i + 3] as f32 / 255.0 + 1e-3;
                                sum += to_lin(cur[i + c as usize]) * a;
                                wsum += a;
                            }
                        }
                        next[((y * nw + x) * 4 + c) as usize] =
                            if c == 3 { ((sum / 4.0 * 1.15).min(1.0) * 255.0 + 0.5) as u8 } else { to_u8(sum / wsum) };
                    }
                }
            }
            out.extend_from_slice(&next);
            (cur, w, h) = (next, nw, nh);
        }
        out
    }

    #[test]
    fn the_chain_is_the_plain_loop_s_bytes() {
        // Odd and even sizes, a strip, every byte value, alpha from 0 to 255.
        for (w, h) in [(37, 23), (64, 64), (1, 9), (16, 3)] {
            let rgba: Vec<u8> = (0..w * h * 4).map(|i| ((i * 97 + i / 7 * 31) % 256) as u8).collect();
            for srgb in [false, true] {
                let (chain, levels) = mip_chain(w, h, &rgba, srgb);
                assert_eq!(chain, plain_chain(w, h, &rgba, srgb), "{w} x {h}, srgb {srgb}");
                assert_eq!(levels, 32 - w.max(h).leading_zeros(), "{w} x {h}");
            }
        }
    }

    /// The coefficients of the cubic in srgb.wgsl's `srgb_decode`, read from the shader's text
    /// so that the test checks what the GPU runs.
    fn shader_cubic() -> [f32; 3] {
        let src = include_str!("../srgb.wgsl");
        let body = src.split("fn srgb_decode").nth(1).expect("srgb_decode in srgb.wgsl");
        let line = body.lines().find(|l| l.contains("return")).expect("a return line");
        let nums: Vec<f32> = line
            .split(|c: char| !(c.is_ascii_digit() || c == '.'))
            .filter(|t| t.contains('.'))
            .map(|t| t.parse().expect("a number"))
            .collect();
        assert_eq!(nums.len(), 3, "three coefficients in {line:?}");
        [nums[0], nums[1], nums[2]]
    }

    /// The packed normal and specular chain holds, level by level, the normal map's RGB and the
    /// specular map's alpha exactly as their own chains would, even where the normal map's alpha
    /// varies (its colours are averaged weighted by it) and the specular map's alpha is boosted
    /// in small mips; missing maps stand as the flat normal and full strength.
    #[test]
    fn the_normal_specular_chain_packs_both_chains_texel_for_texel() {
        let (w, h) = (8u32, 4u32);
        let texels = |seed: u32| -> Vec<u8> { (0..w * h * 4).map(|i| ((i * 37 + seed * 101) % 251) as u8).collect() };
        let (normal, spec) = (texels(1), texels(2));
        let ((pw, ph), packed, levels) = normal_specular_chain(Some((w, h, &normal)), Some((w, h, &spec)));
        let (n_chain, n_levels) = mip_chain(w, h, &normal, false);
        let (s_chain, _) = mip_chain(w, h, &spec, false);
        assert_eq!(((pw, ph), levels), ((w, h), n_levels));
        assert_eq!(packed.len(), n_chain.len());
        for (i, ((p, n), s)) in
            packed.chunks_exact(4).zip(n_chain.chunks_exact(4)).zip(s_chain.chunks_exact(4)).enumerate()
        {
            assert_eq!(p, [n[0], n[1], n[2], s[3]], "texel {i} of the chain");
        }
        let (_, no_spec, _) = normal_specular_chain(Some((w, h, &normal)), None);
        assert!(no_spec.chunks_exact(4).all(|t| t[3] == 255), "a missing specular map is full strength");
        let (size, no_normal, _) = normal_specular_chain(None, Some((w, h, &spec)));
        assert_eq!(size, (w, h));
        assert!(no_normal.chunks_exact(4).all(|t| t[..3] == [128, 128, 255]), "a missing normal map is flat");
        assert_eq!(normal_specular_chain(None, None).1, vec![128, 128, 255, 255]);
    }

    /// A specular map of another size is resampled to the normal map's by the nearest texel:
    /// a 2 × 1 map over a 4 × 2 normal map covers the left and right halves.
    #[test]
    fn a_specular_map_of_another_size_is_resampled_to_the_normal_maps() {
        let normal = [200u8; 4 * 2 * 4];
        let spec = [0, 0, 0, 10, 0, 0, 0, 250];
        let (_, packed, _) = normal_specular_chain(Some((4, 2, &normal)), Some((2, 1, &spec)));
        let alphas: Vec<u8> = packed[..4 * 2 * 4].chunks_exact(4).map(|t| t[3]).collect();
        assert_eq!(alphas, [10, 10, 250, 250, 10, 10, 250, 250]);
    }

    /// Every byte value decoded by the shader's cubic and encoded again by the exact sRGB curve
    /// comes back within 1.4 of 255, as srgb.wgsl states; the cubic maps 0 to 0 and 1 to 1.
    #[test]
    fn the_shader_decode_round_trips_every_byte_within_its_stated_error() {
        let [a, b, c] = shader_cubic();
        let decode = |x: f32| x * (x * (x * a + b) + c);
        assert!((decode(1.0) - 1.0).abs() < 1e-6, "decode(1) = {}", decode(1.0));
        assert_eq!(decode(0.0), 0.0);
        for byte in 0..=255u8 {
            let x = f32::from(byte) / 255.0;
            let back = linear_to_srgb(decode(x).max(0.0)) * 255.0;
            assert!((back - f32::from(byte)).abs() <= 1.4, "byte {byte} comes back as {back}");
            // And it stays close to the exact decode in linear light.
            assert!((decode(x) - srgb_to_linear(x)).abs() < 0.01, "byte {byte}");
        }
    }
}
