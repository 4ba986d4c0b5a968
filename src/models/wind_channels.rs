//! Wind channels (`_WIND`, docs/assets.md) for a model that has none, computed when it is loaded
//! (docs/model-bank.md), so that any tree sways:
//!
//! - the mesh is split into connected parts: triangles join vertices, and vertices at the same
//!   position (to a millimetre) join across primitives;
//! - the part that holds the lowest vertex is the trunk;
//! - x: the height above the model's lowest point, metres (the trunk's lean grows with it);
//! - y: the horizontal distance from the trunk axis (model Y axis), metres, for every part but
//!   the trunk (0 on the trunk, as on grove's own models); a model of one part gets it everywhere;
//! - z: on alpha-clipped parts (leaf cards), the distance from the part's vertex nearest the
//!   trunk axis, where the card hangs, metres; 0 elsewhere;
//! - w: a phase in [0, 1) per part, from its number (parts numbered by their first vertex), 0 on
//!   the trunk, so neighbouring branches do not swing in step.
//!
//! The result depends only on the file: no randomness and no hash-map order.

use std::collections::HashMap;

use glam::{Vec2, Vec3};

use super::mesh::PrimitiveData;

/// Fills the wind channels of every vertex of `primitives` (see the module docs). `lowest` is
/// the model's lowest point, metres. `clipped[i]` says whether primitive i's material is
/// alpha-clipped.
pub fn compute_with(primitives: &mut [PrimitiveData], lowest: f32, clipped: &[bool]) {
    let offsets: Vec<usize> = primitives
        .iter()
        .scan(0, |acc, p| {
            let o = *acc;
            *acc += p.vertices.len();
            Some(o)
        })
        .collect();
    let total: usize = primitives.iter().map(|p| p.vertices.len()).sum();
    if total == 0 {
        return;
    }
    let mut parent: Vec<usize> = (0..total).collect();
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    fn union(parent: &mut [usize], a: usize, b: usize) {
        let (ra, rb) = (find(parent, a), find(parent, b));
        if ra != rb {
            // The smaller index becomes the root, so roots do not depend on the union order.
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            parent[hi] = lo;
        }
    }
    let mut at: HashMap<[i64; 3], usize> = HashMap::new();
    for (k, p) in primitives.iter().enumerate() {
        let o = offsets[k];
        for t in p.indices.chunks_exact(3) {
            union(&mut parent, o + t[0] as usize, o + t[1] as usize);
            union(&mut parent, o + t[0] as usize, o + t[2] as usize);
        }
        for (i, v) in p.vertices.iter().enumerate() {
            let key = v.position.map(|c| (c as f64 * 1000.0).round() as i64);
            match at.get(&key) {
                Some(&j) => union(&mut parent, o + i, j),
                None => {
                    at.insert(key, o + i);
                }
            }
        }
    }
    let positions: Vec<Vec3> =
        primitives.iter().flat_map(|p| p.vertices.iter().map(|v| Vec3::from(v.position))).collect();
    let roots: Vec<usize> = (0..total).map(|i| find(&mut parent, i)).collect();
    // Parts numbered by their first vertex; the trunk is the part of the lowest vertex (the
    // first such vertex on ties).
    let mut number: HashMap<usize, usize> = HashMap::new();
    for &r in &roots {
        let n = number.len();
        number.entry(r).or_insert(n);
    }
    let lowest_vertex = (0..total).fold(0, |best, i| if positions[i].y < positions[best].y { i } else { best });
    let trunk = roots[lowest_vertex];
    let one_part = number.len() == 1;
    // Where each clipped part hangs: its vertex nearest the trunk axis.
    let mut hang: HashMap<usize, Vec3> = HashMap::new();
    for (k, p) in primitives.iter().enumerate() {
        if !clipped.get(k).copied().unwrap_or(false) {
            continue;
        }
        for i in 0..p.vertices.len() {
            let g = offsets[k] + i;
            let d = Vec2::new(positions[g].x, positions[g].z).length();
            let e = hang.entry(roots[g]).or_insert(positions[g]);
            if d < Vec2::new(e.x, e.z).length() {
                *e = positions[g];
            }
        }
    }
    for (k, p) in primitives.iter_mut().enumerate() {
        for (i, v) in p.vertices.iter_mut().enumerate() {
            let g = offsets[k] + i;
            let pos = positions[g];
            let root = roots[g];
            let is_trunk = root == trunk && !one_part;
            let x = (pos.y - lowest).max(0.0);
            let y = if is_trunk { 0.0 } else { Vec2::new(pos.x, pos.z).length() };
            let z = if clipped.get(k).copied().unwrap_or(false) {
                hang.get(&root).map_or(0.0, |h| (pos - *h).length())
            } else {
                0.0
            };
            let w = if root == trunk { 0.0 } else { phase(number[&root] as u64) };
            v.wind = [x, y, z, w];
        }
    }
}

/// Fills the wind channels with no part treated as a leaf card.
pub fn compute(primitives: &mut [PrimitiveData], lowest: f32) {
    let clipped = vec![false; primitives.len()];
    compute_with(primitives, lowest, &clipped);
}

/// A phase in [0, 1) from a part number (SplitMix64's finaliser, top 24 bits).
pub fn phase(n: u64) -> f32 {
    let mut z = n.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 40) as f32 / (1u64 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::mesh::Vertex;

    fn tri(points: [[f32; 3]; 3]) -> PrimitiveData {
        PrimitiveData {
            vertices: points.iter().map(|p| Vertex { position: *p, ..Default::default() }).collect(),
            indices: vec![0, 1, 2],
            material: 0,
        }
    }

    #[test]
    fn the_lowest_part_is_the_trunk_and_other_parts_get_distance_and_their_own_phase() {
        // A trunk triangle from the ground up, a branch triangle sharing no vertex, and a card
        // touching the branch at (1, 2, 0) in another primitive (joined by position).
        let trunk = tri([[-0.1, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 2.0, 0.0]]);
        let branch = tri([[0.5, 1.5, 0.0], [1.0, 2.0, 0.0], [0.5, 1.6, 0.0]]);
        let card = tri([[1.0, 2.0, 0.0], [2.0, 2.0, 0.0], [1.0, 3.0, 0.0]]);
        let mut prims = vec![trunk, branch, card];
        compute_with(&mut prims, 0.0, &[false, false, true]);
        let w = |k: usize, i: usize| prims[k].vertices[i].wind;
        // Trunk: height in x, no distance, no phase.
        assert_eq!(w(0, 2), [2.0, 0.0, 0.0, 0.0]);
        // Branch: height, distance from the axis, its phase.
        let b = w(1, 1);
        assert_eq!((b[0], b[1], b[2]), (2.0, 1.0, 0.0));
        assert!(b[3] > 0.0 && b[3] < 1.0);
        // The card shares the branch's part (same position) and so its phase; z is the distance
        // from the part's vertex nearest the axis inside the clipped primitive, (1, 2, 0).
        let c = w(2, 1);
        assert_eq!(c[3], b[3]);
        assert!((c[2] - 1.0).abs() < 1e-6, "{c:?}");
    }

    #[test]
    fn a_model_of_one_part_sways_by_distance_everywhere() {
        let mut prims = vec![tri([[0.0, 0.0, 0.0], [3.0, 1.0, 4.0], [0.0, 2.0, 0.0]])];
        compute(&mut prims, 0.0);
        assert_eq!(prims[0].vertices[1].wind, [1.0, 5.0, 0.0, 0.0]);
    }
}
