//! The human-performance model of synthetic participants, as pure functions.
//!
//! `docs/participants.md` documents every constant and its source. In short:
//! - aiming time follows Fitts' law for distal (ray) pointing over angular amplitude and angular
//!   target width (Kopper et al. 2010), `MT = a + b·log2(A/W + 1)`;
//! - the ray moves along a minimum-jerk profile (Flash & Hogan 1985);
//! - endpoints scatter with a Gaussian whose standard deviation is `W / 4.133`, the effective
//!   width convention (MacKenzie 1992; Soukoreff & MacKenzie 2004), and a miss is followed by a
//!   corrective sub-movement (Meyer et al. 1988);
//! - mental preparation, button presses and menu pointing are Keystroke-Level Model operators
//!   (Card, Moran & Newell 1980).

use glam::{Quat, Vec3};
use rand::{Rng, RngExt};
use rand_distr::{Distribution, LogNormal, Normal};

/// Mean Fitts intercept for ray pointing, seconds.
pub const FITTS_A: f64 = 0.20;
/// Mean Fitts slope for ray pointing, seconds per bit (throughput ≈ 4.5 bit/s).
pub const FITTS_B: f64 = 0.22;
/// KLM mental preparation, seconds.
pub const KLM_MENTAL: f64 = 1.35;
/// KLM button press, fastest and slowest participants, seconds.
pub const KLM_PRESS: (f64, f64) = (0.20, 0.28);
/// The effective-width constant: a Gaussian endpoint spread of `W / 4.133` puts 96 % of hits
/// inside a target of width `W`.
pub const EFFECTIVE_WIDTH: f64 = 4.133;
/// Angular width of a menu item as seen by the user, radians (a 6 cm item at 45 cm).
pub const MENU_ITEM_WIDTH: f64 = 0.133;
/// Angular amplitude of a typical menu pointing movement, radians.
pub const MENU_AMPLITUDE: f64 = 0.35;

/// One participant's motor and cognitive parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Skill {
    /// Fitts intercept, seconds.
    pub fitts_a: f64,
    /// Fitts slope, seconds per bit.
    pub fitts_b: f64,
    /// Mental preparation, seconds.
    pub mental: f64,
    /// Button press, seconds.
    pub press: f64,
    /// Multiplier on the endpoint spread (1 = exactly the effective-width convention).
    pub scatter: f64,
    /// Probability of a wrong-model or misplaced tree per target.
    pub error_rate: f64,
}

impl Skill {
    /// Draws a participant: Fitts constants and mental time vary log-normally (about ±20 %),
    /// the press time uniformly within the KLM range, and the error rate between 4 % and 12 %.
    pub fn sample<R: Rng + ?Sized>(rng: &mut R) -> Skill {
        let ln = LogNormal::new(0.0, 0.2).expect("valid log-normal");
        let speed = ln.sample(rng);
        Skill {
            fitts_a: FITTS_A * speed,
            fitts_b: FITTS_B * speed * LogNormal::new(0.0, 0.1).expect("valid log-normal").sample(rng),
            mental: KLM_MENTAL * LogNormal::new(0.0, 0.15).expect("valid log-normal").sample(rng),
            press: rng.random_range(KLM_PRESS.0..=KLM_PRESS.1),
            scatter: rng.random_range(0.8..1.2),
            error_rate: rng.random_range(0.04..0.12),
        }
    }

    /// Fitts movement time for an angular amplitude and width (radians), seconds.
    pub fn aim_time(&self, amplitude: f64, width: f64) -> f64 {
        fitts_time(self.fitts_a, self.fitts_b, amplitude, width)
    }

    /// Standard deviation of the angular endpoint for a target of angular width `width`.
    pub fn endpoint_sigma(&self, width: f64) -> f64 {
        self.scatter * width / EFFECTIVE_WIDTH
    }

    /// Time to point at a menu item and select it: Fitts over the menu geometry plus a press.
    pub fn menu_time(&self) -> f64 {
        self.aim_time(MENU_AMPLITUDE, MENU_ITEM_WIDTH) + self.press
    }
}

/// Fitts' law, Shannon formulation: `a + b·log2(A/W + 1)`, seconds. Non-positive widths are
/// treated as a very small target.
pub fn fitts_time(a: f64, b: f64, amplitude: f64, width: f64) -> f64 {
    a + b * (amplitude.max(0.0) / width.max(1e-4) + 1.0).log2()
}

/// The minimum-jerk position profile: 0 at s = 0, 1 at s = 1, zero velocity and acceleration at
/// both ends.
pub fn min_jerk(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)
}

/// The angle between two directions, radians.
pub fn angle_between(a: Vec3, b: Vec3) -> f64 {
    (a.normalize().dot(b.normalize()) as f64).clamp(-1.0, 1.0).acos()
}

/// The angular width of a target of linear `size` metres at `distance` metres, radians.
pub fn angular_width(size: f64, distance: f64) -> f64 {
    2.0 * (0.5 * size / distance.max(1e-3)).atan()
}

/// A direction scattered around `dir` by an angular Gaussian of standard deviation `sigma`
/// radians (in each of two perpendicular axes).
pub fn scatter_direction<R: Rng + ?Sized>(rng: &mut R, dir: Vec3, sigma: f64) -> Vec3 {
    let normal = Normal::new(0.0, sigma.max(0.0)).expect("valid normal");
    let (dx, dy) = (normal.sample(rng) as f32, normal.sample(rng) as f32);
    let dir = dir.normalize();
    let side = dir.cross(Vec3::Y).normalize_or(Vec3::X);
    let up = side.cross(dir).normalize_or(Vec3::Y);
    (Quat::from_axis_angle(up, dx) * Quat::from_axis_angle(side, dy) * dir).normalize()
}

/// A point on the way from direction `from` to `to` at progress `s` of a minimum-jerk movement.
pub fn sweep(from: Vec3, to: Vec3, s: f64) -> Vec3 {
    let k = min_jerk(s) as f32;
    let q = Quat::from_rotation_arc(from.normalize(), to.normalize());
    (Quat::IDENTITY.slerp(q, k) * from.normalize()).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn fitts_time_grows_with_difficulty() {
        assert!((fitts_time(0.2, 0.22, 0.0, 0.1) - 0.2).abs() < 1e-12);
        let easy = fitts_time(0.2, 0.22, 0.2, 0.1);
        let hard = fitts_time(0.2, 0.22, 0.8, 0.02);
        assert!((easy - (0.2 + 0.22 * 3f64.log2())).abs() < 1e-12);
        assert!(hard > easy + 0.5);
    }

    #[test]
    fn min_jerk_has_its_textbook_shape() {
        assert_eq!(min_jerk(0.0), 0.0);
        assert_eq!(min_jerk(1.0), 1.0);
        assert!((min_jerk(0.5) - 0.5).abs() < 1e-12);
        // Zero velocity at the ends: tiny change near 0 and 1.
        assert!(min_jerk(0.01) < 1e-5 && 1.0 - min_jerk(0.99) < 1e-5);
    }

    #[test]
    fn endpoint_scatter_matches_the_effective_width() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let skill = Skill { scatter: 1.0, ..Skill::sample(&mut rng) };
        let width = 0.1;
        let sigma = skill.endpoint_sigma(width);
        let n = 4000;
        let inside = (0..n)
            .filter(|_| angle_between(scatter_direction(&mut rng, Vec3::NEG_Z, sigma), Vec3::NEG_Z) < width / 2.0)
            .count();
        // Two independent axes: P(r < W/2) = 1 − exp(−(W/2)²/(2σ²)) ≈ 0.88 for σ = W/4.133.
        let p = inside as f64 / n as f64;
        assert!((p - 0.882).abs() < 0.03, "{p}");
    }

    #[test]
    fn sweeps_start_and_end_on_their_directions() {
        let a = Vec3::new(0.0, -0.3, -1.0).normalize();
        let b = Vec3::new(0.8, -0.5, -0.6).normalize();
        assert!(angle_between(sweep(a, b, 0.0), a) < 1e-3);
        assert!(angle_between(sweep(a, b, 1.0), b) < 1e-3);
        let mid = sweep(a, b, 0.5);
        assert!((angle_between(a, mid) - angle_between(mid, b)).abs() < 1e-3);
    }

    #[test]
    fn sampled_skills_stay_in_their_ranges() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        for _ in 0..200 {
            let s = Skill::sample(&mut rng);
            assert!((KLM_PRESS.0..=KLM_PRESS.1).contains(&s.press));
            assert!(s.fitts_a > 0.05 && s.fitts_a < 0.8 && s.fitts_b > 0.05 && s.fitts_b < 0.9);
            assert!((0.04..0.12).contains(&s.error_rate));
        }
    }
}
