//! Where the clipmap's levels lie (Ropinski et al. 2007, Section 3), as pure functions.
//!
//! The photograph lies on the plane Y = 0. Three cases, decided by the camera alone:
//!
//! - **Straight down, or within [`CONCENTRIC_BELOW_DEG`] of it**: the concentric layout, every
//!   level centred on the ground point below the eye.
//! - **A free camera**: the levels are placed along the ground vector `g` (the view direction
//!   projected onto the ground, made unit). Let `B` be the point where the ray through the bottom
//!   edge of the view frustum (the view direction turned down by half the vertical field of view)
//!   meets the ground, or the point below the eye when that ray does not come down. Level `i`,
//!   `S_i` metres wide, is centred at `B + g · S_i / 2`: shifted by half a level from `B` so
//!   that its edge nearest the viewer passes through `B` and the whole level lies ahead, in view.
//!   All levels thus share their nearest edge at the bottom of the view.
//!
//! Each level's window is then snapped to whole texels of its mip, and to an even texel so that
//! it starts on a texel of the next coarser mip (levels nest), and clamped so that it stays over
//! the photograph as far as it can (a level larger than its mip covers all of it).

use glam::{DVec2, DVec3, IVec2};

use super::{AerialPlacement, ClipCamera, ClipmapConfig, LevelPlacement};

/// Below this angle between the view direction and straight down, degrees, the levels are
/// concentric.
pub const CONCENTRIC_BELOW_DEG: f64 = 15.0;

/// The size of the photograph's pyramid: what placement needs to clamp the levels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageExtent {
    /// Mip 0's width, texels.
    pub width: u32,
    /// Mip 0's height, texels.
    pub height: u32,
    /// The number of mips in the pyramid (at least 1).
    pub mips: u32,
}

/// How the levels are laid out for a camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Layout {
    /// Every level centred at this ground point (world X, Z), metres.
    Concentric {
        /// The common centre.
        centre: DVec2,
    },
    /// Levels along the ground vector, sharing their nearest edge at the bottom of the view.
    Forward {
        /// Where the bottom of the view frustum meets the ground (world X, Z), metres.
        bottom: DVec2,
        /// The unit ground vector of the view (world X, Z).
        ground: DVec2,
    },
}

impl Layout {
    /// The centre (world X, Z, metres) of a level `side_m` metres wide.
    pub fn centre(&self, side_m: f64) -> DVec2 {
        match *self {
            Layout::Concentric { centre } => centre,
            Layout::Forward { bottom, ground } => bottom + ground * (side_m / 2.0),
        }
    }
}

/// Decides the layout for `camera` (the photograph on Y = 0).
pub fn layout(camera: &ClipCamera) -> Layout {
    let eye = camera.eye;
    let below = if eye.is_finite() { DVec2::new(eye.x, eye.z) } else { DVec2::ZERO };
    let concentric = Layout::Concentric { centre: below };
    let d = camera.forward.normalize_or_zero();
    if !d.is_finite() || d == DVec3::ZERO || !eye.is_finite() {
        return concentric;
    }
    // The angle from straight down is acos(−d.y).
    if -d.y >= CONCENTRIC_BELOW_DEG.to_radians().cos() {
        return concentric;
    }
    let flat = DVec2::new(d.x, d.z);
    if flat.length() < 1e-9 {
        // Looking straight up: nothing of the ground is in view; keep the levels below the eye.
        return concentric;
    }
    let ground = flat.normalize();
    let right = d.cross(DVec3::Y).normalize();
    let up = right.cross(d);
    let half =
        if camera.fov_y.is_finite() { (camera.fov_y / 2.0).clamp(0.0, std::f64::consts::FRAC_PI_2) } else { 0.0 };
    let ray = d * half.cos() - up * half.sin();
    let bottom = if eye.y > 0.0 && ray.y < 0.0 { below + DVec2::new(ray.x, ray.z) * (eye.y / -ray.y) } else { below };
    Layout::Forward { bottom, ground }
}

/// The mip level `level` shows: its own index, or the pyramid's last mip when it has fewer.
pub fn level_mip(level: u32, extent: &ImageExtent) -> u32 {
    level.min(extent.mips.max(1) - 1)
}

/// Every level's placement for `camera`, finest first.
pub fn place_levels(
    config: &ClipmapConfig,
    aerial: &AerialPlacement,
    extent: &ImageExtent,
    camera: &ClipCamera,
) -> Vec<LevelPlacement> {
    let lay = layout(camera);
    let n = config.size as f64;
    (0..config.levels)
        .map(|level| {
            let mip = level_mip(level, extent);
            let texel_m = aerial.gsd_m * (1u64 << mip) as f64;
            let centre = lay.centre(n * texel_m);
            let u = (centre - aerial.origin_m) / texel_m;
            let (w, h) = (shrink(extent.width, mip), shrink(extent.height, mip));
            let origin = IVec2::new(snap(u.x, config.size, w), snap(u.y, config.size, h));
            LevelPlacement { mip, origin }
        })
        .collect()
}

/// A side of `side` texels at mip `mip`, halved and rounded up.
fn shrink(side: u32, mip: u32) -> u32 {
    if mip >= 32 { 1 } else { side.div_ceil(1 << mip).max(1) }
}

/// The window's first texel for a centre at texel coordinate `c`: the nearest even texel to
/// `c − size / 2`, clamped to keep a window of `size` over a mip of `side` texels.
fn snap(c: f64, size: u32, side: u32) -> i32 {
    let even_up = |v: i64| v + v.rem_euclid(2);
    let over = side as i64 - size as i64;
    let (lo, hi) = (even_up(over.min(0)), even_up(over.max(0)));
    let want = 2.0 * ((c - size as f64 / 2.0) / 2.0).round();
    // NaN becomes 0 in the cast; the clamp keeps any finite or infinite value in range.
    (want.clamp(lo as f64, hi as f64) as i64).clamp(lo, hi) as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    const CFG: ClipmapConfig = ClipmapConfig { levels: 3, size: 16 };

    fn cam(eye: DVec3, forward: DVec3) -> ClipCamera {
        ClipCamera { eye, forward: forward.normalize(), fov_y: 60f64.to_radians(), aspect: 16.0 / 9.0 }
    }

    fn origins(p: &[LevelPlacement]) -> Vec<(u32, i32, i32)> {
        p.iter().map(|l| (l.mip, l.origin.x, l.origin.y)).collect()
    }

    const EXTENT: ImageExtent = ImageExtent { width: 1024, height: 1024, mips: 5 };
    const UNIT: AerialPlacement = AerialPlacement { origin_m: DVec2::ZERO, gsd_m: 1.0 };

    /// Worked by hand: the eye above (500.3, 300.7), 1 m texels, windows of 16.
    /// Level 0 (mip 0): 500.3 − 8 = 492.3 → nearest even 492; 300.7 − 8 = 292.7 → 292.
    /// Level 1 (mip 1, 2 m): 250.15 − 8 = 242.15 → 242; 150.35 − 8 = 142.35 → 142.
    /// Level 2 (mip 2, 4 m): 125.075 − 8 = 117.075 → 118; 75.175 − 8 = 67.175 → 68.
    const STRAIGHT_DOWN: [(u32, i32, i32); 3] = [(0, 492, 292), (1, 242, 142), (2, 118, 68)];

    #[test]
    fn looking_straight_down_centres_every_level_below_the_camera() {
        let c = cam(DVec3::new(500.3, 100.0, 300.7), DVec3::NEG_Y);
        assert_eq!(layout(&c), Layout::Concentric { centre: DVec2::new(500.3, 300.7) });
        assert_eq!(origins(&place_levels(&CFG, &UNIT, &EXTENT, &c)), STRAIGHT_DOWN);
    }

    #[test]
    fn within_fifteen_degrees_of_vertical_the_layout_stays_concentric() {
        let eye = DVec3::new(500.3, 100.0, 300.7);
        let tilt = |deg: f64| DVec3::new(0.0, -deg.to_radians().cos(), -deg.to_radians().sin());
        assert_eq!(origins(&place_levels(&CFG, &UNIT, &EXTENT, &cam(eye, tilt(10.0)))), STRAIGHT_DOWN);
        assert_eq!(origins(&place_levels(&CFG, &UNIT, &EXTENT, &cam(eye, tilt(14.9)))), STRAIGHT_DOWN);
        assert!(matches!(layout(&cam(eye, tilt(15.1))), Layout::Forward { .. }));
        assert_ne!(origins(&place_levels(&CFG, &UNIT, &EXTENT, &cam(eye, tilt(20.0)))), STRAIGHT_DOWN);
    }

    /// Worked by hand: the eye at (200, 100, 300) looks north (−Z), 45° down, with a 60° field
    /// of view, so the frustum's bottom ray is 75° down and meets the ground at
    /// z = 300 − 100 / tan 75° = 273.2051, x = 200. The photograph's corner is at (−100, 50),
    /// 0.5 m texels. Level i, 8 · 2^i m wide, is centred 4 · 2^i m north of that point.
    /// Level 0 (0.5 m): centre (200, 269.2051) → texel (600, 438.4102); origin 592, 430.41 → 430.
    /// Level 1 (1 m): centre (200, 265.2051) → texel (300, 215.2051); origin 292, 207.21 → 208.
    /// Level 2 (2 m): centre (200, 257.2051) → texel (150, 103.6026); origin 142, 95.60 → 96.
    #[test]
    fn a_free_camera_lines_the_levels_up_from_the_bottom_of_the_view() {
        let aerial = AerialPlacement { origin_m: DVec2::new(-100.0, 50.0), gsd_m: 0.5 };
        let extent = ImageExtent { width: 4096, height: 4096, mips: 6 };
        let s = 45f64.to_radians();
        let c = cam(DVec3::new(200.0, 100.0, 300.0), DVec3::new(0.0, -s.sin(), -s.cos()));
        match layout(&c) {
            Layout::Forward { bottom, ground } => {
                assert!((bottom - DVec2::new(200.0, 273.2051)).length() < 1e-4, "{bottom}");
                assert!((ground - DVec2::new(0.0, -1.0)).length() < 1e-12);
            }
            other => panic!("expected the forward layout, got {other:?}"),
        }
        let p = place_levels(&CFG, &aerial, &extent, &c);
        assert_eq!(origins(&p), [(0, 592, 430), (1, 292, 208), (2, 142, 96)]);
        // Every level's southern (nearest) edge lies within one texel pair of the bottom point.
        for l in &p {
            let texel = 0.5 * (1 << l.mip) as f64;
            let near_z = 50.0 + (l.origin.y + 16) as f64 * texel;
            assert!((near_z - 273.2051).abs() <= 2.0 * texel, "level at mip {}: {near_z}", l.mip);
        }
    }

    #[test]
    fn looking_at_the_horizon_keeps_the_bottom_point_in_front_and_finite() {
        // Looking east, level: the bottom ray comes down 30° ahead of the eye at height 10.
        let c = cam(DVec3::new(100.0, 10.0, 100.0), DVec3::X);
        match layout(&c) {
            Layout::Forward { bottom, ground } => {
                assert!((bottom - DVec2::new(100.0 + 10.0 / 30f64.to_radians().tan(), 100.0)).length() < 1e-9);
                assert_eq!(ground, DVec2::X);
            }
            other => panic!("{other:?}"),
        }
        // Looking up: the bottom ray never comes down, so the levels start below the eye.
        let up = cam(DVec3::new(100.0, 10.0, 100.0), DVec3::new(1.0, 1.0, 0.0));
        assert_eq!(layout(&up), Layout::Forward { bottom: DVec2::new(100.0, 100.0), ground: DVec2::X });
        // Nonsense cameras do not panic.
        let nan = ClipCamera { eye: DVec3::NAN, forward: DVec3::NAN, fov_y: f64::NAN, aspect: 1.0 };
        assert_eq!(place_levels(&CFG, &UNIT, &EXTENT, &nan).len(), 3);
    }

    #[test]
    fn windows_are_clamped_to_the_photograph_and_levels_past_the_last_mip_repeat_it() {
        // A 40 × 40 photograph with two mips (40, 20); four levels of 16.
        let extent = ImageExtent { width: 40, height: 40, mips: 2 };
        let cfg = ClipmapConfig { levels: 4, size: 16 };
        // Far west of the photograph: mip 0's window stops at the left edge (0), mip 1's (20
        // texels wide) may start at 0 .. 4; straight down at z = 20.
        let c = cam(DVec3::new(-5000.0, 50.0, 20.0), DVec3::NEG_Y);
        let p = place_levels(&cfg, &UNIT, &extent, &c);
        // Mip 0 row: 20 − 8 = 12. Mip 1 row: 10 − 8 = 2.
        assert_eq!(origins(&p), [(0, 0, 12), (1, 0, 2), (1, 0, 2), (1, 0, 2)]);
        // A mip smaller than the window: 10 texels in a window of 16 may start at −6 .. 0.
        let extent = ImageExtent { width: 40, height: 40, mips: 3 };
        let c = cam(DVec3::new(20.0, 50.0, 1e12), DVec3::NEG_Y);
        let p = place_levels(&cfg, &UNIT, &extent, &c);
        // Mip 2: x 5 − 8 = −3 → −2 · 1.5 rounds to −4; z far south → 0 (the highest start).
        assert_eq!((p[2].mip, p[2].origin), (2, IVec2::new(-4, 0)));
    }
}
