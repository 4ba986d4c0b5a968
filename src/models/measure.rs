//! What a bank's catalogue says about a model, computed from its mesh as the renderer loads it:
//! bounds, lowest point, pick shape, crown radius, triangles, and a guess at its kind.

use glam::{Vec2, Vec3};
use grove_systems::catalogue::{ModelKind, PickShape};

use super::mesh::ModelData;
use super::pick::pick_shape;

/// The mean area of an alpha-clipped triangle from which a model counts as a billboard, square
/// metres. grove's own leaf geometry averages 0.004 to 0.010 m² a triangle, its cards 0.1 to
/// 1.9 m² (measured over `assets/trees`); the threshold sits between, a factor of three from each.
pub const CARD_AREA: f32 = 0.03;

/// The measurements of one model, in model space (metres, +Y up).
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// Minimum corner of the axis-aligned bounds of every drawn vertex; `y` is the lowest point.
    pub bounds_min: Vec3,
    /// Maximum corner of the bounds.
    pub bounds_max: Vec3,
    /// The largest horizontal distance of any vertex from the Y axis, metres.
    pub crown_radius: f32,
    /// Drawn triangles.
    pub triangles: u32,
    /// The pick shape ([`super::pick`]).
    pub pick: PickShape,
    /// The kind guessed from the mesh: [`ModelKind::Billboard`] when the triangles of its
    /// alpha-clipped materials are cards, on average at least [`CARD_AREA`] each;
    /// [`ModelKind::Mesh`] otherwise (leaves as geometry, or no clipped material at all).
    pub kind: ModelKind,
    /// Whether every vertex carried its own `_WIND` channels.
    pub own_wind: bool,
}

/// The horizontal radius of a set of meshes around the trunk axis: the largest distance of any
/// vertex from the Y axis, metres.
pub fn crown_radius<'a>(meshes: impl IntoIterator<Item = &'a [Vec3]>) -> f32 {
    meshes.into_iter().flatten().map(|p| Vec2::new(p.x, p.z).length()).fold(0.0, f32::max)
}

/// Measures a loaded model.
pub fn measure(data: &ModelData) -> Measured {
    let positions: Vec<Vec<Vec3>> =
        data.primitives.iter().map(|p| p.vertices.iter().map(|v| Vec3::from(v.position)).collect()).collect();
    let meshes: Vec<(&[Vec3], &[u32])> =
        positions.iter().zip(&data.primitives).map(|(p, prim)| (p.as_slice(), prim.indices.as_slice())).collect();
    let pick = pick_shape(&meshes);
    let crown_radius = crown_radius(positions.iter().map(|p| p.as_slice()));
    let triangles = data.triangles() as u32;
    let (mut clipped, mut area) = (0usize, 0.0f64);
    for p in data.primitives.iter().filter(|p| data.materials.get(p.material).is_some_and(|m| m.alpha_cutoff.is_some()))
    {
        for t in p.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| Vec3::from(p.vertices[i as usize].position));
            area += 0.5 * (b - a).cross(c - a).length() as f64;
            clipped += 1;
        }
    }
    let kind =
        if clipped > 0 && area / clipped as f64 >= CARD_AREA as f64 { ModelKind::Billboard } else { ModelKind::Mesh };
    Measured {
        bounds_min: data.bounds.0,
        bounds_max: data.bounds.1,
        crown_radius,
        triangles,
        pick,
        kind,
        own_wind: data.own_wind,
    }
}
