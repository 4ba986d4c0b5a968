//! The ground's extract: the planes' key, their meshes when the key differs from the one the
//! ground was built from, and the bounds of every plane vertex (the shadow map's fit).

use glam::Vec3;
use grove_systems::Sim;

/// Identifies the planes' geometry: per plane, sorted by entity, its entity bits and its vertex
/// and triangle counts. The ground mesh is rebuilt only when this changes.
pub(crate) type GroundKey = Vec<(u64, usize, usize)>;

/// One plane's mesh: world positions (metres) and counter-clockwise triangles.
pub(crate) struct PlaneMesh {
    /// Vertex positions, world metres.
    pub vertices: Vec<Vec3>,
    /// Triangles as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

/// The ground's data of a frame.
pub(crate) struct Planes {
    /// The planes' key.
    pub key: GroundKey,
    /// The planes' meshes, sorted by entity; only when `key` differs from the one the ground
    /// already has.
    pub meshes: Option<Vec<PlaneMesh>>,
    /// The bounds of every plane vertex, metres.
    pub bounds: Option<(Vec3, Vec3)>,
}

/// The planes of `sim`; their meshes only when their key differs from `have`.
pub(crate) fn planes(sim: &Sim, have: &GroundKey) -> Planes {
    let mut key: GroundKey = Vec::new();
    let mut bounds: Option<(Vec3, Vec3)> = None;
    sim.for_each_plane(|id, p| {
        key.push((id, p.vertices.len(), p.triangles.len()));
        for v in &p.vertices {
            bounds = Some(bounds.map_or((*v, *v), |(a, b)| (a.min(*v), b.max(*v))));
        }
    });
    key.sort_unstable();
    let meshes = (&key != have).then(|| {
        let mut planes: Vec<(u64, PlaneMesh)> = Vec::new();
        sim.for_each_plane(|id, p| {
            planes.push((id, PlaneMesh { vertices: p.vertices.clone(), triangles: p.triangles.clone() }))
        });
        planes.sort_by_key(|(e, _)| *e);
        planes.into_iter().map(|(_, p)| p).collect()
    });
    Planes { key, meshes, bounds }
}
