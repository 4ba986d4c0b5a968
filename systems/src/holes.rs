//! Which triangles of a grid plane lie in a hole, in time proportional to the cells plus the
//! holes' extent along the grid's shorter axis, rather than cells times holes.
//!
//! A grid plane (see [`crate::scene::PlaneShape::Grid`]) has `nx × nz` cells, each split into a
//! lower triangle (centre about a third into the cell along X and Z) and an upper one (about two
//! thirds). The triangle centres therefore lie on straight lines: for each row `j` of cells, one
//! line of lower centres and one of upper centres, all with the same Z. A circular hole covers
//! one contiguous run of every such line. For each hole and each line it crosses, the run is
//! estimated from the circle's equation and then settled with the exact test that the plane
//! has always used (`centre.distance(hole.center) < hole.radius` in single precision), so the
//! result is the same triangle for triangle as testing every triangle against every hole. The
//! runs are accumulated in a difference array per line. Lines run along the grid's longer
//! axis, so a hole costs at most two lines per cell along the shorter one.
//!
//! Units: metres, X and Z of the ground plane (the `Vec2`'s `y` is Z).

use glam::Vec2;

use crate::scene::Hole;

/// The frame of a grid plane: its rectangle and its number of cells along X and Z.
#[derive(Clone, Copy, Debug)]
pub struct GridFrame {
    /// Minimum corner (X, Z), metres.
    pub min: Vec2,
    /// Size along X and Z, metres.
    pub size: Vec2,
    /// Cells along X.
    pub nx: u32,
    /// Cells along Z.
    pub nz: u32,
}

/// Marks the triangles whose centre lies in a hole. `centre(i, j, upper)` is the exact centre
/// (X, Z) of the lower (`upper == false`) or upper triangle of cell `(i, j)`, as the plane
/// builds it. The result has one entry per triangle, index `(j * nx + i) * 2 + upper`.
pub fn hole_mask(grid: &GridFrame, holes: &[Hole], centre: &dyn Fn(u32, u32, bool) -> Vec2) -> Vec<bool> {
    let (nx, nz) = (grid.nx as usize, grid.nz as usize);
    let mut mask = vec![false; nx * nz * 2];
    if holes.is_empty() || nx == 0 || nz == 0 {
        return mask;
    }
    // Lines run along the longer axis: `rows` means lines of constant Z (index j) along X.
    let rows = nx >= nz;
    let (n_along, n_across) = if rows { (nx, nz) } else { (nz, nx) };
    // The exact centre of the triangle at position `m` along line `(n, upper)`.
    let at = |n: usize, upper: bool, m: usize| if rows { centre(m as u32, n as u32, upper) } else { centre(n as u32, m as u32, upper) };
    let along = |p: Vec2| if rows { p.x } else { p.y };
    let across = |p: Vec2| if rows { p.y } else { p.x };
    let (min_along, min_across) = if rows { (grid.min.x, grid.min.y) } else { (grid.min.y, grid.min.x) };
    let (size_along, size_across) = if rows { (grid.size.x, grid.size.y) } else { (grid.size.y, grid.size.x) };
    let cell_along = size_along as f64 / n_along as f64;
    let cell_across = size_across as f64 / n_across as f64;
    // Difference arrays: +1 where a hole's run starts on a line, -1 just after it ends.
    let width = n_along + 1;
    let mut diff = vec![0i32; 2 * n_across * width];
    for h in holes {
        if h.radius.is_nan() || h.radius <= 0.0 {
            continue;
        }
        let inside = |p: Vec2| p.distance(h.center) < h.radius;
        let r = h.radius as f64;
        let (c_along, c_across) = (along(h.center) as f64, across(h.center) as f64);
        for upper in [false, true] {
            let f = if upper { 2.0 / 3.0 } else { 1.0 / 3.0 };
            // The lines whose centres are within the radius across, with a line to spare.
            let first = ((c_across - r - min_across as f64) / cell_across - f).floor() - 1.0;
            let last = ((c_across + r - min_across as f64) / cell_across - f).ceil() + 1.0;
            if last < 0.0 || first > (n_across - 1) as f64 {
                continue;
            }
            let (first, last) = (first.max(0.0) as usize, last.min((n_across - 1) as f64) as usize);
            for n in first..=last {
                let d = across(at(n, upper, 0)) as f64 - c_across;
                let w = (r * r - d * d).max(0.0).sqrt();
                let lo = ((c_along - w - min_along as f64) / cell_along - f).floor() - 1.0;
                let hi = ((c_along + w - min_along as f64) / cell_along - f).ceil() + 1.0;
                if hi < 0.0 || lo > (n_along - 1) as f64 {
                    continue;
                }
                let (mut lo, mut hi) = (lo.max(0.0) as usize, hi.min((n_along - 1) as f64) as usize);
                let exact = |m: usize| inside(at(n, upper, m));
                // Settle the run's start with the exact test: outwards while inside, inwards
                // while outside.
                if exact(lo) {
                    while lo > 0 && exact(lo - 1) {
                        lo -= 1;
                    }
                } else {
                    while lo <= hi && !exact(lo) {
                        lo += 1;
                    }
                    if lo > hi {
                        continue;
                    }
                }
                // And its end; `exact(lo)` holds, so this stops at `lo` at the latest.
                if exact(hi) {
                    while hi + 1 < n_along && exact(hi + 1) {
                        hi += 1;
                    }
                } else {
                    while !exact(hi) {
                        hi -= 1;
                    }
                }
                let line = (n * 2 + upper as usize) * width;
                diff[line + lo] += 1;
                diff[line + hi + 1] -= 1;
            }
        }
    }
    for n in 0..n_across {
        for upper in [false, true] {
            let line = (n * 2 + upper as usize) * width;
            let mut depth = 0;
            for m in 0..n_along {
                depth += diff[line + m];
                if depth > 0 {
                    let (i, j) = if rows { (m, n) } else { (n, m) };
                    mask[(j * nx + i) * 2 + upper as usize] = true;
                }
            }
        }
    }
    mask
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{plane_geometry, PlaneShape};

    /// Every triangle tested against every hole: the definition the mask must match. Returns
    /// the number of triangles kept.
    fn brute_force(shape: &PlaneShape) -> usize {
        let PlaneShape::Grid { min, size, cell, elevation, unevenness, noise_seed, holes } = shape.clone() else { unreachable!() };
        let plain = PlaneShape::Grid { min, size, cell, elevation, unevenness, noise_seed, holes: vec![] };
        let (vertices, all) = plane_geometry(&plain);
        all.iter()
            .filter(|t| {
                let p = (vertices[t[0] as usize] + vertices[t[1] as usize] + vertices[t[2] as usize]) / 3.0;
                !holes.iter().any(|h| Vec2::new(p.x, p.z).distance(h.center) < h.radius)
            })
            .count()
    }

    #[test]
    fn the_mask_matches_testing_every_triangle_against_every_hole() {
        // A small linear congruential generator, so the test needs no RNG crate.
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut rnd = || {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (x >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut checked = 0;
        for case in 0..60 {
            let min = Vec2::new(rnd() * 200.0 - 100.0, rnd() * 200.0 - 100.0);
            // Wide, tall and square grids, so both line directions are exercised.
            let size = match case % 3 {
                0 => Vec2::new(5.0 + rnd() * 40.0, 2.0 + rnd() * 5.0),
                1 => Vec2::new(2.0 + rnd() * 5.0, 5.0 + rnd() * 40.0),
                _ => Vec2::splat(5.0 + rnd() * 20.0),
            };
            let cell = 0.1 + rnd() * 0.9;
            let holes: Vec<Hole> = (0..(case % 7) * 3)
                .map(|_| Hole { center: min + Vec2::new(rnd() * size.x * 1.4 - size.x * 0.2, rnd() * size.y * 1.4 - size.y * 0.2), radius: rnd() * rnd() * size.max_element() * 0.5 })
                .collect();
            let shape = PlaneShape::Grid { min, size, cell, elevation: 0.3, unevenness: 0.2, noise_seed: case, holes };
            let (_, kept) = plane_geometry(&shape);
            let expected = brute_force(&shape);
            assert_eq!(kept.len(), expected, "case {case}: {shape:?}");
            checked += expected;
        }
        assert!(checked > 1000, "the cases hold triangles");
    }

    #[test]
    fn a_hole_larger_than_the_plane_removes_every_triangle_and_a_far_one_none() {
        let grid = |holes| PlaneShape::Grid { min: Vec2::new(-2.0, -3.0), size: Vec2::new(4.0, 6.0), cell: 0.5, elevation: 0.0, unevenness: 0.0, noise_seed: 0, holes };
        let (_, t) = plane_geometry(&grid(vec![Hole { center: Vec2::ZERO, radius: 100.0 }]));
        assert!(t.is_empty());
        let (_, t) = plane_geometry(&grid(vec![Hole { center: Vec2::new(50.0, 0.0), radius: 10.0 }]));
        assert_eq!(t.len(), 8 * 12 * 2);
    }
}
