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

use glam::{Vec2, Vec3};

use serde::{Deserialize, Serialize};

/// A circular hole in a grid plane.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hole {
    /// Centre (X, Z), metres.
    pub center: Vec2,
    /// Radius, metres.
    pub radius: f32,
}

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
    let at = |n: usize, upper: bool, m: usize| {
        if rows { centre(m as u32, n as u32, upper) } else { centre(n as u32, m as u32, upper) }
    };
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

/// Cuts the holes of a grid plane exactly: moves the vertices on the rims of `holes` onto the
/// holes' circles, so that each rim is a polygon inscribed in its circle instead of a zigzag
/// along the grid's triangles (whose tips, where a diagonal crosses the circle, read as spikes).
/// A rim vertex is one shared by a kept triangle (`kept`) and a left-out one (in `all`, the
/// grid's every triangle, but not in `kept`); it moves along the line from the nearest hole's
/// centre onto that circle, where that is within `cell` of it, and takes the plane's height there
/// (`height`). A kept triangle that this leaves with less than a hundredth of a cell's area, or
/// turned over (a sliver between the circle and its chord), is left out too, and the rims it
/// uncovers are moved in turn. Returns the kept triangles.
pub fn cut_rims(
    vertices: &mut [Vec3],
    mut kept: Vec<[u32; 3]>,
    all: &[[u32; 3]],
    holes: &[Hole],
    cell: f32,
    height: &dyn Fn(Vec2) -> f32,
) -> Vec<[u32; 3]> {
    let n = vertices.len();
    let mut moved = vec![false; n];
    for _ in 0..4 {
        let (mut on_kept, mut on_cut) = (vec![false; n], vec![false; n]);
        for t in &kept {
            for &i in t {
                on_kept[i as usize] = true;
            }
        }
        let kept_set: std::collections::HashSet<[u32; 3]> = kept.iter().copied().collect();
        for t in all.iter().filter(|t| !kept_set.contains(*t)) {
            for &i in t {
                on_cut[i as usize] = true;
            }
        }
        for (k, v) in vertices.iter_mut().enumerate() {
            if moved[k] || !(on_kept[k] && on_cut[k]) {
                continue;
            }
            let q = Vec2::new(v.x, v.z);
            let nearest = holes.iter().min_by(|a, b| {
                (q.distance(a.center) - a.radius).abs().total_cmp(&(q.distance(b.center) - b.radius).abs())
            });
            let Some(h) = nearest else { continue };
            let off = q - h.center;
            if off.length() < 1e-6 || (off.length() - h.radius).abs() > cell {
                continue;
            }
            let on = h.center + off.normalize() * h.radius;
            *v = Vec3::new(on.x, height(on), on.y);
            moved[k] = true;
        }
        let before = kept.len();
        let area = |t: &[u32; 3]| {
            let p = |i: u32| Vec2::new(vertices[i as usize].x, vertices[i as usize].z);
            // Counter-clockwise seen from above (+Y) in (x, z) is clockwise: the sign flips.
            -(p(t[1]) - p(t[0])).perp_dot(p(t[2]) - p(t[0])) * 0.5
        };
        kept.retain(|t| area(t) > 0.01 * cell * cell);
        if kept.len() == before {
            break;
        }
    }
    kept
}
