//! The frame-time budget of the 3D view: when frames run slower than the target, the world is
//! rendered at a lower internal resolution and scaled up to the window; when they run fast
//! again, the resolution comes back. `grove play --quality` fixes the scale instead.
//!
//! The controller looks at the mean frame time over half a second and changes the scale at most
//! that often. The rendering cost of a software rasteriser grows with the pixel count, so the
//! new scale (a fraction of the window's width and height) is the old one times the square root
//! of target over measured time, kept in steps of 5 % between [`MIN_SCALE`] and 1. When frames
//! are still too slow at the smallest scale, the automatic budget also turns the sun's shadow
//! map off (its cost does not shrink with the resolution); it comes back first when frames are
//! fast again.

use std::str::FromStr;

/// The smallest internal resolution, as a fraction of the window's width and height.
pub const MIN_SCALE: f32 = 0.3;
/// The frame time the automatic budget aims at, seconds (25 fps, leaving room under 20 fps).
pub const TARGET_FRAME_S: f64 = 0.040;
/// How long the controller measures before it changes the scale, wall-clock seconds.
pub const ADJUST_EVERY_S: f64 = 0.5;

/// `--quality`: the automatic budget, or a fixed internal resolution scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Quality {
    /// Choose the scale from the measured frame time.
    Auto,
    /// A fixed scale in [`MIN_SCALE`, 1].
    Fixed(f32),
}

impl FromStr for Quality {
    type Err = String;

    fn from_str(s: &str) -> Result<Quality, String> {
        match s {
            "auto" => Ok(Quality::Auto),
            "full" => Ok(Quality::Fixed(1.0)),
            _ => match s.parse::<f32>() {
                Ok(v) if (MIN_SCALE..=1.0).contains(&v) => Ok(Quality::Fixed(v)),
                _ => Err(format!("'{s}' is not auto, full or a resolution scale between {MIN_SCALE} and 1")),
            },
        }
    }
}

/// The internal resolution controller.
#[derive(Clone, Debug)]
pub struct Budget {
    /// Automatic or fixed.
    pub quality: Quality,
    scale: f32,
    shadows: bool,
    spent: f64,
    frames: u32,
}

impl Budget {
    /// A controller starting at full resolution (or the fixed scale).
    pub fn new(quality: Quality) -> Budget {
        let scale = match quality {
            Quality::Auto => 1.0,
            Quality::Fixed(s) => s,
        };
        Budget { quality, scale, shadows: true, spent: 0.0, frames: 0 }
    }

    /// Whether the 3D view draws the sun's shadows.
    pub fn shadows(&self) -> bool {
        self.shadows
    }

    /// The current scale of the internal resolution.
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// Records one frame that took `seconds`; returns whether the scale or the shadows changed.
    pub fn frame(&mut self, seconds: f64) -> bool {
        if self.quality != Quality::Auto || !(seconds.is_finite() && seconds > 0.0) {
            return false;
        }
        self.spent += seconds;
        self.frames += 1;
        if self.spent < ADJUST_EVERY_S {
            return false;
        }
        let mean = self.spent / self.frames as f64;
        self.spent = 0.0;
        self.frames = 0;
        // Leave the scale alone inside a dead band, so that it does not hunt.
        let ratio = TARGET_FRAME_S / mean;
        if (0.85..=1.4).contains(&ratio) {
            return false;
        }
        if ratio < 0.85 && self.scale <= MIN_SCALE + 1e-6 && self.shadows {
            self.shadows = false;
            return true;
        }
        if ratio > 1.4 && !self.shadows {
            self.shadows = true;
            return true;
        }
        let wanted = self.scale * (ratio.sqrt() as f32).clamp(0.6, 1.15);
        let stepped = ((wanted / 0.05).round() * 0.05).clamp(MIN_SCALE, 1.0);
        let changed = (stepped - self.scale).abs() > 1e-6;
        self.scale = stepped;
        changed
    }

    /// The internal size for a window of `size` pixels.
    pub fn internal_size(&self, size: (u32, u32)) -> (u32, u32) {
        let f = |v: u32| ((v as f32 * self.scale).round() as u32).clamp(1, v.max(1));
        (f(size.0), f(size.1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slow_frames_lower_the_resolution_and_fast_ones_raise_it() {
        let mut b = Budget::new(Quality::Auto);
        // 8 fps at full size: the scale drops, by at most 40 % a step, towards the target.
        for _ in 0..4 {
            b.frame(0.125);
        }
        assert!(b.scale() < 1.0 && b.scale() >= 0.6 - 1e-6, "{}", b.scale());
        let mut steps = 0;
        while b.scale() > MIN_SCALE + 1e-6 && steps < 100 {
            b.frame(0.125);
            steps += 1;
        }
        assert_eq!(b.scale(), MIN_SCALE, "it never goes below the floor");
        for _ in 0..8 {
            b.frame(0.125);
        }
        assert!(!b.shadows(), "at the floor, still slow: the shadows go");
        assert_eq!(b.scale(), MIN_SCALE);
        for _ in 0..200 {
            b.frame(0.005);
        }
        assert!(b.shadows(), "fast again: the shadows come back first");
        assert!(b.scale() < 0.5);
        // Now very fast frames: it climbs back to full size.
        for _ in 0..2000 {
            b.frame(0.005);
        }
        assert_eq!(b.scale(), 1.0);
        assert_eq!(b.internal_size((1280, 720)), (1280, 720));
    }

    #[test]
    fn near_the_target_the_scale_stays() {
        let mut b = Budget::new(Quality::Auto);
        for _ in 0..1000 {
            b.frame(TARGET_FRAME_S * 1.1);
        }
        assert_eq!(b.scale(), 1.0);
    }

    #[test]
    fn a_fixed_quality_never_changes_and_sizes_follow_the_scale() {
        let mut b = Budget::new("0.5".parse().unwrap());
        for _ in 0..100 {
            assert!(!b.frame(1.0));
        }
        assert_eq!(b.internal_size((1280, 720)), (640, 360));
        assert_eq!(b.internal_size((1, 1)), (1, 1));
        assert_eq!("full".parse::<Quality>().unwrap(), Quality::Fixed(1.0));
        assert_eq!("auto".parse::<Quality>().unwrap(), Quality::Auto);
        for bad in ["0", "1.5", "fast", "NaN", ""] {
            assert!(bad.parse::<Quality>().is_err(), "{bad}");
        }
    }
}
