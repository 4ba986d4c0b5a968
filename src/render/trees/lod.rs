//! Foliage level of detail by stochastic simplification (after Cook, Halstead, Planck and Ryu,
//! "Stochastic Simplification of Aggregate Detail", SIGGRAPH 2007).
//!
//! A crown is an aggregate of many small, similar pieces: leaves on mesh trees, cards on
//! billboard trees. Far away, each piece covers a pixel or less, and a software rasteriser pays
//! per triangle and per 4×4 block touched, not per pixel. So a far tree draws only a random
//! subset of its leaves, each grown so that the crown keeps its area and its look.
//!
//! - **At load time** ([`order_leaves`]), the triangles of an alpha-clipped primitive are split
//!   into leaves (groups of triangles that share vertices), and the leaves are shuffled in a
//!   fixed, seeded order. Each vertex gets its leaf's centre and its rank in that order, in
//!   `0..1`. The index buffer is rewritten in rank order, so any prefix of it is the first
//!   leaves of the shuffle.
//! - **Every frame**, the renderer gives each tree a keep fraction `f` in `1/32..=1` from its
//!   distance ([`keep_fraction`]): the share of leaves whose projected area stays above a pixel
//!   budget. It draws the index prefix that holds ranks below `2f` (in power-of-two buckets, so
//!   trees share draws), and the vertex shader sizes each leaf by [`leaf_scale`]: full size
//!   (times the area compensation) below rank `f`, shrinking linearly in area to nothing at
//!   `2f`. Leaves therefore fade in and out one by one as a tree nears or recedes, with no
//!   popping, and the total leaf area stays that of the whole crown.
//!
//! This module knows nothing of wgpu: it is plain data in and out, tested here and mirrored by
//! `leaf_scale` in `trees.wgsl`.

use glam::Vec3;

use crate::models::Vertex;
use crate::render::mix::mix;

/// A primitive needs at least this many leaves to be simplified.
pub const MIN_LEAVES: usize = 16;

/// The smallest keep fraction: far trees keep 1/32 of their leaves.
pub const MIN_KEEP: f32 = 1.0 / 32.0;

/// The number of keep-fraction buckets: bucket `b` holds fractions in `(2^-(b+1), 2^-b]`.
pub const BUCKETS: usize = 6;

/// A primitive's leaves in shuffled order.
#[derive(Clone, Debug, PartialEq)]
pub struct LeafOrder {
    /// The primitive's indices, leaf by leaf in rank order.
    pub indices: Vec<u32>,
    /// Per vertex: the centre of its leaf (model space, metres) and the leaf's rank in `0..1`.
    pub leaf: Vec<[f32; 4]>,
    /// `prefix[k]`: the number of indices of the first `k` leaves (`k` in `0..=leaves`).
    pub prefix: Vec<u32>,
    /// The mean area of one leaf, square metres (model space).
    pub mean_leaf_area: f32,
}

impl LeafOrder {
    /// The number of leaves.
    pub fn leaves(&self) -> usize {
        self.prefix.len() - 1
    }

    /// The number of indices to draw for trees in keep bucket `bucket`: every leaf of rank
    /// below `min(1, 2^(1-bucket))`, the largest `2f` of the bucket.
    pub fn index_count(&self, bucket: usize) -> u32 {
        let reach = (2.0f32).powi(1 - bucket as i32).min(1.0);
        let n = self.leaves();
        let k = ((reach * n as f32).ceil() as usize).min(n);
        self.prefix[k]
    }
}

/// The per-vertex leaf data of a primitive that is not simplified: rank -1 means "always full
/// size" to the shader.
pub fn unsimplified(vertices: usize) -> Vec<[f32; 4]> {
    vec![[0.0, 0.0, 0.0, -1.0]; vertices]
}

fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let p = parent[i as usize];
        parent[i as usize] = parent[p as usize];
        i = p;
    }
    i
}

/// Splits `indices` (a triangle list over `vertices`) into leaves, shuffles them with `seed`,
/// and returns them in rank order. `None` when there are fewer than [`MIN_LEAVES`] leaves, so
/// one-piece meshes (a trunk, a third-party crown modelled as one surface) are left whole.
pub fn order_leaves(vertices: &[Vertex], indices: &[u32], seed: u64) -> Option<LeafOrder> {
    let n = vertices.len();
    if n == 0 || indices.len() < 3 || indices.iter().any(|&i| i as usize >= n) {
        return None;
    }
    let mut parent: Vec<u32> = (0..n as u32).collect();
    for t in indices.chunks_exact(3) {
        let a = find(&mut parent, t[0]);
        for &v in &t[1..] {
            let b = find(&mut parent, v);
            if a != b {
                parent[b as usize] = a;
            }
        }
    }
    // Leaves in order of their first triangle, with their triangles.
    let mut leaf_of_root = vec![u32::MAX; n];
    let mut leaves: Vec<Vec<[u32; 3]>> = Vec::new();
    for t in indices.chunks_exact(3) {
        let r = find(&mut parent, t[0]) as usize;
        if leaf_of_root[r] == u32::MAX {
            leaf_of_root[r] = leaves.len() as u32;
            leaves.push(Vec::new());
        }
        leaves[leaf_of_root[r] as usize].push([t[0], t[1], t[2]]);
    }
    if leaves.len() < MIN_LEAVES {
        return None;
    }
    let mut order: Vec<usize> = (0..leaves.len()).collect();
    order.sort_by_key(|&k| (mix(seed ^ mix(k as u64)), k));

    let count = leaves.len() as f32;
    let mut out = LeafOrder {
        indices: Vec::with_capacity(indices.len()),
        leaf: unsimplified(n),
        prefix: vec![0],
        mean_leaf_area: 0.0,
    };
    let mut total_area = 0.0f32;
    for (rank, &k) in order.iter().enumerate() {
        let tris = &leaves[k];
        let pos = |i: u32| Vec3::from(vertices[i as usize].position);
        // The area-weighted centroid (a degenerate leaf still gets the mean of its corners).
        let (mut area, mut weights, mut centre) = (0.0f32, 0.0f32, Vec3::ZERO);
        for t in tris {
            let (a, b, c) = (pos(t[0]), pos(t[1]), pos(t[2]));
            let w = 0.5 * (b - a).cross(c - a).length();
            area += w;
            weights += w.max(1e-12);
            centre += (a + b + c) / 3.0 * w.max(1e-12);
        }
        let centre = centre / weights;
        total_area += area;
        let r = (rank as f32 + 0.5) / count;
        for t in tris {
            out.indices.extend_from_slice(t);
            for &v in t {
                out.leaf[v as usize] = [centre.x, centre.y, centre.z, r];
            }
        }
        out.prefix.push(out.indices.len() as u32);
    }
    out.mean_leaf_area = total_area / count;
    Some(out)
}

/// The share of a tree's leaves to draw, in [`MIN_KEEP`]`..=1`: the ratio of a leaf's projected
/// area to `leaf_pixels`, the smallest area in pixels a drawn leaf should cover. `leaf_area` is
/// the model's mean leaf area in square metres (already scaled with the tree), `distance` the
/// camera's distance to the tree in metres, `pixels_per_radian` the viewport height over the
/// vertical field of view's extent, `(height / 2) / tan(fov_y / 2)`. A `leaf_pixels` of 0
/// turns simplification off.
pub fn keep_fraction(leaf_area: f32, distance: f32, pixels_per_radian: f32, leaf_pixels: f32) -> f32 {
    if leaf_pixels <= 0.0 || !(leaf_area > 0.0) {
        return 1.0;
    }
    let px_per_m = pixels_per_radian / distance.max(0.01);
    let projected = leaf_area * px_per_m * px_per_m;
    (projected / leaf_pixels).clamp(MIN_KEEP, 1.0)
}

/// The keep bucket of a fraction: `b` with `f` in `(2^-(b+1), 2^-b]`, at most `BUCKETS - 1`.
pub fn bucket(keep: f32) -> usize {
    let mut b = 0;
    let mut top = 1.0f32;
    while b + 1 < BUCKETS && keep <= top * 0.5 {
        top *= 0.5;
        b += 1;
    }
    b
}

/// The linear size of the leaf of rank `rank` on a tree that keeps the fraction `keep` (the
/// CPU twin of `leaf_scale` in `trees.wgsl`). Leaves of rank up to `keep` get weight 1, those
/// up to `2 keep` a weight falling linearly to 0, and all are grown by the same factor so that
/// the weights' sum, the drawn area, equals the whole crown's. A negative rank (a primitive that
/// is not simplified) or `keep >= 1` gives 1.
pub fn leaf_scale(rank: f32, keep: f32) -> f32 {
    if rank < 0.0 || keep >= 1.0 {
        return 1.0;
    }
    let weight = ((2.0 * keep - rank) / keep).clamp(0.0, 1.0);
    let over = (2.0 * keep - 1.0).max(0.0);
    let kept = keep + (keep * keep - over * over) / (2.0 * keep);
    (weight / kept).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `count` separate quads (two triangles each) of side `side` along X.
    fn quads(count: usize, side: f32) -> (Vec<Vertex>, Vec<u32>) {
        let mut v = Vec::new();
        let mut idx = Vec::new();
        for q in 0..count {
            let x = q as f32 * 2.0;
            let base = v.len() as u32;
            for (dx, dy) in [(0.0, 0.0), (side, 0.0), (side, side), (0.0, side)] {
                v.push(Vertex { position: [x + dx, dy, 0.0], ..Default::default() });
            }
            idx.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
        }
        (v, idx)
    }

    #[test]
    fn leaves_are_found_shuffled_and_kept_whole() {
        let (v, idx) = quads(40, 0.5);
        let o = order_leaves(&v, &idx, 7).expect("40 leaves");
        assert_eq!(o.leaves(), 40);
        assert_eq!(o.indices.len(), idx.len());
        assert!((o.mean_leaf_area - 0.25).abs() < 1e-6);
        // Every leaf's six indices are contiguous and its four vertices share a centre and rank.
        for k in 0..40 {
            let tri = &o.indices[o.prefix[k] as usize..o.prefix[k + 1] as usize];
            assert_eq!(tri.len(), 6);
            let l = o.leaf[tri[0] as usize];
            assert!(tri.iter().all(|&i| o.leaf[i as usize] == l));
            assert!((l[3] - (k as f32 + 0.5) / 40.0).abs() < 1e-6, "ranks rise along the index buffer");
            assert!((l[1] - 0.25).abs() < 1e-6, "the centre is the quad's middle");
        }
        // The shuffle is not the identity, and the same seed gives the same order.
        assert_ne!(o.indices, idx);
        assert_eq!(order_leaves(&v, &idx, 7), Some(o.clone()));
        assert_ne!(order_leaves(&v, &idx, 8).map(|p| p.indices), Some(o.indices));
    }

    #[test]
    fn few_leaves_or_bad_indices_are_not_simplified() {
        let (v, idx) = quads(MIN_LEAVES - 1, 0.5);
        assert_eq!(order_leaves(&v, &idx, 1), None);
        let (v, mut idx) = quads(MIN_LEAVES * 2, 0.5);
        idx[4] = 10_000;
        assert_eq!(order_leaves(&v, &idx, 1), None);
    }

    #[test]
    fn buckets_draw_every_leaf_with_a_weight() {
        let (v, idx) = quads(64, 0.5);
        let o = order_leaves(&v, &idx, 3).unwrap();
        for keep in [1.0, 0.9, 0.5, 0.3, 0.2, 0.1, 0.05, MIN_KEEP] {
            let drawn = o.index_count(bucket(keep)) as usize;
            // A leaf outside the drawn prefix must have zero size.
            for &i in &o.indices[drawn..] {
                assert_eq!(leaf_scale(o.leaf[i as usize][3], keep), 0.0, "keep {keep}");
            }
        }
        assert_eq!(o.index_count(0), idx.len() as u32);
        assert_eq!(o.index_count(1), idx.len() as u32);
        assert_eq!(o.index_count(2), idx.len() as u32 / 2);
    }

    #[test]
    fn drawn_area_stays_the_crowns() {
        let n = 4096;
        for keep in [1.0, 0.8, 0.5, 0.25, 0.1, MIN_KEEP] {
            let area: f32 =
                (0..n).map(|k| leaf_scale((k as f32 + 0.5) / n as f32, keep).powi(2)).sum::<f32>() / n as f32;
            assert!((area - 1.0).abs() < 0.01, "keep {keep}: area {area}");
        }
        assert_eq!(leaf_scale(-1.0, 0.1), 1.0);
    }

    #[test]
    fn size_changes_smoothly_with_the_keep_fraction() {
        // No leaf jumps in area as a tree recedes: each 0.1 % step in the keep fraction (about
        // 0.05 % in distance) changes a leaf's area by a small share of a full leaf.
        for rank in [0.01, 0.1, 0.3, 0.6, 0.95] {
            let area = |keep: f32| leaf_scale(rank, keep).powi(2);
            let mut keep = 1.0f32;
            while keep > MIN_KEEP {
                let next = keep * 0.999;
                let (a, b) = (area(keep), area(next));
                assert!((a - b).abs() < 0.05 * b.max(1.0), "rank {rank} at keep {keep}: area {a} -> {b}");
                keep = next;
            }
        }
    }

    #[test]
    fn keep_fraction_follows_projected_area() {
        // A 0.01 m² leaf, 1000 px per radian: at 10 m it covers 100 px², so with a 16 px budget
        // every leaf is kept; at 50 m it covers 4 px², a quarter of the budget.
        assert_eq!(keep_fraction(0.01, 10.0, 1000.0, 16.0), 1.0);
        assert!((keep_fraction(0.01, 50.0, 1000.0, 16.0) - 0.25).abs() < 1e-6);
        assert_eq!(keep_fraction(0.01, 5000.0, 1000.0, 16.0), MIN_KEEP);
        assert_eq!(keep_fraction(0.01, 5000.0, 1000.0, 0.0), 1.0);
        assert_eq!(bucket(1.0), 0);
        assert_eq!(bucket(0.5), 1);
        assert_eq!(bucket(0.26), 1);
        assert_eq!(bucket(0.25), 2);
        assert_eq!(bucket(MIN_KEEP), BUCKETS - 1);
    }
}
