//! Text burned into a video's frames: who and which condition (top left), the task's elapsed
//! time (top right) and a caption for a second after each event (bottom centre), white on dark
//! translucent boxes so they read over sky and grass alike. Glyphs come from egui's bundled
//! Hack font, rasterised with `ab_glyph`.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use grove_systems::events::Happening;
use image::RgbaImage;

/// What a frame shows in text.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Captions {
    /// Top left: participant, condition and task.
    pub who: String,
    /// Top right: the task's clock.
    pub clock: String,
    /// Bottom centre: the events of the last second, newest last.
    pub events: Vec<String>,
}

/// The words a caption shows for a happening, for the events a viewer follows (planted,
/// snapped, removed, selected, a target satisfied (numbered from 1, as the task file's
/// targets are read), and the task's marks); `None` for the rest.
pub fn event_words(what: &Happening) -> Option<String> {
    let words = match what {
        Happening::Planted { .. } => "planted",
        Happening::Snapped { .. } => "snapped to the ground",
        Happening::Removed { .. } => "removed",
        Happening::Selected { .. } => "selected",
        Happening::TargetSatisfied { target, .. } => return Some(format!("target {} satisfied", target + 1)),
        Happening::TaskStarted { .. } => "task started",
        Happening::TaskCompleted => "task completed",
        Happening::TaskEnded => "task ended",
        _ => return None,
    };
    Some(words.to_string())
}

/// The task's clock in words: seconds since the task started, with tenths ("12.4 s"), "before
/// the task", or the final time once it ended.
pub fn clock(tick: u64, start: Option<u64>, end: Option<u64>, dt: f32) -> String {
    match start {
        Some(s) if tick >= s => {
            let t = end.map_or(tick, |e| tick.min(e));
            format!("task {:.1} s", (t - s) as f64 * dt as f64)
        }
        Some(_) => "before the task".into(),
        None => format!("{:.1} s", tick as f64 * dt as f64),
    }
}

fn font() -> FontRef<'static> {
    // The bundled font is valid; `try_from_slice` only fails for a broken file.
    FontRef::try_from_slice(epaint_default_fonts::HACK_REGULAR).expect("the bundled Hack font parses")
}

/// The pixel width of `text` at `scale`.
fn text_width(font: &FontRef<'_>, scale: PxScale, text: &str) -> f32 {
    let f = font.as_scaled(scale);
    text.chars().map(|c| f.h_advance(f.glyph_id(c))).sum()
}

/// Darkens a rectangle of `img` (clipped to it) to 40 % of its colour.
fn shade(img: &mut RgbaImage, x0: i64, y0: i64, x1: i64, y1: i64) {
    let (w, h) = (img.width() as i64, img.height() as i64);
    for y in y0.max(0)..y1.min(h) {
        for x in x0.max(0)..x1.min(w) {
            let p = img.get_pixel_mut(x as u32, y as u32);
            for c in 0..3 {
                p.0[c] = (p.0[c] as u16 * 2 / 5) as u8;
            }
        }
    }
}

/// Draws `text` with its top-left corner at (`x`, `y`), white, blended by glyph coverage.
fn draw_text(img: &mut RgbaImage, font: &FontRef<'_>, scale: PxScale, x: f32, y: f32, text: &str) {
    let f = font.as_scaled(scale);
    let mut pen = x;
    let (w, h) = (img.width() as i64, img.height() as i64);
    for c in text.chars() {
        let id = f.glyph_id(c);
        let glyph = id.with_scale_and_position(scale, ab_glyph::point(pen, y + f.ascent()));
        pen += f.h_advance(id);
        if let Some(outline) = font.outline_glyph(glyph) {
            let b = outline.px_bounds();
            outline.draw(|gx, gy, cov| {
                let (px, py) = (b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64);
                if px >= 0 && py >= 0 && px < w && py < h {
                    let p = img.get_pixel_mut(px as u32, py as u32);
                    let a = cov.clamp(0.0, 1.0);
                    for ch in 0..3 {
                        p.0[ch] = (p.0[ch] as f32 * (1.0 - a) + 255.0 * a).round() as u8;
                    }
                }
            });
        }
    }
}

/// The text's height, pixels, for an image `height` pixels tall (1/30 of it, at least 10).
pub fn text_px(height: u32) -> f32 {
    (height as f32 / 30.0).max(10.0)
}

/// The rows at the top and the bottom of a frame that captions may cover, pixels: everything
/// between them is the rendered world untouched.
pub fn covered_rows(height: u32) -> (u32, u32) {
    let line = text_px(height) * 1.5;
    ((line * 1.2).ceil() as u32, (line * 3.4).ceil() as u32)
}

/// Burns `captions` into `img`.
pub fn burn(img: &mut RgbaImage, captions: &Captions) {
    let font = font();
    let px = text_px(img.height());
    let scale = PxScale::from(px);
    let pad = (px * 0.35).round();
    let line = px * 1.5;
    let (w, h) = (img.width() as f32, img.height() as f32);
    let boxed = |img: &mut RgbaImage, x: f32, y: f32, text: &str| {
        let tw = text_width(&font, scale, text);
        shade(img, (x - pad) as i64, (y - pad * 0.5) as i64, (x + tw + pad) as i64, (y + line - pad * 0.5) as i64);
        draw_text(img, &font, scale, x, y, text);
    };
    if !captions.who.is_empty() {
        boxed(img, pad * 2.0, pad, &captions.who);
    }
    if !captions.clock.is_empty() {
        let tw = text_width(&font, scale, &captions.clock);
        boxed(img, w - tw - pad * 2.0, pad, &captions.clock);
    }
    // The newest two events, the newest at the bottom.
    let shown: Vec<&String> = captions.events.iter().rev().take(2).collect();
    for (i, text) in shown.iter().enumerate() {
        let tw = text_width(&font, scale, text);
        let y = h - (i as f32 + 1.0) * line - pad * 2.0;
        boxed(img, (w - tw) * 0.5, y, text);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clock_starts_with_the_task_and_stops_at_its_end() {
        let dt = 1.0 / 60.0;
        assert_eq!(clock(10, Some(31), None, dt), "before the task");
        assert_eq!(clock(31, Some(31), None, dt), "task 0.0 s");
        assert_eq!(clock(31 + 750, Some(31), None, dt), "task 12.5 s");
        assert_eq!(clock(5000, Some(31), Some(31 + 600), dt), "task 10.0 s");
        assert_eq!(clock(120, None, None, dt), "2.0 s");
    }

    #[test]
    fn captions_mark_the_followed_events_only() {
        assert_eq!(
            event_words(&Happening::Snapped { tree: 1, position: glam::Vec3::ZERO }).as_deref(),
            Some("snapped to the ground")
        );
        assert_eq!(event_words(&Happening::MenuOpened), None);
        // Targets are numbered from 1 where a person reads them; the log keeps the file's index.
        assert_eq!(
            event_words(&Happening::TargetSatisfied { target: 2, tree: 1 }).as_deref(),
            Some("target 3 satisfied")
        );
    }

    #[test]
    fn burned_text_stays_in_the_covered_rows_and_is_light_on_dark() {
        let (w, h) = (640, 360);
        let grey = image::Rgba([128, 128, 128, 255]);
        let mut img = RgbaImage::from_pixel(w, h, grey);
        burn(
            &mut img,
            &Captions { who: "P03 · ray-casting".into(), clock: "task 12.4 s".into(), events: vec!["planted".into()] },
        );
        let (top, bottom) = covered_rows(h);
        let mut changed_top = 0;
        let (mut white, mut dark) = (0, 0);
        for (x, y, p) in img.enumerate_pixels() {
            if *p != grey {
                assert!(y < top || y >= h - bottom, "pixel ({x}, {y}) changed outside the caption rows");
                changed_top += usize::from(y < top);
                white += usize::from(p.0[0] > 200);
                dark += usize::from(p.0[0] < 60);
            }
        }
        assert!(changed_top > 0 && white > 50 && dark > 500, "{changed_top} {white} {dark}");
        // Both top corners carry text: the left box and the right one.
        let row_has = |x0: u32, x1: u32| (0..top).any(|y| (x0..x1).any(|x| *img.get_pixel(x, y) != grey));
        assert!(row_has(0, 80) && row_has(w - 80, w));
    }
}
