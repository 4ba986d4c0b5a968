//! The room layout of a task (`docs/headset.md`, "A layout that fits the room"): a task started
//! with `layout: room` has its targets placed within the floor a headset detected, keeping their
//! order and models (the task's mesh and billboard models stay on their targets) and the ratios
//! of their spacing: the task file's layout is scaled about its centroid by the largest factor
//! (never above 1) for which a shift puts every target inside the floor's outline at least
//! [`EDGE_MARGIN_M`] from its edges, and among such shifts the one nearest the task file's own
//! place. Every target then lies on the floor (y = 0, the room's floor in the simulation's frame).
//! The study then stands in the room as a scale model: the task's tolerance is scaled alike
//! (`TaskState::laid_out`) and so are the trees planted or taken from the menu during the task
//! and the radius their box's handles are picked at (`crate::task::layout_scale`): at full size,
//! seven crowns 3 to 6 m wide would stand within a few square metres, and a tree's lowest
//! branches (a conifer's reach 2 m from its trunk) would cover its neighbours' targets from the
//! ray; handles of full size would cover a small tree's whole box.
//!
//! The layout is written into the recording as the task's: the `start_task` event carries the
//! floor's outline ([`TaskLayout`]), so a replay places the targets again with the same maths.
//! Pure and deterministic: plain f64 arithmetic with libm's square root, the shifts searched on a
//! fixed grid in a fixed order, no state.

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// How far every target stays from the floor's edges, metres.
pub const EDGE_MARGIN_M: f64 = 0.5;

/// The most points a layout's outlines may have, the floor's and the keep-outs' together (the
/// search's work grows with them: every candidate shift casts each target's segment against every
/// edge).
pub const MAX_FLOOR_POINTS: usize = 256;

/// How far from the origin a floor's point may lie, metres.
const MAX_FLOOR_COORD: f32 = 1.0e4;

/// The shifts the first pass tries at most (a grid over the floor's bounds).
const GRID_POINTS: f64 = 1600.0;

/// In the first pass, a scale within this fraction of the best one counts as as good (the shift
/// nearer the task file's place wins); the finer passes keep the largest scale.
const SCALE_TIE: f64 = 0.005;

/// The margin the search keeps, a millimetre more than [`EDGE_MARGIN_M`], so that the positions'
/// rounding to f32 never brings a target nearer the edge than that.
const SEARCH_MARGIN_M: f64 = EDGE_MARGIN_M + 1e-3;

/// The most keep-out outlines a room layout may have.
pub const MAX_KEEP_OUT: usize = 16;

/// How a task's targets are laid out, when not as the task file puts them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TaskLayout {
    /// Within the room's detected floor.
    Room {
        /// The floor's outline in the simulation's frame, `[x, z]` metres, in order around it.
        floor: Vec<[f32; 2]>,
        /// The outlines, seen from above, of what stands over the floor (a table, a shelf: the
        /// room's other horizontal planes), which the targets keep away from as from the floor's
        /// edges: a target under a table is out of a ray's reach.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        keep_out: Vec<Vec<[f32; 2]>>,
    },
}

/// Why a layout's floor is refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FloorError {
    /// Fewer than 3 or more than [`MAX_FLOOR_POINTS`] points.
    #[error("a room layout's floor needs 3 to {MAX_FLOOR_POINTS} points, not {0}")]
    Points(usize),
    /// A point that is not finite or lies more than 10 km away.
    #[error("a room layout's floor has a NaN, infinite or far-away point")]
    Point,
    /// An outline without area.
    #[error("a room layout's floor has no area")]
    Area,
    /// More than [`MAX_KEEP_OUT`] keep-out outlines, or one that is not an outline.
    #[error("a room layout's keep_out needs at most {MAX_KEEP_OUT} outlines of at least 3 finite points within 10 km, and at most {MAX_FLOOR_POINTS} points with the floor's")]
    KeepOut,
}

impl TaskLayout {
    /// Checks the outlines: the floor's 3 to [`MAX_FLOOR_POINTS`] finite points within 10 km,
    /// with an area; at most [`MAX_KEEP_OUT`] keep-out outlines of at least 3 such points, and at
    /// most [`MAX_FLOOR_POINTS`] points in all.
    pub fn validate(&self) -> Result<(), FloorError> {
        let TaskLayout::Room { floor, keep_out } = self;
        let far = |o: &[[f32; 2]]| o.iter().flatten().any(|v| !v.is_finite() || v.abs() > MAX_FLOOR_COORD);
        if floor.len() < 3 || floor.len() > MAX_FLOOR_POINTS {
            return Err(FloorError::Points(floor.len()));
        }
        if far(floor) {
            return Err(FloorError::Point);
        }
        if area(&points(floor)) < 1e-4 {
            return Err(FloorError::Area);
        }
        let all = floor.len() + keep_out.iter().map(Vec::len).sum::<usize>();
        if keep_out.len() > MAX_KEEP_OUT || all > MAX_FLOOR_POINTS || keep_out.iter().any(|o| o.len() < 3 || far(o)) {
            return Err(FloorError::KeepOut);
        }
        Ok(())
    }
}

/// Where a room layout put a task's targets, as `grove replay` and `grove study` report it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RoomPlacement {
    /// The factor the task file's spacing was scaled by (at most 1).
    pub scale: f32,
    /// How far the targets' centroid moved from the task file's, `[x, z]` metres.
    pub shift: [f32; 2],
    /// The floor's area, square metres.
    pub floor_m2: f32,
    /// The floor's bounds, `[width along x, depth along z]` metres.
    pub floor_size: [f32; 2],
    /// The smallest distance from a target to the floor's edges and the keep-outs', metres.
    pub edge_m: f32,
}

type P = (f64, f64);

fn points(floor: &[[f32; 2]]) -> Vec<P> {
    floor.iter().map(|p| (p[0] as f64, p[1] as f64)).collect()
}

fn sub(a: P, b: P) -> P {
    (a.0 - b.0, a.1 - b.1)
}

fn dot(a: P, b: P) -> f64 {
    a.0 * b.0 + a.1 * b.1
}

/// The outline's area (by the shoelace formula), square metres.
fn area(poly: &[P]) -> f64 {
    let n = poly.len();
    let twice: f64 = (0..n).map(|i| poly[i].0 * poly[(i + 1) % n].1 - poly[(i + 1) % n].0 * poly[i].1).sum();
    twice.abs() / 2.0
}

/// Whether `p` lies inside the outline (even-odd rule).
fn inside(poly: &[P], p: P) -> bool {
    let mut odd = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a.1 > p.1) != (b.1 > p.1) && p.0 < a.0 + (p.1 - a.1) / (b.1 - a.1) * (b.0 - a.0) {
            odd = !odd;
        }
    }
    odd
}

/// The distance from `p` to the segment `a`–`b`.
fn segment_distance(p: P, a: P, b: P) -> f64 {
    let d = sub(b, a);
    let len2 = dot(d, d);
    let t = if len2 > 0.0 { (dot(sub(p, a), d) / len2).clamp(0.0, 1.0) } else { 0.0 };
    let q = sub(p, (a.0 + d.0 * t, a.1 + d.1 * t));
    libm::sqrt(dot(q, q))
}

/// The distance from `p` to the outline's nearest edge.
fn edge_distance(poly: &[P], p: P) -> f64 {
    let n = poly.len();
    (0..n).map(|i| segment_distance(p, poly[i], poly[(i + 1) % n])).fold(f64::INFINITY, f64::min)
}

/// Where targets may lie: inside the floor's outline and outside every keep-out outline.
struct Region {
    outlines: Vec<Vec<P>>, // the floor's first, then the keep-outs
}

impl Region {
    fn inside(&self, p: P) -> bool {
        inside(&self.outlines[0], p) && !self.outlines[1..].iter().any(|o| inside(o, p))
    }

    /// The distance from `p` to the nearest edge of any outline.
    fn edge_distance(&self, p: P) -> f64 {
        self.outlines.iter().map(|o| edge_distance(o, p)).fold(f64::INFINITY, f64::min)
    }

    fn edges(&self) -> impl Iterator<Item = (P, P)> + '_ {
        self.outlines.iter().flat_map(|o| (0..o.len()).map(move |i| (o[i], o[(i + 1) % o.len()])))
    }
}

/// The smallest λ ≥ 0 at which `o + λ u` comes within `r` of `c` (`o` lies farther than `r`).
fn circle_entry(o: P, u: P, c: P, r: f64) -> Option<f64> {
    let w = sub(o, c);
    let (a, b, k) = (dot(u, u), 2.0 * dot(w, u), dot(w, w) - r * r);
    let disc = b * b - 4.0 * a * k;
    if a <= 0.0 || disc < 0.0 {
        return None;
    }
    let l = (-b - libm::sqrt(disc)) / (2.0 * a);
    (l >= 0.0).then_some(l)
}

/// The smallest λ ≥ 0 at which `o + λ u` comes within `r` of the segment `a`–`b` (the segment's
/// capsule), for `o` outside it.
fn capsule_entry(o: P, u: P, a: P, b: P, r: f64) -> Option<f64> {
    let mut best = [circle_entry(o, u, a, r), circle_entry(o, u, b, r)].into_iter().flatten().fold(None, |m: Option<f64>, l| Some(m.map_or(l, |m| m.min(l))));
    let d = sub(b, a);
    let len = libm::sqrt(dot(d, d));
    if len > 0.0 {
        let n = (-d.1 / len, d.0 / len);
        let side = dot(sub(o, a), n);
        let un = dot(u, n);
        if side.abs() > r && un != 0.0 {
            let l = (side.signum() * r - side) / un;
            let along = dot(sub((o.0 + u.0 * l, o.1 + u.1 * l), a), d) / (len * len);
            if l >= 0.0 && (0.0..=1.0).contains(&along) {
                best = Some(best.map_or(l, |m| m.min(l)));
            }
        }
    }
    best
}

/// The largest scale (at most 1) for targets at `centre + s q` (each `q` an offset from the
/// centroid) on the segments from `centre`, all within the region at least `margin` from its
/// edges; `None` when `centre` itself is not, or when the scale falls below `at_least` (the
/// search has a better one already).
fn reach(region: &Region, centre: P, offsets: &[P], margin: f64, at_least: f64) -> Option<f64> {
    if !region.inside(centre) || region.edge_distance(centre) < margin {
        return None;
    }
    let mut s: f64 = 1.0;
    for &q in offsets {
        for (a, b) in region.edges() {
            if let Some(l) = capsule_entry(centre, q, a, b, margin) {
                s = s.min(l);
            }
        }
        if s < at_least {
            return None;
        }
    }
    Some(s)
}

/// The best of the shifts `centres` for `offsets`: the largest reach, and among reaches within
/// the fraction `tie` of it the centre nearest `home`; earlier centres win exact ties.
fn best(region: &Region, centres: impl Iterator<Item = P>, offsets: &[P], home: P, tie: f64) -> Option<(P, f64)> {
    // A centre whose reach falls below the best so far, less the tie, can never be chosen: its
    // search stops early (the same choice as searching every centre through).
    let mut top: f64 = 0.0;
    let mut found: Vec<(P, f64)> = Vec::new();
    for c in centres {
        if let Some(s) = reach(region, c, offsets, SEARCH_MARGIN_M, top * (1.0 - tie)).filter(|s| *s > 0.0) {
            top = top.max(s);
            found.push((c, s));
        }
    }
    let far = |c: P| dot(sub(c, home), sub(c, home));
    found.into_iter().filter(|(_, s)| *s >= top * (1.0 - tie)).fold(None, |m: Option<(P, f64)>, x| match m {
        Some(m) if far(m.0) <= far(x.0) => Some(m),
        _ => Some(x),
    })
}

/// A square grid of `2k + 1` points a side, `step` apart, around `c`.
fn grid(c: P, step: f64, k: i32) -> impl Iterator<Item = P> {
    (-k..=k).flat_map(move |i| (-k..=k).map(move |j| (c.0 + i as f64 * step, c.1 + j as f64 * step)))
}

/// Places `targets` (the task file's positions) within `floor` and outside `keep_out` (outlines
/// checked by [`TaskLayout::validate`]): the new positions, on the floor (y = 0), in the same
/// order, and the placement; `None` when no point of the floor lies [`EDGE_MARGIN_M`] from every
/// edge.
pub fn place(targets: &[Vec3], floor: &[[f32; 2]], keep_out: &[Vec<[f32; 2]>]) -> Option<(Vec<Vec3>, RoomPlacement)> {
    let poly = points(floor);
    if targets.is_empty() || poly.len() < 3 {
        return None;
    }
    let region = Region { outlines: std::iter::once(poly.clone()).chain(keep_out.iter().map(|o| points(o))).collect() };
    let n = targets.len() as f64;
    let home = (targets.iter().map(|t| t.x as f64).sum::<f64>() / n, targets.iter().map(|t| t.z as f64).sum::<f64>() / n);
    let offsets: Vec<P> = targets.iter().map(|t| (t.x as f64 - home.0, t.z as f64 - home.1)).collect();
    // The search tries the farthest targets first: they bind first, so a poor shift stops soon.
    let mut order = offsets.clone();
    order.sort_by(|a, b| dot(*b, *b).total_cmp(&dot(*a, *a)));
    let (lo, hi) = poly.iter().fold(((f64::INFINITY, f64::INFINITY), (f64::NEG_INFINITY, f64::NEG_INFINITY)), |(lo, hi), p| ((lo.0.min(p.0), lo.1.min(p.1)), (hi.0.max(p.0), hi.1.max(p.1))));
    // The task file's own place, when the whole layout fits there, is kept as it is.
    let (centre, scale) = match reach(&region, home, &order, SEARCH_MARGIN_M, 0.0) {
        Some(s) if s >= 1.0 => (home, 1.0),
        _ => {
            let step = libm::sqrt((hi.0 - lo.0) * (hi.1 - lo.1) / GRID_POINTS).max(0.02);
            let mid = ((lo.0 + hi.0) / 2.0, (lo.1 + hi.1) / 2.0);
            let k = (((hi.0 - lo.0).max(hi.1 - lo.1) / step / 2.0) as i32) + 1;
            // The middle first: good shifts come early, so the poor ones' search stops soon.
            let mut first: Vec<P> = grid(mid, step, k).collect();
            first.sort_by(|a, b| dot(sub(*a, mid), sub(*a, mid)).total_cmp(&dot(sub(*b, mid), sub(*b, mid))));
            let (mut c, mut s) = best(&region, first.into_iter(), &order, home, SCALE_TIE)?;
            // Two finer passes around the best shift found.
            for fine in [step / 10.0, step / 100.0] {
                (c, s) = best(&region, grid(c, fine, 10), &order, home, 1e-9).unwrap_or((c, s));
            }
            (c, s)
        }
    };
    let placed: Vec<Vec3> = offsets.iter().map(|q| Vec3::new((centre.0 + q.0 * scale) as f32, 0.0, (centre.1 + q.1 * scale) as f32)).collect();
    let edge = placed.iter().map(|p| region.edge_distance((p.x as f64, p.z as f64))).fold(f64::INFINITY, f64::min);
    let placement = RoomPlacement {
        scale: scale as f32,
        shift: [(centre.0 - home.0) as f32, (centre.1 - home.1) as f32],
        floor_m2: area(&poly) as f32,
        floor_size: [(hi.0 - lo.0) as f32, (hi.1 - lo.1) as f32],
        edge_m: edge as f32,
    };
    Some((placed, placement))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The study's targets (assets/tasks/ray-casting-7.ron; systems/tests/room_layout.rs lays out the file's own).
    fn study() -> Vec<Vec3> {
        [(-7.0, 0.0, -1.5), (0.0, 0.0, -4.5), (5.5, 0.0, -0.5), (-3.0, 0.0, -9.5), (3.5, 0.0, -11.5), (-12.5, 0.0, -5.0), (10.0, 0.8, -11.0)].map(|(x, y, z)| Vec3::new(x, y, z)).to_vec()
    }

    fn rect(x0: f32, z0: f32, x1: f32, z1: f32) -> Vec<[f32; 2]> {
        vec![[x0, z0], [x1, z0], [x1, z1], [x0, z1]]
    }

    /// Every placed target inside the floor, at least the margin from its edges, on the floor.
    fn within(placed: &[Vec3], floor: &[[f32; 2]]) {
        let poly = points(floor);
        for p in placed {
            let q = (p.x as f64, p.z as f64);
            assert!(inside(&poly, q), "{p} outside {floor:?}");
            assert!(edge_distance(&poly, q) >= EDGE_MARGIN_M, "{p} is {} m from an edge", edge_distance(&poly, q));
            assert_eq!(p.y, 0.0);
        }
    }

    /// The placed targets are the task file's scaled by `s` and shifted: same order, same ratios.
    fn similar(placed: &[Vec3], s: f32) {
        let from = study();
        for i in 0..from.len() {
            for j in 0..from.len() {
                let a = Vec3::new(from[i].x - from[j].x, 0.0, from[i].z - from[j].z).length() * s;
                let b = Vec3::new(placed[i].x - placed[j].x, 0.0, placed[i].z - placed[j].z).length();
                assert!((a - b).abs() < 1e-3, "{i}-{j}: {a} scaled, {b} placed");
            }
        }
    }

    #[test]
    fn a_four_by_four_room_scales_the_study_into_its_middle_three_metres() {
        let floor = rect(-2.0, 2.0, 2.0, 6.0);
        let (placed, p) = place(&study(), &floor, &[]).unwrap();
        within(&placed, &floor);
        similar(&placed, p.scale);
        // The study spans 22.5 m in x (-12.5 to 10): 3 m of it fit between the margins.
        assert!((p.scale - 3.0 / 22.5).abs() < 2e-3, "{p:?}");
        assert!((p.floor_m2 - 16.0).abs() < 1e-4 && p.floor_size == [4.0, 4.0]);
        assert!(p.edge_m >= 0.499 && p.edge_m < 0.52, "{p:?}");
    }

    #[test]
    fn a_floor_that_holds_the_task_file_keeps_it_where_it_is() {
        let floor = rect(-30.0, -30.0, 30.0, 30.0);
        let (placed, p) = place(&study(), &floor, &[]).unwrap();
        assert_eq!(p.scale, 1.0);
        assert_eq!(p.shift, [0.0, 0.0]);
        let file = study();
        for (a, b) in placed.iter().zip(&file) {
            assert_eq!([a.x, a.z], [b.x, b.z]);
        }
        assert_eq!(placed[6].y, 0.0, "the terrace target lies on the floor");
    }

    #[test]
    fn a_large_floor_elsewhere_takes_the_whole_layout_unscaled() {
        // 40 m square whose middle is 50 m east of the study's targets.
        let floor = rect(30.0, -25.0, 70.0, 15.0);
        let (placed, p) = place(&study(), &floor, &[]).unwrap();
        assert_eq!(p.scale, 1.0);
        within(&placed, &floor);
        similar(&placed, 1.0);
    }

    #[test]
    fn an_l_shaped_floor_keeps_every_target_on_it() {
        // An L: a 6 x 2 m strip and a 2 x 6 m strip sharing a corner.
        let floor = vec![[0.0, 0.0], [6.0, 0.0], [6.0, 2.0], [2.0, 2.0], [2.0, 6.0], [0.0, 6.0]];
        let (placed, p) = place(&study(), &floor, &[]).unwrap();
        within(&placed, &floor);
        similar(&placed, p.scale);
        assert!(p.scale > 0.01 && p.scale < 0.1, "{p:?}");
    }

    #[test]
    fn the_same_floor_gives_the_same_bits_and_a_floor_too_small_gives_none() {
        let floor = vec![[-1.23, 4.81], [1.19, 4.85], [1.22, 7.2], [-1.25, 7.18]];
        let a = place(&study(), &floor, &[]).unwrap();
        let b = place(&study(), &floor, &[]).unwrap();
        assert_eq!(a, b);
        within(&a.0, &floor);
        assert_eq!(place(&study(), &rect(0.0, 0.0, 0.9, 3.0), &[]), None, "no point is 0.5 m from both long edges");
    }

    #[test]
    fn a_table_keeps_the_targets_from_under_it() {
        // A 4 x 4 m room with a 1.6 x 0.8 m table across its middle: the targets lie on one side.
        let floor = rect(-2.0, 2.0, 2.0, 6.0);
        let table = rect(-0.8, 3.6, 0.8, 4.4);
        let (placed, p) = place(&study(), &floor, std::slice::from_ref(&table)).unwrap();
        within(&placed, &floor);
        similar(&placed, p.scale);
        let t = points(&table);
        for q in &placed {
            let q = (q.x as f64, q.z as f64);
            assert!(!inside(&t, q) && edge_distance(&t, q) >= EDGE_MARGIN_M, "{q:?} under or by the table");
        }
        assert!(p.scale < place(&study(), &floor, &[]).unwrap().1.scale, "less room, a smaller layout: {p:?}");
        assert!(p.edge_m >= EDGE_MARGIN_M as f32);
    }

    #[test]
    fn floors_are_checked() {
        let ok = TaskLayout::Room { floor: rect(0.0, 0.0, 2.0, 2.0), keep_out: vec![] };
        assert_eq!(ok.validate(), Ok(()));
        assert_eq!(TaskLayout::Room { floor: vec![[0.0, 0.0], [1.0, 0.0]], keep_out: vec![] }.validate(), Err(FloorError::Points(2)));
        assert_eq!(TaskLayout::Room { floor: vec![[0.0, 0.0], [1.0, f32::NAN], [1.0, 1.0]], keep_out: vec![] }.validate(), Err(FloorError::Point));
        assert_eq!(TaskLayout::Room { floor: vec![[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]], keep_out: vec![] }.validate(), Err(FloorError::Area));
        assert_eq!(TaskLayout::Room { floor: vec![[0.0, 0.0]; 300], keep_out: vec![] }.validate(), Err(FloorError::Points(300)));
        assert_eq!(TaskLayout::Room { floor: rect(0.0, 0.0, 2.0, 2.0), keep_out: vec![vec![[0.0, 0.0], [1.0, 0.0]]] }.validate(), Err(FloorError::KeepOut));
        assert_eq!(TaskLayout::Room { floor: rect(0.0, 0.0, 2.0, 2.0), keep_out: vec![rect(0.5, 0.5, 1.0, 1.0); 17] }.validate(), Err(FloorError::KeepOut));
        let many = (0..253).map(|i| [i as f32, (i % 2) as f32]).collect::<Vec<_>>();
        assert_eq!(TaskLayout::Room { floor: rect(0.0, 0.0, 2.0, 2.0), keep_out: vec![many[..252].to_vec()] }.validate(), Ok(()), "256 points in all");
        assert_eq!(TaskLayout::Room { floor: rect(0.0, 0.0, 2.0, 2.0), keep_out: vec![many] }.validate(), Err(FloorError::KeepOut), "257 points in all");
    }
}
