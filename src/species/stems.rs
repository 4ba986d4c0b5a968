//! The stems of a Weber–Penn tree: the trunk, its branches to `levels.len()` levels, their
//! curves, splits, pruning, and the leaves on the last level, as polylines with radii and frames.
//!
//! After Weber and Penn, "Creation and rendering of realistic trees" (SIGGRAPH 1995). Every random
//! number is drawn from one seeded ChaCha generator in depth-first order (and each stem's shape
//! from its own seed, so a pruned stem is the same stem, shorter), all in f32: the same preset
//! and seed give the same stems.

use std::f32::consts::PI;

use glam::{Quat, Vec2, Vec3};

use super::preset::{Level, Preset, Shape};
use crate::assetgen::geometry::Rng;

/// The most stems a tree may have (splits and branches together); past it, no more are made.
pub const MAX_STEMS: usize = 60_000;
/// The most leaves a tree may have.
pub const MAX_LEAVES: usize = 400_000;

/// One point of a stem.
#[derive(Clone, Copy, Debug)]
pub struct Node {
    /// Position, metres.
    pub pos: Vec3,
    /// Radius, metres.
    pub radius: f32,
    /// Orientation: local +Y along the stem.
    pub frame: Quat,
    /// Distance from the stem's base along it, metres.
    pub s: f32,
}

/// A stem (the trunk, a branch, or a clone from a split).
#[derive(Clone, Debug)]
pub struct Stem {
    /// Level: 0 the trunk.
    pub level: usize,
    /// Points from base to tip.
    pub nodes: Vec<Node>,
    /// The first-level branch this stem belongs to, as a wind phase in 0..1 (0 on the trunk).
    pub phase: f32,
}

/// One leaf (or shoot card).
#[derive(Clone, Copy, Debug)]
pub struct Leaf {
    /// Where it hangs on its stem.
    pub attach: Vec3,
    /// Direction from the base to the tip.
    pub dir: Vec3,
    /// The leaf's face normal.
    pub normal: Vec3,
    /// Its stem's wind phase.
    pub phase: f32,
    /// A random number in 0..1 for its colour.
    pub tint: f32,
    /// How far it lies out from the middle of its clump, 0..1 (1 for a leaf in no clump): the
    /// clump's inside is darker.
    pub depth: f32,
}

/// A generated tree.
#[derive(Clone, Debug, Default)]
pub struct Tree {
    /// The stems, trunk first.
    pub stems: Vec<Stem>,
    /// The leaves (cards of level of detail 0: a leaf, or a sprig or shoot of `card_leaves`).
    pub leaves: Vec<Leaf>,
    /// The tree's scale, metres (its height before variation and branches).
    pub scale: f32,
}

/// Weber and Penn's shape ratio of `shape` at `r` in 0..1.
pub fn shape_ratio(shape: Shape, r: f32, p: &Preset) -> f32 {
    let r = r.clamp(0.0, 1.0);
    match shape {
        Shape::Conical => 0.2 + 0.8 * r,
        Shape::Spherical => 0.2 + 0.8 * (PI * r).sin(),
        Shape::Hemispherical => 0.2 + 0.8 * (0.5 * PI * r).sin(),
        Shape::Cylindrical => 1.0,
        Shape::TaperedCylindrical => 0.5 + 0.5 * r,
        Shape::Flame => {
            if r <= 0.7 {
                r / 0.7
            } else {
                (1.0 - r) / 0.3
            }
        }
        Shape::InverseConical => 1.0 - 0.8 * r,
        Shape::TendFlame => {
            if r <= 0.7 {
                0.5 + 0.5 * r / 0.7
            } else {
                0.5 + 0.5 * (1.0 - r) / 0.3
            }
        }
        Shape::Envelope => envelope(r, p),
    }
}

/// The pruning envelope's width at `r` (1 at the crown's base, 0 at the top).
fn envelope(r: f32, p: &Preset) -> f32 {
    let peak = p.prune_width_peak;
    if r < 1.0 - peak {
        (r / (1.0 - peak).max(1e-3)).powf(p.prune_power_high)
    } else {
        ((1.0 - r) / peak.max(1e-3)).max(0.0).powf(p.prune_power_low)
    }
}

struct Gen<'a> {
    p: &'a Preset,
    rng: Rng,
    tree: Tree,
    base_len: f32,
}

/// ± `v` at random.
fn pm(rng: &mut Rng, v: f32) -> f32 {
    rng.range(-v, v)
}

/// Generates the tree of preset `p` with `seed`.
pub fn generate(p: &Preset, seed: u64) -> Tree {
    let mut rng = Rng::new(seed ^ 0x9e37_79b9_7f4a_7c15);
    let scale = (p.height + pm(&mut rng, p.height_v)).max(0.1);
    let l0 = &p.levels[0];
    let trunk_len = scale * (l0.length + pm(&mut rng, l0.length_v)).max(0.05);
    let mut g = Gen { p, rng, tree: Tree { scale, ..Tree::default() }, base_len: scale * p.base_size };
    let radius = trunk_len * p.ratio;
    let stems = 1 + p.base_splits as usize;
    let turn0 = g.rng.range(0.0, 2.0 * PI);
    for k in 0..stems {
        let frame = if k == 0 && stems == 1 {
            Quat::IDENTITY
        } else {
            let az = turn0 + k as f32 * 2.0 * PI / stems as f32;
            let tilt = (l0.split_angle_deg + pm(&mut g.rng, l0.split_angle_v_deg)).to_radians()
                * if k == 0 { 0.3 } else { 1.0 };
            Quat::from_rotation_y(az) * Quat::from_rotation_x(tilt)
        };
        let len = if k == 0 { trunk_len } else { trunk_len * g.rng.range(0.7, 1.0) };
        let r = if k == 0 { radius } else { radius * 0.8 };
        let seed = seed_of(&mut g.rng);
        g.stem(0, Vec3::ZERO, frame, len, r, 0.0, 0.0, seed);
    }
    g.tree
}

/// A 64-bit seed for a sub-generator.
fn seed_of(rng: &mut Rng) -> u64 {
    ((rng.f() * 16_777_216.0) as u64) << 40 | ((rng.f() * 16_777_216.0) as u64) << 16 | (rng.f() * 65_536.0) as u64
}

/// The point, radius and frame at distance `s` from the base of the stem whose points are `nodes`.
fn at(nodes: &[Node], s: f32) -> Node {
    let k = nodes.partition_point(|n| n.s <= s).clamp(1, nodes.len() - 1);
    let (a, b) = (&nodes[k - 1], &nodes[k]);
    let t = ((s - a.s) / (b.s - a.s).max(1e-6)).clamp(0.0, 1.0);
    Node {
        pos: a.pos.lerp(b.pos, t),
        radius: a.radius + (b.radius - a.radius) * t,
        frame: a.frame.slerp(b.frame, t),
        s,
    }
}

/// The frame of a stem growing level from a parent whose frame is `parent`: turned `side_deg`
/// from the parent's heading in the horizontal plane, or, from an upright parent, towards the
/// azimuth `rot_deg`.
fn flat_frame(parent: Quat, rot_deg: f32, side_deg: f32) -> Quat {
    let d = parent * Vec3::Y;
    let heading = Vec3::new(d.x, 0.0, d.z);
    let dir = if heading.length() < 0.3 {
        let a = rot_deg.to_radians();
        Vec3::new(a.cos(), 0.0, a.sin())
    } else {
        Quat::from_rotation_y(side_deg.to_radians()) * heading.normalize()
    };
    Quat::from_rotation_arc(Vec3::Y, dir).normalize()
}

impl Gen<'_> {
    /// Whether a point is inside the pruning envelope.
    fn inside(&self, q: Vec3) -> bool {
        let crown = (self.tree.scale - self.base_len).max(1e-3);
        let r = (self.tree.scale - q.y) / crown;
        if !(0.0..=1.0).contains(&r) {
            return false;
        }
        Vec2::new(q.x, q.z).length() <= self.p.prune_width * self.tree.scale * envelope(r, self.p)
    }

    /// The radius of a stem of level `level`, base radius `radius`, at fraction `z` of its length.
    fn radius_at(&self, level: usize, radius: f32, z: f32) -> f32 {
        let taper = self.p.levels[level].taper;
        let mut r = radius * (1.0 - taper * z);
        if level == 0 {
            let y = (1.0 - 8.0 * z).max(0.0);
            r *= 1.0 + self.p.flare * (100f32.powf(y) - 1.0) / 100.0;
        }
        r.max(0.0008)
    }

    /// The polylines of one stem: the stem itself and the clones its splits make.
    #[allow(clippy::too_many_arguments)]
    fn curve(&self, level: usize, start: Vec3, frame: Quat, len: f32, radius: f32, seed: u64) -> Vec<Vec<Node>> {
        let lv: &Level = &self.p.levels[level];
        let res = lv.curve_res.max(1) as usize;
        let seg = len / res as f32;
        let mut rng = Rng::new(seed);
        let curve_v = pm(&mut rng, lv.curve_v_deg);
        let half = res.div_ceil(2).max(1) as f32;
        let mut out = Vec::new();
        let mut err = 0.0f32;
        let first = Node { pos: start, radius: self.radius_at(level, radius, 0.0), frame, s: 0.0 };
        let mut work = vec![(0usize, vec![first])];
        while let Some((seg0, mut nodes)) = work.pop() {
            let last = *nodes.last().expect("a polyline starts with a point");
            let (mut pos, mut frame) = (last.pos, last.frame);
            for i in seg0..res {
                let mut bend = if lv.curve_back_deg == 0.0 {
                    lv.curve_deg / res as f32
                } else if (i as f32) < half {
                    lv.curve_deg / half
                } else {
                    lv.curve_back_deg / half
                };
                bend += curve_v / res as f32;
                frame = (frame * Quat::from_rotation_x(bend.to_radians())).normalize();
                if level >= 2 && self.p.attraction_up != 0.0 {
                    let dir = frame * Vec3::Y;
                    let target = if self.p.attraction_up > 0.0 { Vec3::Y } else { Vec3::NEG_Y };
                    let axis = dir.cross(target);
                    if axis.length_squared() > 1e-8 {
                        let decl = dir.angle_between(target);
                        let turn = (self.p.attraction_up.abs() / res as f32 * decl * 0.5).min(decl);
                        frame = (Quat::from_axis_angle(axis.normalize(), turn) * frame).normalize();
                    }
                }
                pos += frame * Vec3::Y * seg;
                let z = (i + 1) as f32 / res as f32;
                nodes.push(Node { pos, radius: self.radius_at(level, radius, z), frame, s: z * len });
                if i + 1 < res && out.len() + work.len() < 24 {
                    let n = (lv.seg_splits + err).floor().max(0.0);
                    err += lv.seg_splits - n;
                    let n = n as usize;
                    if n > 0 {
                        let angle =
                            (lv.split_angle_deg + pm(&mut rng, lv.split_angle_v_deg)).max(0.0).to_radians() * 0.5;
                        let az0 = rng.range(0.0, 2.0 * PI);
                        for k in 1..=n {
                            let az = az0 + k as f32 * 2.0 * PI / (n + 1) as f32;
                            let f = (frame * Quat::from_rotation_y(az) * Quat::from_rotation_x(angle)).normalize();
                            let start =
                                Node { pos, radius: nodes.last().map_or(radius, |n| n.radius), frame: f, s: z * len };
                            work.push((i + 1, vec![start]));
                        }
                        frame = (frame * Quat::from_rotation_y(az0) * Quat::from_rotation_x(angle)).normalize();
                    }
                }
            }
            out.push(nodes);
        }
        out
    }

    /// Makes a stem and, depth first, its children and leaves.
    #[allow(clippy::too_many_arguments)]
    fn stem(
        &mut self,
        level: usize,
        start: Vec3,
        frame: Quat,
        length: f32,
        radius: f32,
        phase: f32,
        offset: f32,
        seed: u64,
    ) {
        if self.tree.stems.len() >= MAX_STEMS {
            return;
        }
        let mut len = length;
        if level >= 1 && self.p.prune_ratio > 0.0 {
            let mut l = length;
            for _ in 0..14 {
                let polys = self.curve(level, start, frame, l, radius, seed);
                if polys.iter().flatten().all(|n| self.inside(n.pos)) {
                    break;
                }
                l *= 0.8;
            }
            len = length + (l - length) * self.p.prune_ratio;
        }
        let polys = self.curve(level, start, frame, len, radius, seed);
        let last = level + 1 == self.p.levels.len();
        // A split stem's branches and leaves are shared among its clones by the length each covers.
        let base = if level == 0 && !last { self.base_len.min(len * 0.95) } else { 0.0 };
        let covered: f32 =
            polys.iter().filter(|n| n.len() >= 2).map(|n| (n[n.len() - 1].s - n[0].s.max(base)).max(0.0)).sum();
        let share = ((len - base) / covered.max(1e-6)).min(1.0);
        for nodes in polys {
            if nodes.len() < 2 || self.tree.stems.len() >= MAX_STEMS {
                continue;
            }
            let (s0, s1) = (nodes[0].s, nodes[nodes.len() - 1].s);
            self.tree.stems.push(Stem { level, nodes: nodes.clone(), phase });
            if last {
                self.leaves(&nodes, len, offset, phase, share);
            } else {
                self.children(level + 1, &nodes, len, offset, phase, (s0, s1), share);
            }
        }
    }

    /// The stems of level `level` on a parent polyline covering `s0..s1` of a stem of length `len`.
    #[allow(clippy::too_many_arguments)]
    fn children(
        &mut self,
        level: usize,
        nodes: &[Node],
        len: f32,
        offset: f32,
        phase: f32,
        (s0, s1): (f32, f32),
        share: f32,
    ) {
        let lv = self.p.levels[level].clone();
        let base = if level == 1 { self.base_len.min(len * 0.95) } else { 0.0 };
        let (a, b) = (s0.max(base), s1);
        if b <= a {
            return;
        }
        let mut n = lv.branches * share * (b - a) / (len - base).max(1e-3);
        if level >= 2 {
            n *= 1.0 - 0.5 * offset;
        }
        let count = (n + self.rng.f()).floor() as usize;
        let mut rot = self.rng.range(0.0, 360.0);
        let lmax = |rng: &mut Rng| (lv.length + pm(rng, lv.length_v)).max(0.0);
        for i in 0..count {
            let s = a + (b - a) * ((i as f32 + 0.5 + pm(&mut self.rng, 0.3)) / count as f32).clamp(0.0, 1.0);
            let here = at(nodes, s);
            let rel = (len - s) / (len - base).max(1e-3);
            let child_len = if level == 1 {
                len * lmax(&mut self.rng) * shape_ratio(self.p.shape, rel, self.p)
            } else {
                lmax(&mut self.rng) * (len - 0.6 * s)
            };
            if child_len < 0.02 {
                continue;
            }
            let child_r =
                (nodes[0].radius * (child_len / len).powf(self.p.ratio_power)).min(here.radius * 0.9).max(0.001);
            let down = if lv.down_angle_v_deg >= 0.0 {
                lv.down_angle_deg + pm(&mut self.rng, lv.down_angle_v_deg)
            } else {
                lv.down_angle_deg + lv.down_angle_v_deg * (1.0 - 2.0 * shape_ratio(Shape::Conical, rel, self.p))
            };
            let step = if lv.rotate_deg >= 0.0 { lv.rotate_deg } else { 180.0 };
            rot += step + pm(&mut self.rng, lv.rotate_v_deg);
            let frame = if lv.flat {
                flat_frame(here.frame, rot, if i % 2 == 0 { down } else { -down })
            } else {
                (here.frame * Quat::from_rotation_y(rot.to_radians()) * Quat::from_rotation_x(down.to_radians()))
                    .normalize()
            };
            let child_phase = if level == 1 { self.rng.range(0.02, 1.0) } else { phase };
            let seed = seed_of(&mut self.rng);
            self.stem(level, here.pos, frame, child_len, child_r, child_phase, s / len.max(1e-3), seed);
        }
    }

    /// The leaves on a last-level polyline: spread along it, and the share `leaf_clumps` of them
    /// in a clump about its tip (leaves radiating from the clump's middle, deeper ones darker,
    /// one colour shift for the whole clump).
    fn leaves(&mut self, nodes: &[Node], len: f32, offset: f32, phase: f32, share: f32) {
        let (s0, s1) = (nodes[0].s, nodes[nodes.len() - 1].s);
        let a = s0.max(len * 0.1);
        if s1 <= a || self.tree.leaves.len() >= MAX_LEAVES {
            return;
        }
        let n = self.p.leaves * share * shape_ratio(Shape::TaperedCylindrical, offset, self.p) * (s1 - a)
            / (len * 0.9).max(1e-3);
        let count = (n + self.rng.f()).floor() as usize;
        let count = count.min(MAX_LEAVES - self.tree.leaves.len());
        let clumped = if self.p.leaf_clumps > 0.0 {
            ((count as f32 * self.p.leaf_clumps).round() as usize).min(count)
        } else {
            0
        };
        let spread = count - clumped;
        let mut rot = self.rng.range(0.0, 360.0);
        for i in 0..spread {
            let s = a + (s1 - a) * ((i as f32 + 0.5 + pm(&mut self.rng, 0.4)) / spread as f32).clamp(0.0, 1.0);
            let here = at(nodes, s);
            rot += self.p.leaf_rotate_deg + pm(&mut self.rng, 30.0);
            let down = self.p.leaf_down_angle_deg + pm(&mut self.rng, self.p.leaf_down_angle_v_deg);
            let f = here.frame * Quat::from_rotation_y(rot.to_radians()) * Quat::from_rotation_x(down.to_radians());
            let dir = f * Vec3::Y;
            let mut normal = f * Vec3::Z;
            if normal.y < 0.0 {
                normal = -normal;
            }
            let normal = normal.lerp(Vec3::Y, self.p.leaf_bend).normalize_or(Vec3::Y);
            let dir = (dir - normal * normal.dot(dir)).normalize_or(normal.any_orthonormal_vector());
            let tint = self.rng.f();
            self.tree.leaves.push(Leaf { attach: here.pos, dir, normal, phase, tint, depth: 1.0 });
        }
        if clumped > 0 {
            self.clump(&nodes[nodes.len() - 1], clumped, phase);
        }
    }

    /// `count` leaves in a clump about a stem's tip `tip`: their bases fill a ball a little
    /// ahead of the tip, each pointing away from its middle and turned up by `leaf_bend`.
    fn clump(&mut self, tip: &Node, count: usize, phase: f32) {
        let radius = self.p.clump_radius * self.p.leaf_scale;
        let ahead = tip.frame * Vec3::Y;
        let centre = tip.pos + ahead * (0.35 * radius);
        let shift = self.rng.f();
        let v = self.p.clump_colour_v / self.p.leaf_colour_v.max(1e-3);
        for _ in 0..count {
            let u = self.rng.unit();
            let u = (u + ahead * 0.3).normalize_or(ahead);
            // Bases from the middle to 70 % of the radius (the cards reach out to the rest).
            let r = 0.7 * self.rng.f().sqrt();
            let attach = centre + u * (radius * r);
            let mut normal =
                (u.any_orthonormal_vector() * pm(&mut self.rng, 1.0) + Vec3::Y * 0.5 + u * 0.3).normalize_or(Vec3::Y);
            if normal.y < 0.0 {
                normal = -normal;
            }
            let normal = normal.lerp(Vec3::Y, self.p.leaf_bend).normalize_or(Vec3::Y);
            let dir = (u - normal * normal.dot(u)).normalize_or(normal.any_orthonormal_vector());
            // The clump's shift, in the units of the per-leaf variation, plus the leaf's own.
            let own = self.rng.f();
            let tint = (0.5 + (shift - 0.5) * v + (own - 0.5) * 0.5).clamp(0.0, 1.0);
            self.tree.leaves.push(Leaf { attach, dir, normal, phase, tint, depth: r / 0.7 });
        }
    }
}
