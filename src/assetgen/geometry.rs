//! Procedural tree geometry: tubes for the trunk and branches, folded leaves for mesh foliage and
//! crossed cards for billboard foliage, each vertex with its wind channels.
//!
//! Model space: metres, +Y up, origin at the base of the trunk. The per-vertex wind channels
//! (`_WIND`, see `docs/assets.md`) are: x = height above the root, y = distance from the trunk
//! axis, z = distance from the attachment point on the branch (leaves only), w = the branch's
//! random phase in 0..1.

use glam::{Vec2, Vec3, Vec4};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A seeded random source for the generator.
pub struct Rng(ChaCha8Rng);

impl Rng {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Rng {
        Rng(ChaCha8Rng::seed_from_u64(seed))
    }

    /// A uniform number in `[0, 1)`.
    pub fn f(&mut self) -> f32 {
        self.0.random::<f32>()
    }

    /// A uniform number in `[a, b)`.
    pub fn range(&mut self, a: f32, b: f32) -> f32 {
        a + (b - a) * self.f()
    }

    /// A random unit vector.
    pub fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            let l = v.length_squared();
            if l > 0.01 && l <= 1.0 {
                return v / l.sqrt();
            }
        }
    }
}

/// An indexed triangle mesh with the attributes the glTF files carry.
#[derive(Clone, Debug, Default)]
pub struct MeshData {
    /// Positions, metres.
    pub positions: Vec<Vec3>,
    /// Unit normals.
    pub normals: Vec<Vec3>,
    /// Tangents (xyz unit, w = ±1 bitangent sign).
    pub tangents: Vec<Vec4>,
    /// Texture coordinates.
    pub uvs: Vec<Vec2>,
    /// Wind channels, see the module documentation.
    pub wind: Vec<Vec4>,
    /// Vertex colours (linear RGBA, `COLOR_0`), one per vertex, or empty for none.
    pub colors: Vec<Vec4>,
    /// Triangles, counter-clockwise front faces.
    pub indices: Vec<u32>,
}

impl MeshData {
    /// Appends one vertex (its normal normalised; no colour) and returns its index.
    pub fn push(&mut self, p: Vec3, n: Vec3, t: Vec4, uv: Vec2, w: Vec4) -> u32 {
        let i = self.positions.len() as u32;
        self.positions.push(p);
        self.normals.push(n.normalize());
        self.tangents.push(t);
        self.uvs.push(uv);
        self.wind.push(w);
        i
    }

    /// Number of triangles.
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// Axis-aligned bounds (min, max) of the positions.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(a, b), p| (a.min(*p), b.max(*p)))
    }
}

/// A tangent that is unit length and orthogonal to `n`, with the handedness for which
/// `cross(n, t) * w` points along `bitangent_dir`.
pub fn tangent_frame(n: Vec3, t: Vec3, bitangent_dir: Vec3) -> Vec4 {
    let n = n.normalize();
    let t = (t - n * n.dot(t)).normalize_or(n.any_orthonormal_vector());
    let w = if n.cross(t).dot(bitangent_dir) >= 0.0 { 1.0 } else { -1.0 };
    t.extend(w)
}

/// One segment of wood: a tapered tube.
#[derive(Clone, Copy, Debug)]
pub struct Limb {
    /// Start point.
    pub start: Vec3,
    /// End point.
    pub end: Vec3,
    /// Radius at the start.
    pub r0: f32,
    /// Radius at the end.
    pub r1: f32,
    /// The branch's phase in 0..1 (wind channel w).
    pub phase: f32,
    /// Whether this is the trunk (distance to trunk 0).
    pub trunk: bool,
}

/// Appends a tapered tube with `sides` sides and `rings` segments along a slightly curved
/// path (`droop` metres of sag at the middle).
pub fn tube(mesh: &mut MeshData, limb: &Limb, sides: u32, rings: u32, droop: f32, v_scale: f32) {
    let axis = (limb.end - limb.start).normalize();
    let len = limb.start.distance(limb.end);
    let b1 = axis.any_orthonormal_vector();
    let b2 = axis.cross(b1);
    let base = mesh.positions.len() as u32;
    for j in 0..=rings {
        let s = j as f32 / rings as f32;
        let sag = Vec3::new(0.0, -droop * 4.0 * s * (1.0 - s), 0.0);
        let c = limb.start.lerp(limb.end, s) + sag;
        let r = limb.r0 + (limb.r1 - limb.r0) * s;
        for i in 0..=sides {
            let a = i as f32 / sides as f32 * std::f32::consts::TAU;
            let (sa, ca) = a.sin_cos();
            let n = b1 * ca + b2 * sa;
            let p = c + n * r;
            let t = -b1 * sa + b2 * ca;
            let uv = Vec2::new(i as f32 / sides as f32, s * len * v_scale);
            let dist_trunk = if limb.trunk { 0.0 } else { Vec2::new(p.x, p.z).length() };
            let w = Vec4::new(p.y.max(0.0), dist_trunk, 0.0, limb.phase);
            mesh.push(p, n, tangent_frame(n, t, axis), uv, w);
        }
    }
    let row = sides + 1;
    for j in 0..rings {
        for i in 0..sides {
            let a = base + j * row + i;
            let b = a + 1;
            let c = a + row;
            let d = c + 1;
            mesh.indices.extend_from_slice(&[a, b, d, a, d, c]);
        }
    }
    // Close the tip with a small cone so the tube is not open at the end.
    let tip = limb.end + axis * limb.r1.max(0.005);
    let tw =
        Vec4::new(tip.y.max(0.0), if limb.trunk { 0.0 } else { Vec2::new(tip.x, tip.z).length() }, 0.0, limb.phase);
    let ti = mesh.push(tip, axis, tangent_frame(axis, b1, b2), Vec2::new(0.5, len * v_scale + 0.05), tw);
    let last = base + rings * row;
    for i in 0..sides {
        mesh.indices.extend_from_slice(&[last + i, last + i + 1, ti]);
    }
}

/// Appends one folded leaf: a diamond of four vertices (base, right, tip, left) with a slight
/// V fold along the midrib. `attach` is the point on the branch the leaf hangs from.
#[allow(clippy::too_many_arguments)]
pub fn leaf(
    mesh: &mut MeshData,
    attach: Vec3,
    base: Vec3,
    dir: Vec3,
    side: Vec3,
    length: f32,
    width: f32,
    outward: Vec3,
    phase: f32,
) {
    let dir = dir.normalize();
    let mut side = (side - dir * dir.dot(side)).normalize_or(dir.any_orthonormal_vector());
    let mut face_n = side.cross(dir).normalize();
    // Turn the leaf so that its front faces away from the crown centre.
    if face_n.dot(outward) < 0.0 {
        side = -side;
        face_n = -face_n;
    }
    let fold = face_n * (0.12 * width);
    let tip = base + dir * length;
    let mid = base + dir * (0.45 * length);
    let right = mid + side * (0.5 * width) + fold;
    let left = mid - side * (0.5 * width) + fold;
    let n = (face_n + outward.normalize_or(face_n) * 0.8).normalize();
    let wind = |p: Vec3| Vec4::new(p.y.max(0.0), Vec2::new(p.x, p.z).length(), p.distance(attach), phase);
    // u runs from left (0) to right (1), v from tip (0) to base (1).
    let t = tangent_frame(n, side, -dir);
    let i0 = mesh.push(base, n, t, Vec2::new(0.5, 1.0), wind(base));
    let i1 = mesh.push(right, n, t, Vec2::new(1.0, 0.55), wind(right));
    let i2 = mesh.push(tip, n, t, Vec2::new(0.5, 0.0), wind(tip));
    let i3 = mesh.push(left, n, t, Vec2::new(0.0, 0.55), wind(left));
    // Counter-clockwise seen from the front (face_n): base → right → tip, base → tip → left.
    mesh.indices.extend_from_slice(&[i0, i1, i2, i0, i2, i3]);
}

/// Appends one foliage card: a square of `size` metres centred at `centre`, facing `normal`,
/// textured with the whole leaf-cluster texture. The vertex normals lean outward from the crown
/// centre so that the cards shade like a rounded crown.
pub fn card(
    mesh: &mut MeshData,
    centre: Vec3,
    normal: Vec3,
    up: Vec3,
    size: f32,
    crown_centre: Vec3,
    attach: Vec3,
    phase: f32,
) {
    let n = normal.normalize();
    let up = (up - n * n.dot(up)).normalize_or(n.any_orthonormal_vector());
    let right = up.cross(n);
    let h = size * 0.5;
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let mut ids = [0u32; 4];
    for (k, (sx, sy)) in corners.iter().enumerate() {
        let p = centre + right * (sx * h) + up * (sy * h);
        let out = (p - crown_centre).normalize_or(n);
        let vn = (n * 0.5 + out).normalize();
        let t = tangent_frame(vn, right, -up);
        let uv = Vec2::new((sx + 1.0) * 0.5, 1.0 - (sy + 1.0) * 0.5);
        let w = Vec4::new(p.y.max(0.0), Vec2::new(p.x, p.z).length(), p.distance(attach), phase);
        ids[k] = mesh.push(p, vn, t, uv, w);
    }
    mesh.indices.extend_from_slice(&[ids[0], ids[1], ids[2], ids[0], ids[2], ids[3]]);
}
