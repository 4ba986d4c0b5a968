//! Scattering trees over a region of a scene: Poisson-disk positions (Bridson's algorithm) at a
//! minimum spacing inside a boundary polygon, each kept with a probability from a Perlin noise
//! field (the `noise` crate), with model, heading and scale drawn from the scatter's own seed.
//! The result depends only on the scatter definition; each tree becomes an ordinary `TreeDef`.
//!
//! Units: metres and degrees; the boundary is given in the ground plane as (x, z) points.

use glam::{Vec2, Vec3};
use noise::{NoiseFn, Perlin};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::tree_def::TreeDef;

/// The most trees one scatter may place.
pub const MAX_TREES: usize = 20_000;

/// The most points of a scatter's boundary.
pub const MAX_BOUNDARY: usize = 4096;

/// The most cells of a scatter's sampling grid (4 bytes each).
pub const MAX_GRID_CELLS: usize = 4 << 20;

/// The range of a scatter's spacing, metres.
pub const SPACING: (f32, f32) = (0.01, 1.0e4);

/// The range of a scatter's noise feature size, metres.
pub const FEATURE: (f32, f32) = (0.1, 1.0e5);

/// The range of a scatter's noise contrast.
pub const CONTRAST: (f32, f32) = (-100.0, 100.0);

/// The range of a scattered tree's scale (the same as a tree's).
pub const SCALE: (f32, f32) = (0.0, 1000.0);

/// The area of a simple polygon (shoelace formula, in double precision), m².
pub fn polygon_area(poly: &[Vec2]) -> f64 {
    let mut twice = 0.0f64;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        twice += a.x as f64 * b.y as f64 - b.x as f64 * a.y as f64;
    }
    (twice / 2.0).abs()
}

/// A scatter: trees spread over a region.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScatterDef {
    /// Catalogue model names; each tree takes one of them at random.
    pub models: Vec<String>,
    /// The region: a simple polygon of (x, z) points, metres.
    pub boundary: Vec<Vec2>,
    /// The minimum distance between two trees, metres.
    pub spacing: f32,
    /// The mean probability that a Poisson-disk position gets a tree, 0..1.
    #[serde(default = "default_coverage")]
    pub coverage: f32,
    /// How strongly the noise moves the probability: p = clamp(coverage + contrast × noise, 0, 1),
    /// with the noise roughly in −1..1.
    #[serde(default = "default_contrast")]
    pub contrast: f32,
    /// The size of a noise feature (clearings and thickets), metres.
    #[serde(default = "default_feature")]
    pub feature: f32,
    /// The scale of a tree is drawn uniformly from this range.
    #[serde(default = "default_scale")]
    pub scale: (f32, f32),
    /// The seed of this scatter's positions, noise and draws.
    pub seed: u64,
}

fn default_coverage() -> f32 {
    0.6
}
fn default_contrast() -> f32 {
    1.0
}
fn default_feature() -> f32 {
    8.0
}
fn default_scale() -> (f32, f32) {
    (0.9, 1.1)
}

/// Whether `p` is inside the polygon `poly` (even-odd rule).
pub fn inside(poly: &[Vec2], p: Vec2) -> bool {
    let mut odd = false;
    let mut j = poly.len() - 1;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[j]);
        if (a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x {
            odd = !odd;
        }
        j = i;
    }
    odd
}

impl ScatterDef {
    /// Checks the numbers against their stated ranges and bounds the work before anything is
    /// allocated: the polygon's own area (not its bounding box) over the spacing bounds the
    /// trees, and the bounding box over the spacing bounds the sampling grid. Returns a one-line
    /// message for the first problem.
    pub fn validate(&self) -> Result<(), crate::limits::InvalidScene> {
        self.validate_message().map_err(crate::limits::InvalidScene)
    }

    fn validate_message(&self) -> Result<(), String> {
        if self.models.is_empty() {
            return Err("a scatter needs at least one model".into());
        }
        if self.boundary.len() < 3 {
            return Err(format!("a scatter's boundary has {} points; it needs at least 3", self.boundary.len()));
        }
        if self.boundary.len() > MAX_BOUNDARY {
            return Err(format!("a scatter's boundary has {} points; at most {MAX_BOUNDARY}", self.boundary.len()));
        }
        let nums = [self.spacing, self.coverage, self.contrast, self.feature, self.scale.0, self.scale.1];
        if !self.boundary.iter().all(|p| p.is_finite()) || !nums.iter().all(|v| v.is_finite()) {
            return Err("a scatter has a NaN or infinite number".into());
        }
        let c = crate::limits::MAX_COORD;
        if self.boundary.iter().any(|p| p.x.abs() > c || p.y.abs() > c) {
            return Err(format!("a scatter's boundary has a point beyond {c} m"));
        }
        let range = |name: &str, v: f32, (lo, hi): (f32, f32)| {
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(format!("a scatter's {name} is {v}; it must be within {lo}..={hi}"))
            }
        };
        range("spacing", self.spacing, SPACING)?;
        range("feature", self.feature, FEATURE)?;
        range("coverage", self.coverage, (0.0, 1.0))?;
        range("contrast", self.contrast, CONTRAST)?;
        range("scale's minimum", self.scale.0, SCALE)?;
        range("scale's maximum", self.scale.1, SCALE)?;
        if self.scale.0 <= 0.0 || self.scale.1 < self.scale.0 {
            return Err("a scatter's scale must be (min, max) with 0 < min <= max".into());
        }
        let area = polygon_area(&self.boundary);
        if area <= 0.0 {
            return Err("a scatter's boundary encloses no area (its points are collinear or repeated)".into());
        }
        let most = self.most_trees();
        if most > (4 * MAX_TREES) as f64 {
            return Err(format!(
                "a scatter of spacing {} m over {area:.0} m² could place more than {MAX_TREES} trees",
                self.spacing
            ));
        }
        let cells = self.grid_cells();
        if cells > MAX_GRID_CELLS as f64 {
            return Err(format!(
                "a scatter's boundary spans {cells:.0} cells of its spacing ({} m), more than {MAX_GRID_CELLS}: a thin or stretched boundary for so small a spacing",
                self.spacing
            ));
        }
        Ok(())
    }

    /// An upper bound on the positions this scatter can sample: a Poisson-disk set at spacing r
    /// holds at most about 1.15 / r² points per unit area.
    pub fn most_trees(&self) -> f64 {
        polygon_area(&self.boundary) / (self.spacing as f64 * self.spacing as f64) * 1.2
    }

    /// The cells of the sampling grid (cell = spacing / √2 over the bounding box).
    fn grid_cells(&self) -> f64 {
        let (lo, hi) = self.bounds();
        let cell = self.spacing as f64 / std::f64::consts::SQRT_2;
        ((hi.x - lo.x) as f64 / cell + 2.0) * ((hi.y - lo.y) as f64 / cell + 2.0)
    }

    fn bounds(&self) -> (Vec2, Vec2) {
        self.boundary.iter().fold((Vec2::splat(f32::MAX), Vec2::splat(f32::MIN)), |(a, b), p| (a.min(*p), b.max(*p)))
    }

    /// The probability of a tree at `p` (x, z).
    pub fn probability(&self, noise: &Perlin, p: Vec2) -> f32 {
        let n = noise.get([(p.x / self.feature) as f64, (p.y / self.feature) as f64]) as f32;
        (self.coverage + self.contrast * n).clamp(0.0, 1.0)
    }

    /// The trees of this scatter (positions at height 0, put on the ground when spawned).
    pub fn trees(&self) -> Result<Vec<TreeDef>, crate::limits::InvalidScene> {
        self.trees_message().map_err(crate::limits::InvalidScene)
    }

    fn trees_message(&self) -> Result<Vec<TreeDef>, String> {
        self.validate()?;
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let noise = Perlin::new(self.seed as u32 ^ (self.seed >> 32) as u32);
        let (lo, hi) = self.bounds();
        let r = self.spacing;
        let cell = r / std::f32::consts::SQRT_2;
        let (gw, gh) = (((hi.x - lo.x) / cell).ceil() as usize + 1, ((hi.y - lo.y) / cell).ceil() as usize + 1);
        let mut grid: Vec<u32> = vec![u32::MAX; gw * gh];
        let at = |p: Vec2| (((p.x - lo.x) / cell) as usize, ((p.y - lo.y) / cell) as usize);
        let mut points: Vec<Vec2> = Vec::new();
        let mut active: Vec<u32> = Vec::new();
        // The first point: a random position inside the boundary.
        for _ in 0..10_000 {
            let p = lo + (hi - lo) * Vec2::new(rng.random::<f32>(), rng.random::<f32>());
            if inside(&self.boundary, p) {
                points.push(p);
                active.push(0);
                let (x, y) = at(p);
                grid[y * gw + x] = 0;
                break;
            }
        }
        while let Some(&k) = active.last() {
            let base = points[k as usize];
            let mut found = false;
            for _ in 0..30 {
                let a = rng.random::<f32>() * std::f32::consts::TAU;
                let d = r * (1.0 + rng.random::<f32>());
                let p = base + Vec2::new(libm::cosf(a), libm::sinf(a)) * d;
                if p.x < lo.x || p.y < lo.y || p.x > hi.x || p.y > hi.y || !inside(&self.boundary, p) {
                    continue;
                }
                let (x, y) = at(p);
                let mut clear = true;
                'near: for yy in y.saturating_sub(2)..(y + 3).min(gh) {
                    for xx in x.saturating_sub(2)..(x + 3).min(gw) {
                        let q = grid[yy * gw + xx];
                        if q != u32::MAX && points[q as usize].distance_squared(p) < r * r {
                            clear = false;
                            break 'near;
                        }
                    }
                }
                if clear {
                    grid[y * gw + x] = points.len() as u32;
                    active.push(points.len() as u32);
                    points.push(p);
                    found = true;
                    break;
                }
            }
            if !found {
                active.pop();
            }
        }
        let mut trees = Vec::new();
        for p in points {
            let keep = rng.random::<f32>() < self.probability(&noise, p);
            let model = &self.models[(rng.random::<u32>() as usize) % self.models.len()];
            let yaw_deg = rng.random::<f32>() * 360.0;
            let scale = self.scale.0 + (self.scale.1 - self.scale.0) * rng.random::<f32>();
            if keep {
                trees.push(TreeDef {
                    model: model.clone(),
                    position: Vec3::new(p.x, 0.0, p.y),
                    yaw_deg,
                    scale,
                    on_ground: true,
                });
            }
        }
        if trees.len() > MAX_TREES {
            return Err(format!("a scatter placed {} trees, more than {MAX_TREES}", trees.len()));
        }
        Ok(trees)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(size: f32) -> Vec<Vec2> {
        vec![Vec2::ZERO, Vec2::new(size, 0.0), Vec2::new(size, size), Vec2::new(0.0, size)]
    }

    fn def(coverage: f32, contrast: f32) -> ScatterDef {
        ScatterDef {
            models: vec!["a".into(), "b".into()],
            boundary: square(40.0),
            spacing: 2.0,
            coverage,
            contrast,
            feature: 8.0,
            scale: (0.8, 1.2),
            seed: 9,
        }
    }

    #[test]
    fn positions_keep_their_spacing_and_stay_inside() {
        let t = def(1.0, 0.0).trees().unwrap();
        // A maximal Poisson-disk set at spacing 2 fills a 40 m square with roughly 0.6–1.15 points per 4 m².
        assert!(t.len() > 200 && t.len() < 460, "{} trees", t.len());
        for (i, a) in t.iter().enumerate() {
            assert!(a.position.x >= 0.0 && a.position.x <= 40.0 && a.position.z >= 0.0 && a.position.z <= 40.0);
            assert!((0.8..=1.2).contains(&a.scale));
            for b in &t[i + 1..] {
                assert!(a.position.distance(b.position) >= 2.0 - 1e-4);
            }
        }
        // Same definition, same trees; another seed, other trees.
        assert_eq!(t, def(1.0, 0.0).trees().unwrap());
        assert_ne!(t, ScatterDef { seed: 10, ..def(1.0, 0.0) }.trees().unwrap());
    }

    #[test]
    fn the_noise_field_thins_the_trees() {
        let all = def(1.0, 0.0).trees().unwrap().len();
        assert_eq!(def(0.0, 0.0).trees().unwrap().len(), 0);
        let half = def(0.5, 0.0).trees().unwrap().len();
        assert!((half as f32 / all as f32 - 0.5).abs() < 0.1, "{half} of {all}");
        // With contrast, trees gather where the noise is high.
        let d = def(0.5, 2.0);
        let noise = Perlin::new(9);
        let t = d.trees().unwrap();
        let mean_p: f32 = t.iter().map(|x| d.probability(&noise, Vec2::new(x.position.x, x.position.z))).sum::<f32>()
            / t.len() as f32;
        assert!(mean_p > 0.6, "mean probability at the trees {mean_p}");
    }

    #[test]
    fn a_boundary_excludes_the_outside() {
        // A triangle: the half of the square below the diagonal x = z.
        let d = ScatterDef { boundary: vec![Vec2::ZERO, Vec2::new(40.0, 0.0), Vec2::new(40.0, 40.0)], ..def(1.0, 0.0) };
        let t = d.trees().unwrap();
        assert!(!t.is_empty());
        assert!(t.iter().all(|x| x.position.z <= x.position.x + 1e-4));
        assert!(ScatterDef { spacing: 0.001, ..def(1.0, 0.0) }.trees().is_err());
        assert!(ScatterDef { boundary: vec![Vec2::ZERO, Vec2::X], ..def(1.0, 0.0) }.trees().is_err());
    }

    #[test]
    fn hostile_scatters_are_refused_before_any_allocation() {
        // Collinear points: no area, whatever the spacing.
        let line = vec![Vec2::ZERO, Vec2::new(1000.0, 0.0), Vec2::new(2000.0, 0.0)];
        let e = ScatterDef { boundary: line, spacing: 1e-9, ..def(1.0, 0.0) }.validate().unwrap_err().to_string();
        assert!(e.contains("spacing"), "{e}");
        let line = vec![Vec2::ZERO, Vec2::new(1000.0, 0.0), Vec2::new(2000.0, 0.0)];
        let e = ScatterDef { boundary: line, ..def(1.0, 0.0) }.validate().unwrap_err().to_string();
        assert!(e.contains("no area"), "{e}");
        // A sliver: a tiny area but a huge bounding box at a small spacing.
        let sliver = vec![Vec2::ZERO, Vec2::new(1.0e4, 1.0e4), Vec2::new(1.0e4, 1.0e4 + 0.01)];
        let e = ScatterDef { boundary: sliver, spacing: 0.05, ..def(1.0, 0.0) }.validate().unwrap_err().to_string();
        assert!(e.contains("cells"), "{e}");
        for bad in [
            ScatterDef { feature: 1e-30, ..def(1.0, 0.0) },
            ScatterDef { scale: (1e30, 1e30), ..def(1.0, 0.0) },
            ScatterDef { coverage: 2.0, ..def(1.0, 0.0) },
        ] {
            let e = bad.validate().unwrap_err().to_string();
            assert!(e.contains("within"), "{e}");
        }
        assert_eq!(polygon_area(&square(40.0)), 1600.0);
    }
}
