//! The vertices and triangles of a scene's plane shapes (`scene::PlaneShape`): a mesh as written,
//! a grid raised by Perlin noise with the triangles in its holes left out, or cut exactly at the
//! holes' rims. Used by the simulation's ground and by the renderer's banks, through `scene`.

use glam::{Vec2, Vec3};
use noise::{NoiseFn, Perlin};

use crate::scene::PlaneShape;

/// Builds the vertices and triangles of a plane shape, with its holes cut exactly where
/// `exact_holes` ([`Scene::exact_holes`]).
pub fn plane_geometry_cut(shape: &PlaneShape, exact_holes: bool) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let (mut vertices, mut triangles) = plane_geometry(shape);
    if let (true, PlaneShape::Grid { min, size, cell, elevation, unevenness, noise_seed, holes }) = (exact_holes, shape) {
        let plain = PlaneShape::Grid { min: *min, size: *size, cell: *cell, elevation: *elevation, unevenness: *unevenness, noise_seed: *noise_seed, holes: Vec::new() };
        let full = plane_geometry(&plain).1;
        let perlin = Perlin::new(*noise_seed);
        let height = |q: Vec2| elevation + unevenness * perlin.get([q.x as f64 * 0.23, q.y as f64 * 0.23]) as f32;
        triangles = crate::holes::cut_rims(&mut vertices, triangles, &full, holes, *cell, &height);
    }
    (vertices, triangles)
}

/// Builds the vertices and triangles of a plane shape.
pub fn plane_geometry(shape: &PlaneShape) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    match shape {
        PlaneShape::Mesh { vertices, triangles } => (vertices.clone(), triangles.clone()),
        PlaneShape::Grid { min, size, cell, elevation, unevenness, noise_seed, holes } => {
            let nx = (size.x / cell).ceil().max(1.0) as u32;
            let nz = (size.y / cell).ceil().max(1.0) as u32;
            let perlin = Perlin::new(*noise_seed);
            let mut vertices = Vec::with_capacity(((nx + 1) * (nz + 1)) as usize);
            for j in 0..=nz {
                for i in 0..=nx {
                    let x = min.x + size.x * i as f32 / nx as f32;
                    let z = min.y + size.y * j as f32 / nz as f32;
                    let n = perlin.get([x as f64 * 0.23, z as f64 * 0.23]) as f32;
                    vertices.push(Vec3::new(x, elevation + unevenness * n, z));
                }
            }
            let idx = |i: u32, j: u32| j * (nx + 1) + i;
            // A triangle is left out when its centre lies in a hole; `holes::hole_mask` finds
            // them in time proportional to the cells plus the holes' extent along one axis.
            let centre = |i: u32, j: u32, upper: bool| {
                let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
                let tri = if upper { [b, d, c] } else { [a, d, b] };
                let p = (vertices[tri[0] as usize] + vertices[tri[1] as usize] + vertices[tri[2] as usize]) / 3.0;
                Vec2::new(p.x, p.z)
            };
            let grid = crate::holes::GridFrame { min: *min, size: *size, nx, nz };
            let in_hole = crate::holes::hole_mask(&grid, holes, &centre);
            let mut triangles = Vec::with_capacity((nx * nz * 2) as usize);
            for j in 0..nz {
                for i in 0..nx {
                    let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
                    // Counter-clockwise seen from above (+Y), so the normal points up.
                    for (k, tri) in [[a, d, b], [b, d, c]].into_iter().enumerate() {
                        if !in_hole[((j * nx + i) * 2) as usize + k] {
                            triangles.push(tri);
                        }
                    }
                }
            }
            (vertices, triangles)
        }
    }
}
