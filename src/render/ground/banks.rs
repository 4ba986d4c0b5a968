//! The sides of the planes as earth (drawn only; the simulation's planes, their ray casts and
//! the world hash know nothing of them): a plane's outer edge is an earth bank, a short cut of
//! soil under the edge and then a grassed slope going down and out, so that a raised plane (the
//! terrace) reads as a bank and a plane at ground level meets the terrain with a thin soil line;
//! a hole's rim is a pit, a soil wall sloping in from the rim down to the soil floor, darker
//! towards its foot ([`PIT_FOOT_SHADE`]).
//!
//! Every boundary edge of a plane (an edge of exactly one triangle) belongs to a rim: the loops
//! they form are found and each is told apart as the plane's outline (its edges' sides face away
//! from the loop's inside) or a hole's (they face into it). Each vertex of a rim gets one foot
//! shared by the quads of its two edges, so the sides close at the corners:
//! - on an outline, along the mitre of its two edges' outward normals (the offset lines of the
//!   two edges meet there, so every bank quad lies at its slope across its edge, and a convex
//!   corner becomes a hip);
//! - on a hole's rim, towards the rim's centre (the mean of its vertices), no further than
//!   [`PIT_REACH`] of the way, so that the walls of a small pit do not meet: a hole's rim
//!   zigzags along the triangles of the grid, and its centre smooths that out at the pit's
//!   bottom; at the tip of a spike of the hole, whose edges the centre lies behind, along the
//!   mitre of its two edges, so that every wall slopes into the pit. (Walls of a rim far from
//!   round may overlap: no wall rises above its rim.)
//!
//! Both go down to the soil floor (`floor_y`, below every plane): a bank passes under whatever
//! ground lies below it (the terrain, a lower plane), which hides the rest of it, and goes on
//! down where nothing does. An edge on no clean loop (a vertex where two rims touch) gets a
//! vertical soil wall, as every side once was. Units: metres; +Y up.

use std::collections::{HashMap, HashSet};

use glam::{Vec2, Vec3};

use super::landscape::{KIND_BANK, KIND_SIDE, LandMesh};

/// A bank's grassed slope: metres out for every metre down (1 : 1.5, about 34°).
pub const BANK_RUN: f32 = 1.5;
/// How far the soil cut under a plane's outer edge drops before the grass starts, metres.
pub const SOIL_EDGE: f32 = 0.12;
/// The soil cut's slope: metres out for every metre down (steep, about 76°).
pub const SOIL_EDGE_RUN: f32 = 0.25;
/// A pit's wall: metres in for every metre down (about 59°).
pub const PIT_RUN: f32 = 0.6;
/// The furthest a pit wall's foot moves towards its rim's centre, as a share of the way.
pub const PIT_REACH: f32 = 0.6;
/// The shade of a pit wall's foot (its top's is 1): soil deep in a pit gets less light, and the
/// wall's foot then matches the floor (the shader's soil is twice as bright on a side as on the
/// floor).
pub const PIT_FOOT_SHADE: f32 = 0.5;
/// The longest mitre of a bank's corner, in units of its slope's run: a sharp corner's foot is
/// kept this close.
const MITRE_LIMIT: f32 = 2.0;

/// A closed loop of boundary edges: its vertices in order around it.
#[derive(Debug, Clone, PartialEq)]
pub struct Rim {
    /// Indices of the plane's vertices, each once, in order around the loop.
    pub vertices: Vec<u32>,
    /// Whether the loop rims a hole (the plane lies outside it) rather than the plane's outline.
    pub hole: bool,
    /// For each edge (from `vertices[i]` to the next), the unit direction in (x, z) that points
    /// away from the plane: out of the outline, into the hole.
    pub away: Vec<Vec2>,
}

/// The xz position of a vertex.
fn xz(p: Vec3) -> Vec2 {
    Vec2::new(p.x, p.z)
}

/// The rims of a plane's mesh, and the boundary edges on no clean loop (with the index of their
/// triangle), in a fixed order. Triangles with an index out of range are skipped.
pub fn rims(vertices: &[Vec3], triangles: &[[u32; 3]]) -> (Vec<Rim>, Vec<((u32, u32), usize)>) {
    let n = vertices.len() as u32;
    let mut edges: HashMap<(u32, u32), (u32, usize)> = HashMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        if tri.iter().any(|&i| i >= n) {
            continue;
        }
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            edges.entry(key).and_modify(|e| e.0 += 1).or_insert((1, t));
        }
    }
    let mut boundary: Vec<((u32, u32), usize)> =
        edges.into_iter().filter(|(_, (c, _))| *c == 1).map(|(k, (_, t))| (k, t)).collect();
    // A fixed order, so the mesh is the same from run to run.
    boundary.sort_unstable();
    let tri_of: HashMap<(u32, u32), usize> = boundary.iter().copied().collect();
    let mut next: HashMap<u32, Vec<u32>> = HashMap::new();
    for &((a, b), _) in &boundary {
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    }
    let clean = |v: u32| next.get(&v).is_some_and(|n| n.len() == 2 && n[0] != n[1]);
    let mut used: HashSet<(u32, u32)> = HashSet::new();
    let (mut found, mut stray) = (Vec::new(), Vec::new());
    for &((a, b), t) in &boundary {
        if used.contains(&(a, b)) {
            continue;
        }
        // Walk from a through b until back at a, through vertices of exactly two boundary edges.
        let mut walk = vec![a];
        let (mut prev, mut cur) = (a, b);
        let mut ok = clean(a);
        used.insert((a, b));
        let mut walked = vec![((a, b), t)];
        while ok && cur != a {
            if !clean(cur) || walk.len() > boundary.len() {
                ok = false;
                break;
            }
            walk.push(cur);
            let n = &next[&cur];
            let to = if n[0] == prev { n[1] } else { n[0] };
            let key = (cur.min(to), cur.max(to));
            used.insert(key);
            walked.push((key, tri_of[&key]));
            (prev, cur) = (cur, to);
        }
        if !ok || walk.len() < 3 {
            stray.extend(walked);
            continue;
        }
        found.push(rim(vertices, triangles, walk, &walked));
    }
    stray.sort_unstable();
    stray.dedup();
    (found, stray)
}

/// The rim of the loop `walk` (vertices in order; `walked[i]` the edge from `walk[i]` to the
/// next, with its triangle): which side the plane lies on, and each edge's away direction.
fn rim(vertices: &[Vec3], triangles: &[[u32; 3]], walk: Vec<u32>, walked: &[((u32, u32), usize)]) -> Rim {
    let p = |i: usize| xz(vertices[walk[i % walk.len()] as usize]);
    // Twice the signed area (shoelace, x then z): positive when the inside is on the left of
    // the direction of travel, left of (dx, dz) being (-dz, dx).
    let area: f32 = (0..walk.len()).map(|i| p(i).perp_dot(p(i + 1))).sum();
    // Which side of the travel the plane lies on: its triangles' centres, summed over the edges.
    let mut plane_left = 0.0f32;
    for (i, &(_, t)) in walked.iter().enumerate() {
        let centre = triangles[t].iter().map(|&k| xz(vertices[k as usize])).sum::<Vec2>() / 3.0;
        let along = p(i + 1) - p(i);
        plane_left += along.perp().dot(centre - (p(i) + p(i + 1)) * 0.5).signum();
    }
    let plane_left = plane_left > 0.0;
    let away = (0..walk.len())
        .map(|i| {
            let along = (p(i + 1) - p(i)).normalize_or(Vec2::X);
            if plane_left { -along.perp() } else { along.perp() }
        })
        .collect();
    // The plane inside the loop: the outline; outside it: a hole.
    let hole = plane_left != (area > 0.0);
    Rim { vertices: walk, hole, away }
}

/// The mitre of two unit normals `a` and `b`: the offset that moves both edges out by one,
/// no longer than [`MITRE_LIMIT`].
pub fn mitre(a: Vec2, b: Vec2) -> Vec2 {
    let c = 1.0 + a.dot(b);
    if c >= 2.0 / (MITRE_LIMIT * MITRE_LIMIT) { (a + b) / c } else { (a + b).normalize_or(a) * MITRE_LIMIT }
}

/// The feet of a hole's rim at `floor_y`, in (x, z), for the rim's vertices `rim` and its edges'
/// away directions `away` (into the hole): each vertex moved towards the rim's centre (the mean
/// of its vertices) by its depth times [`PIT_RUN`], at most [`PIT_REACH`] of the way. Where the
/// centre lies behind one of the vertex's two edges (the tip of a spike of the hole, as a grid's
/// diagonals leave them), along the mitre of the two edges instead: every foot lies on the hole's
/// side of both its edges, so every wall slopes into the pit.
pub fn pit_feet(rim: &[Vec3], away: &[Vec2], floor_y: f32) -> Vec<Vec2> {
    let n = rim.len();
    let pts: Vec<Vec2> = rim.iter().map(|&p| xz(p)).collect();
    let c = pts.iter().sum::<Vec2>() / n.max(1) as f32;
    (0..n)
        .map(|i| {
            let (q, a, b) = (pts[i], away[(i + n - 1) % n], away[i]);
            let to = c - q;
            let dir = if to.dot(a) > 0.0 && to.dot(b) > 0.0 { to.normalize_or_zero() } else { (a + b).normalize_or(b) };
            q + dir * ((rim[i].y - floor_y).max(0.0) * PIT_RUN).min(PIT_REACH * to.length())
        })
        .collect()
}

/// One vertex of a bank's profile: where its soil cut ends (the lip, [`SOIL_EDGE`] down) and
/// its foot at `floor_y`, for the top `p` and the mitre `m` of its two edges.
pub fn bank_profile(p: Vec3, m: Vec2, floor_y: f32) -> (Vec3, Vec3) {
    let drop = SOIL_EDGE.min((p.y - floor_y).max(0.0));
    let lip_xz = xz(p) + m * (drop * SOIL_EDGE_RUN);
    let lip = Vec3::new(lip_xz.x, p.y - drop, lip_xz.y);
    let foot_xz = lip_xz + m * ((lip.y - floor_y).max(0.0) * BANK_RUN);
    (lip, Vec3::new(foot_xz.x, floor_y, foot_xz.y))
}

/// The sides of one plane (see the module's docs) added to `mesh`: banks under its outline,
/// pits under its holes, down to `floor_y`.
pub fn sides(mesh: &mut LandMesh, vertices: &[Vec3], triangles: &[[u32; 3]], floor_y: f32) {
    let (found, stray) = rims(vertices, triangles);
    for r in &found {
        let top: Vec<Vec3> = r.vertices.iter().map(|&i| vertices[i as usize]).collect();
        let n = top.len();
        if r.hole {
            let feet = pit_feet(&top, &r.away, floor_y);
            for i in 0..n {
                let j = (i + 1) % n;
                let (a, b) = (top[i], top[j]);
                let (fa, fb) = (Vec3::new(feet[i].x, floor_y, feet[i].y), Vec3::new(feet[j].x, floor_y, feet[j].y));
                let away = Vec3::new(r.away[i].x, 0.0, r.away[i].y);
                let mut normal = (b - a).cross((fa + fb) * 0.5 - (a + b) * 0.5).normalize_or(away);
                if normal.dot(away + Vec3::Y) < 0.0 {
                    normal = -normal;
                }
                mesh.quad_shaded([a, b, fb, fa], normal, KIND_SIDE, [1.0, 1.0, PIT_FOOT_SHADE, PIT_FOOT_SHADE]);
            }
        } else {
            let profile: Vec<(Vec3, Vec3)> =
                (0..n).map(|i| bank_profile(top[i], mitre(r.away[(i + n - 1) % n], r.away[i]), floor_y)).collect();
            for i in 0..n {
                let j = (i + 1) % n;
                let away = Vec3::new(r.away[i].x, 0.0, r.away[i].y);
                let ((la, fa), (lb, fb)) = (profile[i], profile[j]);
                mesh.quad([top[i], top[j], lb, la], (away + Vec3::Y * SOIL_EDGE_RUN).normalize(), KIND_SIDE);
                mesh.quad([la, lb, fb, fa], (away + Vec3::Y * BANK_RUN).normalize(), KIND_BANK);
            }
        }
    }
    // The edges on no clean loop: vertical walls, facing away from their triangle.
    for ((a, b), t) in stray {
        let (pa, pb) = (vertices[a as usize], vertices[b as usize]);
        let centre = triangles[t].iter().map(|&i| vertices[i as usize]).sum::<Vec3>() / 3.0;
        let along = pb - pa;
        let mut out = Vec3::new(along.z, 0.0, -along.x).normalize_or(Vec3::X);
        if out.dot((pa + pb) * 0.5 - centre) < 0.0 {
            out = -out;
        }
        let low = |p: Vec3| Vec3::new(p.x, floor_y.min(p.y), p.z);
        mesh.quad([pa, pb, low(pb), low(pa)], out, KIND_SIDE);
    }
}

#[cfg(test)]
#[path = "banks_tests.rs"]
mod tests;
