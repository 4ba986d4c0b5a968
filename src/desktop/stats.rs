//! Rolling rates for the debug panel: frames per second and frame time from the same window of
//! recent frames (so the two always agree), and simulation ticks per second.

use std::collections::VecDeque;

/// The length of the rolling window, wall-clock seconds.
pub const WINDOW_S: f64 = 1.0;

/// A rolling window of events, each with the wall-clock seconds it covered and how many things
/// it counted (one frame, or the ticks run in that frame).
#[derive(Clone, Debug, Default)]
pub struct Rolling {
    samples: VecDeque<(f64, u64)>,
    span: f64,
    count: u64,
}

impl Rolling {
    /// Adds one sample: `seconds` of wall-clock time in which `count` things happened. Samples
    /// older than [`WINDOW_S`] (keeping at least the newest) are dropped.
    pub fn push(&mut self, seconds: f64, count: u64) {
        if !(seconds.is_finite() && seconds >= 0.0) {
            return;
        }
        self.samples.push_back((seconds, count));
        self.span += seconds;
        self.count += count;
        let mut dropped = false;
        while self.samples.len() > 1 && self.span - self.samples[0].0 >= WINDOW_S {
            let (s, c) = self.samples.pop_front().unwrap_or_default();
            self.span -= s;
            self.count -= c;
            dropped = true;
        }
        if dropped {
            // Sum afresh so that rounding does not build up over a long session.
            self.span = self.samples.iter().map(|s| s.0).sum();
        }
    }

    /// Things per second over the window (0 before any time has passed).
    pub fn rate(&self) -> f64 {
        if self.span > 0.0 { self.count as f64 / self.span } else { 0.0 }
    }

    /// The mean wall-clock seconds per sample over the window (0 when empty).
    pub fn mean_seconds(&self) -> f64 {
        if self.samples.is_empty() { 0.0 } else { self.span / self.samples.len() as f64 }
    }
}

/// What the debug panel shows about speed, all over the same rolling window.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// Frames per second over the window.
    pub fps: f32,
    /// Mean frame time over the window, milliseconds (1000 / `fps`).
    pub frame_ms: f32,
}

impl FrameStats {
    /// The statistics of a rolling window of frames (one sample per frame, count 1).
    pub fn of(frames: &Rolling) -> FrameStats {
        FrameStats { fps: frames.rate() as f32, frame_ms: (frames.mean_seconds() * 1000.0) as f32 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_rate_and_frame_time_agree() {
        let mut r = Rolling::default();
        // Frames alternating 10 ms and 30 ms: 20 ms on average, 50 frames per second.
        for i in 0..200 {
            r.push(if i % 2 == 0 { 0.010 } else { 0.030 }, 1);
        }
        let s = FrameStats::of(&r);
        assert!((s.fps - 50.0).abs() < 0.5, "{s:?}");
        assert!((s.frame_ms - 20.0).abs() < 0.2, "{s:?}");
        assert!((s.fps * s.frame_ms - 1000.0).abs() < 1.0, "fps × ms = 1000: {s:?}");
    }

    #[test]
    fn old_frames_leave_the_window() {
        let mut r = Rolling::default();
        for _ in 0..10 {
            r.push(0.3, 1);
        }
        // Then a fast second: only it is reported.
        for _ in 0..100 {
            r.push(0.01, 1);
        }
        assert!((r.rate() - 100.0).abs() < 2.0, "{}", r.rate());
        // One very long frame is kept on its own.
        r.push(5.0, 1);
        assert!((r.rate() - 0.2).abs() < 1e-9, "{}", r.rate());
        assert!((r.mean_seconds() - 5.0).abs() < 1e-9, "{}", r.mean_seconds());
    }

    #[test]
    fn ticks_per_second_count_ticks_not_frames() {
        let mut r = Rolling::default();
        // 30 frames of 1/30 s, each running 3 or 4 ticks of a 100 Hz clock.
        for i in 0..30 {
            r.push(1.0 / 30.0, if i % 3 == 0 { 4 } else { 3 });
        }
        assert!((r.rate() - 100.0).abs() < 4.0, "{}", r.rate());
        r.push(f64::NAN, 1);
        assert!(r.rate().is_finite());
    }
}
