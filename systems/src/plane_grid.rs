//! A plane's triangle mesh for ray casts: parry3d's `TriMesh` (with its BVH), and the same
//! triangles bucketed by a uniform grid of cells over the ground (X, Z), so that a ray is
//! tested only against the triangles of the cells it passes through at their height.
//!
//! The grid only finds candidates faster: each candidate is tested with parry's own triangle
//! ray test, and the hit is returned only when it is provably the hit that parry's BVH search
//! (`TriMesh::cast_local_ray_and_get_normal`) returns, bit for bit. That search keeps the
//! first triangle it meets at the smallest distance and skips a node whose box the ray enters
//! no nearer than the best hit so far; so the grid's nearest hit is returned when it is
//! strictly nearer than every other triangle's hit, and the ray enters its triangle's leaf box
//! (parry's own box test, which no enclosing node's box can fail when the leaf's passes) before
//! every other hit and the limit. Anything else (a tie, an edge case of rounding, a ray or
//! plane the grid does not cover) is answered by parry's search itself.
//!
//! A cell holds the triangles whose bounding box overlaps it; the walk visits every cell within
//! a margin of the ray (far larger than single-precision rounding at the scene's scale), in
//! order along the ray, until it is past the best hit; a cell whose triangles all lie above or
//! below the ray there is not tested.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use parry3d::query::{Ray, RayCast, RayIntersection};
use parry3d::shape::{TriMesh, TriMeshFlags};

use crate::components::Plane;

/// A plane's mesh for ray casts: parry's triangle mesh and the grid of its triangles.
pub struct PlaneMesh {
    mesh: TriMesh,
    grid: Option<CellGrid>,
}

/// The triangles of a mesh bucketed by cells of the X–Z plane.
struct CellGrid {
    /// The corner of cell (0, 0): the smallest X and Z of the mesh.
    min: Vec2,
    /// The side of a cell, metres.
    cell: f32,
    /// Cells along X and along Z.
    nx: usize,
    nz: usize,
    /// Per cell (`iz * nx + ix`), where its triangles start in `tris`; one more at the end.
    starts: Vec<u32>,
    /// The triangles of each cell in turn.
    tris: Vec<u32>,
    /// Per cell, the lowest and highest Y of its triangles.
    heights: Vec<[f32; 2]>,
    /// The mesh's bounding box.
    lo: Vec3,
    hi: Vec3,
    /// The largest absolute coordinate of the mesh, for the walk's margin.
    scale: f32,
}

/// At most this many cells per triangle (a mesh of long thin triangles gets no grid).
const CELLS_PER_TRIANGLE: usize = 4;
/// Meshes with fewer triangles are searched by parry alone.
const MIN_TRIANGLES: usize = 16;

impl PlaneMesh {
    /// The mesh of a plane; `None` if it has no valid triangle.
    pub fn new(plane: &Plane) -> Option<PlaneMesh> {
        let mesh = plane_trimesh(plane)?;
        let grid = CellGrid::new(&mesh);
        Some(PlaneMesh { mesh, grid })
    }

    /// parry's triangle mesh.
    pub fn trimesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// Whether casts use the grid (a mesh too small or too odd for one has none).
    pub fn has_grid(&self) -> bool {
        self.grid.is_some()
    }

    /// The nearest hit within `limit` (strictly nearer), the very value of
    /// `self.trimesh().cast_local_ray_and_get_normal(ray, limit, false)`.
    pub fn cast(&self, ray: &Ray, limit: f32) -> Option<RayIntersection> {
        match self.cast_by_grid(ray, limit) {
            Some(answer) => answer,
            None => self.cast_plain(ray, limit),
        }
    }

    /// The grid's answer, where it is certain to be parry's (`None`: parry's search must give
    /// it; always `None` without a grid).
    pub fn cast_by_grid(&self, ray: &Ray, limit: f32) -> Option<Option<RayIntersection>> {
        self.grid.as_ref().and_then(|g| g.cast(&self.mesh, ray, limit))
    }

    /// The same as [`PlaneMesh::cast`] through parry's BVH search alone: the reference.
    pub fn cast_plain(&self, ray: &Ray, limit: f32) -> Option<RayIntersection> {
        self.mesh.cast_local_ray_and_get_normal(ray, limit, false)
    }
}

/// A parry3d triangle mesh for a plane; `None` if it has no valid triangle.
pub fn plane_trimesh(plane: &Plane) -> Option<TriMesh> {
    if plane.triangles.is_empty() {
        return None;
    }
    TriMesh::with_flags(plane.vertices.clone(), plane.triangles.clone(), TriMeshFlags::empty()).ok()
}

/// [`PlaneMesh::new`], built once per process for each distinct plane (found by its
/// [`crate::components::plane_hash`], then compared whole): every recording of a study starts
/// from the same planes, and building their meshes' trees was a twentieth of a replay's time.
/// The mesh is a pure function of the plane, so sharing it changes nothing a simulation computes.
pub fn shared_plane_mesh(plane: &Plane) -> Option<Arc<PlaneMesh>> {
    use std::collections::HashMap;
    use std::sync::{Mutex, OnceLock};
    type Cache = Mutex<HashMap<u64, Vec<(Plane, Arc<PlaneMesh>)>>>;
    static CACHE: OnceLock<Cache> = OnceLock::new();
    /// At most this many planes are kept; past it the cache starts again.
    const MAX_PLANES: usize = 64;
    let key = crate::components::plane_hash(plane);
    let cache = CACHE.get_or_init(Cache::default);
    if let Ok(map) = cache.lock()
        && let Some(found) = map.get(&key).and_then(|v| v.iter().find(|(p, _)| p == plane))
    {
        return Some(found.1.clone());
    }
    let mesh = Arc::new(PlaneMesh::new(plane)?);
    if let Ok(mut map) = cache.lock() {
        if map.values().map(Vec::len).sum::<usize>() >= MAX_PLANES {
            map.clear();
        }
        map.entry(key).or_default().push((plane.clone(), mesh.clone()));
    }
    Some(mesh)
}

/// The nearest candidate so far: triangle, distance, the entry distance of its leaf box, the hit.
#[derive(Clone, Copy)]
struct Best {
    tri: u32,
    toi: f32,
    entry: f32,
    hit: RayIntersection,
}

impl CellGrid {
    fn new(mesh: &TriMesh) -> Option<CellGrid> {
        let n = mesh.num_triangles();
        if n < MIN_TRIANGLES || n > u32::MAX as usize / 2 {
            return None;
        }
        let boxes: Vec<[Vec3; 2]> = mesh.triangles().map(|t| [t.a.min(t.b).min(t.c), t.a.max(t.b).max(t.c)]).collect();
        let (lo, hi) = boxes.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), b| (lo.min(b[0]), hi.max(b[1])));
        if !lo.is_finite() || !hi.is_finite() {
            return None;
        }
        let size = Vec2::new(hi.x - lo.x, hi.z - lo.z);
        // A cell as wide as the median triangle: a regular grid's own cells.
        let mut widths: Vec<f32> = boxes.iter().map(|b| (b[1].x - b[0].x).max(b[1].z - b[0].z)).collect();
        let mid = widths.len() / 2;
        let cell = *widths.select_nth_unstable_by(mid, f32::total_cmp).1;
        if !(cell > 0.0) || !(size.x > 0.0) || !(size.y > 0.0) {
            return None;
        }
        let count = |extent: f32| (extent / cell).ceil().max(1.0);
        let (fx, fz) = (count(size.x), count(size.y));
        if fx * fz > (CELLS_PER_TRIANGLE * n) as f32 {
            return None;
        }
        let (nx, nz) = (fx as usize, fz as usize);
        let min = Vec2::new(lo.x, lo.z);
        // The cells a box overlaps, as a half-open range of cells: a triangle that only touches
        // a cell's edge is not in it (the walk's margin reaches across such edges).
        let span = |a: f32, b: f32, origin: f32, cells: usize| {
            let first = ((a - origin) / cell).floor().clamp(0.0, (cells - 1) as f32) as usize;
            let last = (((b - origin) / cell).ceil() - 1.0).clamp(0.0, (cells - 1) as f32) as usize;
            (first, last.max(first))
        };
        let mut counts = vec![0u32; nx * nz + 1];
        let mut heights = vec![[f32::INFINITY, f32::NEG_INFINITY]; nx * nz];
        let cells_of = |b: &[Vec3; 2]| {
            let (x0, x1) = span(b[0].x, b[1].x, min.x, nx);
            let (z0, z1) = span(b[0].z, b[1].z, min.y, nz);
            (z0..=z1).flat_map(move |iz| (x0..=x1).map(move |ix| iz * nx + ix))
        };
        for b in &boxes {
            for c in cells_of(b) {
                counts[c + 1] += 1;
                heights[c] = [heights[c][0].min(b[0].y), heights[c][1].max(b[1].y)];
            }
        }
        for c in 0..nx * nz {
            counts[c + 1] += counts[c];
        }
        let mut fill = counts.clone();
        let mut tris = vec![0u32; counts[nx * nz] as usize];
        for (i, b) in boxes.iter().enumerate() {
            for c in cells_of(b) {
                tris[fill[c] as usize] = i as u32;
                fill[c] += 1;
            }
        }
        let scale = lo.abs().max(hi.abs()).max_element();
        Some(CellGrid { min, cell, nx, nz, starts: counts, tris, heights, lo, hi, scale })
    }

    /// The cast through the grid: `Some(answer)` when the answer is certain to be parry's,
    /// `None` when parry's search must give it.
    fn cast(&self, mesh: &TriMesh, ray: &Ray, limit: f32) -> Option<Option<RayIntersection>> {
        let (o, d) = (ray.origin, ray.dir);
        if !o.is_finite() || !d.is_finite() || !(limit > 0.0) || limit > crate::limits::MAX_COORD {
            return None;
        }
        // The margin: far above single-precision rounding at the scale of the scene and the ray's
        // origin (a point of the ray inside the grid is no larger than both together).
        let eps = 1.0e-3 + 1.0e-4 * (self.scale + o.abs().max_element());
        // The stretch of the ray inside the mesh's box (grown by the margin): no triangle can be
        // hit elsewhere.
        let (mut t0, mut t1) = (0.0f32, limit);
        for (o, d, lo, hi) in
            [(o.x, d.x, self.lo.x, self.hi.x), (o.y, d.y, self.lo.y, self.hi.y), (o.z, d.z, self.lo.z, self.hi.z)]
        {
            let (lo, hi) = (lo - eps, hi + eps);
            if d == 0.0 {
                if o < lo || o > hi {
                    return Some(None);
                }
            } else {
                let (p, q) = ((lo - o) / d, (hi - o) / d);
                t0 = t0.max(p.min(q));
                t1 = t1.min(p.max(q));
            }
        }
        if t0 > t1 {
            return Some(None);
        }
        // Walk along the axis the ray moves along most; `u` is that axis, `v` the other one.
        let along_x = d.x.abs() >= d.z.abs();
        let (ou, du, ov, dv) = if along_x { (o.x, d.x, o.z, d.z) } else { (o.z, d.z, o.x, d.x) };
        let (min_u, min_v, nu, nv) = if along_x {
            (self.min.x, self.min.y, self.nx, self.nz)
        } else {
            (self.min.y, self.min.x, self.nz, self.nx)
        };
        let cell_of = |iu: usize, iv: usize| if along_x { iv * self.nx + iu } else { iu * self.nx + iv };
        // The cell holding a coordinate, -1 before the first and `cells` after the last (a
        // truncation, which is the floor for the non-negative values it is used on).
        let index = |x: f32, origin: f32, cells: usize| {
            let f = (x - origin) / self.cell;
            if !(f >= 0.0) {
                -1
            } else if f >= cells as f32 {
                cells as isize
            } else {
                f as isize
            }
        };
        // The columns of that stretch.
        let (u0, u1) = (ou + du * t0, ou + du * t1);
        let (first, last) =
            (index(u0.min(u1) - eps, min_u, nu).max(0), index(u0.max(u1) + eps, min_u, nu).min(nu as isize - 1));
        if first > last {
            return Some(None);
        }
        let mut best: Option<Best> = None;
        // The nearest hit on a triangle other than the best one.
        let mut second = f32::INFINITY;
        // The walk goes on while a column can hold a hit nearer than this.
        let mut bound = limit;
        for step in 0..=last - first {
            let iu = if du >= 0.0 { first + step } else { last - step };
            let (a, b) = (min_u + self.cell * iu as f32 - eps, min_u + self.cell * (iu + 1) as f32 + eps);
            let (ta, tb) = if du == 0.0 {
                if ou < a || ou > b {
                    continue;
                }
                (t0, t1)
            } else {
                let (p, q) = ((a - ou) / du, (b - ou) / du);
                (p.min(q).max(t0), p.max(q).min(t1))
            };
            if ta > bound {
                break;
            }
            if ta > tb {
                continue;
            }
            let (va, vb) = (ov + dv * ta, ov + dv * tb);
            let (y0, y1) = (o.y + d.y * ta, o.y + d.y * tb);
            let (ylo, yhi) = (y0.min(y1) - eps, y0.max(y1) + eps);
            let (j0, j1) =
                (index(va.min(vb) - eps, min_v, nv).max(0), index(va.max(vb) + eps, min_v, nv).min(nv as isize - 1));
            for iv in j0..=j1 {
                let c = cell_of(iu as usize, iv as usize);
                let [lo, hi] = self.heights[c];
                if hi < ylo || lo > yhi {
                    continue;
                }
                for &tri in &self.tris[self.starts[c] as usize..self.starts[c + 1] as usize] {
                    if best.is_some_and(|b| b.tri == tri) {
                        continue;
                    }
                    let Some(hit) = mesh.triangle(tri).cast_local_ray_and_get_normal(ray, f32::MAX, false) else {
                        continue;
                    };
                    let toi = hit.time_of_impact;
                    if !(toi < limit) {
                        continue;
                    }
                    match best {
                        Some(b) if toi >= b.toi => second = second.min(toi),
                        _ => {
                            if let Some(b) = best {
                                second = second.min(b.toi);
                            }
                            // parry's own box test of the triangle's leaf, as its search runs it.
                            let entry = mesh.bvh().leaf_node(tri).map_or(f32::MAX, |leaf| leaf.cast_ray(ray, f32::MAX));
                            if entry == f32::MAX {
                                return None;
                            }
                            best = Some(Best { tri, toi, entry, hit });
                            bound = limit.min(toi.max(entry));
                        }
                    }
                }
            }
        }
        match best {
            None => Some(None),
            Some(b) if b.toi < second && b.entry < second && b.entry < limit => Some(Some(b.hit.with_subshape(b.tri))),
            Some(_) => None,
        }
    }
}
