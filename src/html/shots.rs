//! The report's pictures, rendered headless by the renderer (lavapipe where there is no GPU) and
//! embedded as JPEG data URIs: the filmstrip's head-camera frames and the task area from above.

use crate::render::offscreen::{self, Gpu};
use crate::render::{RenderOptions, Renderer, TopView};
use base64::Engine as _;
use grove_systems::Sim;

use super::HtmlError;
use image::RgbaImage;

/// The size of a filmstrip frame, pixels.
pub const FRAME_SIZE: (u32, u32) = (320, 180);
/// The width of the task area's picture, pixels (its height follows the area's shape).
pub const TOP_WIDTH: u32 = 960;

/// A GPU device and the renderers of the report's two kinds of picture, made on first use.
pub struct Shots {
    gpu: Gpu,
    film: Option<Renderer>,
    top: Option<(Renderer, (u32, u32))>,
    /// Frames rendered so far.
    pub frames: usize,
}

/// An image as a `data:image/jpeg;base64,…` URI.
pub fn jpeg_uri(img: &RgbaImage, quality: u8) -> Result<String, HtmlError> {
    let rgb = image::DynamicImage::ImageRgba8(img.clone()).to_rgb8();
    let mut bytes = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, quality)
        .encode_image(&rgb)
        .map_err(HtmlError::Jpeg)?;
    Ok(format!("data:image/jpeg;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bytes)))
}

/// A renderer of `size` with the shipped models and the bank models `sim`'s catalogue holds
/// (found in the session's banks, as the replay found them).
fn renderer(gpu: &Gpu, sim: &Sim, size: (u32, u32)) -> Result<Renderer, HtmlError> {
    let mut r = Renderer::new(&gpu.device, &gpu.queue, offscreen::FORMAT, size.0, size.1)?;
    let banks = crate::bank::open_session(&[])?;
    crate::bank::load_into(&mut r, &crate::bank::files_for(&banks, sim.catalogue()))?;
    Ok(r)
}

impl Shots {
    /// Opens the GPU device (one line when there is none).
    pub fn new() -> Result<Shots, HtmlError> {
        Ok(Shots { gpu: Gpu::new()?, film: None, top: None, frames: 0 })
    }

    /// The head camera's view of `sim`, with the interaction visuals (ray, hit marker, targets).
    pub fn frame(&mut self, sim: &Sim) -> Result<String, HtmlError> {
        if self.film.is_none() {
            let mut r = renderer(&self.gpu, sim, FRAME_SIZE)?;
            r.options = RenderOptions { shadow_size: 512, overlay: true, ..Default::default() };
            self.film = Some(r);
        }
        let r = self.film.as_mut().ok_or(HtmlError::NoRenderer)?;
        let img = offscreen::render_image(&self.gpu, r, sim)?;
        self.frames += 1;
        jpeg_uri(&img, 70)
    }

    /// The head camera's frame ([`Shots::frame`]) and `sim` from straight above over `view`'s
    /// rectangle (which should have the frame's shape), both [`FRAME_SIZE`], drawn by the one
    /// renderer (a scenario trace's pair of frames).
    pub fn frame_pair(&mut self, sim: &Sim, view: TopView) -> Result<(String, String), HtmlError> {
        let head = self.frame(sim)?;
        let r = self.film.as_mut().ok_or(HtmlError::NoRenderer)?;
        let top = top_options(view, r.options.clone());
        let film = std::mem::replace(&mut r.options, top);
        let img = offscreen::render_image(&self.gpu, r, sim);
        r.options = film;
        Ok((head, jpeg_uri(&img?, 70)?))
    }

    /// `sim`'s ground from straight above over `view`'s rectangle, without the interaction
    /// visuals (the report draws its own over it), `TOP_WIDTH` pixels wide.
    pub fn top(&mut self, sim: &Sim, view: TopView) -> Result<String, HtmlError> {
        let (w, h) = (view.max.x - view.min.x, view.max.y - view.min.y);
        let size = (TOP_WIDTH, ((TOP_WIDTH as f32 * h / w.max(1e-3)).round() as u32).clamp(64, 2 * TOP_WIDTH));
        if self.top.as_ref().is_none_or(|(_, s)| *s != size) {
            let r = renderer(&self.gpu, sim, size)?;
            self.top = Some((r, size));
        }
        let (r, _) = self.top.as_mut().ok_or(HtmlError::NoRenderer)?;
        r.options = top_options(view, RenderOptions::default());
        let img = offscreen::render_image(&self.gpu, r, sim)?;
        jpeg_uri(&img, 80)
    }
}

/// `base` seen from straight above over `view`'s rectangle: no interaction visuals, grass or
/// water, and every leaf with no impostor or far model (seen from far above, level of detail
/// would thin the crowns).
fn top_options(view: TopView, base: RenderOptions) -> RenderOptions {
    RenderOptions {
        overlay: false,
        grass: false,
        water: false,
        leaf_pixels: 0.0,
        impostor_pixels: 0.0,
        far_pixels: 0.0,
        top_view: Some(view),
        ..base
    }
}
