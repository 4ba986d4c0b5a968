//! The spatial index: parry3d acceleration structures for ray queries against planes and trees.
//!
//! It is a cache derived from the world (plane meshes and tree transforms), rebuilt when the
//! systems mark it dirty. It is not part of the world hash. Queries use a BVH over the trees'
//! bounds and each plane's own triangle BVH, never a linear scan of the trees.
//!
//! A tree whose catalogue model has a pick shape ([`PickShape`]: a stack of vertical cylinders as
//! wide as the model at each height) is hit only where the ray meets that shape, each band grown
//! by the wind's largest sway at its height; its box only bounds it in the BVH. So the ground
//! between a trunk and the rim of its crown can be pointed at. A model without a pick shape is
//! hit by its box.

use glam::{Quat, Vec3};
use hecs::{Entity, World};
use parry3d::bounding_volume::Aabb;
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhNode};
use parry3d::query::{Ray, RayCast, RayIntersection};
use parry3d::shape::Cuboid;

use crate::catalogue::{Catalogue, PICK_BANDS, PickShape};
use crate::components::{Plane, Scale, Transform, Tree, Wind};
pub use crate::plane_grid::plane_trimesh;
use crate::plane_grid::{PlaneMesh, shared_plane_mesh};
use crate::wind_model::{SwayExtent, max_sway};

/// A tree as the index sees it: its entity and its oriented box in world space.
#[derive(Clone, Copy, Debug)]
pub struct TreeBox {
    /// The tree entity.
    pub entity: Entity,
    /// Centre of the box, world space.
    pub center: Vec3,
    /// Half extents along the box's own axes.
    pub half_extents: Vec3,
    /// Rotation about +Y, radians.
    pub yaw: f32,
}

/// A ray hit on a plane or a tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The entity hit.
    pub entity: Entity,
    /// Distance along the ray, metres.
    pub distance: f32,
    /// The hit point.
    pub point: Vec3,
    /// The surface normal at the hit point (unit length, facing the ray origin for planes).
    pub normal: Vec3,
}

/// Acceleration structures for ray queries, derived from the world.
#[derive(Default)]
pub struct SpatialIndex {
    planes: Vec<(Entity, std::sync::Arc<PlaneMesh>)>,
    trees: Vec<TreeBox>,
    /// Per tree (same order as `trees`), its pick shape, if its model has one.
    picks: Vec<Option<TreePick>>,
    tree_bvh: Bvh,
    /// A BVH for ray casts with tighter leaves: a tree with a pick shape has one leaf per run of
    /// bands of similar width (so a ray under a crown only enters the trunk's thin leaf), a tree
    /// without one has its box.
    ray_bvh: Bvh,
    /// Per leaf of `ray_bvh`, the index of its tree in `trees`.
    ray_leaf_tree: Vec<u32>,
    planes_dirty: bool,
    trees_dirty: bool,
    built_once: bool,
    generation: u64,
    tree_changes: u64,
    /// The inputs of the last controller ray cast, so that an unchanged ray in an unchanged
    /// world is not cast again (see the raycast system).
    pub last_ray: Option<RayKey>,
}

/// Everything a controller ray cast depends on. Equal keys give equal hits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayKey {
    /// Ray origin.
    pub origin: Vec3,
    /// Ray direction.
    pub dir: Vec3,
    /// The index's generation (bumped on every rebuild).
    pub generation: u64,
    /// The dragged tree, if any.
    pub dragged: Option<u64>,
    /// The selected tree's box (centre, half extents, yaw), if a tree is selected.
    pub selected: Option<(u64, Vec3, Vec3, f32)>,
    /// Ray length and handle radius from the config.
    pub limits: (f32, f32),
}

/// The world-space oriented box of a tree from its transform, scale and catalogue bounds.
pub fn tree_box(entity: Entity, transform: &Transform, scale: f32, min: Vec3, max: Vec3) -> TreeBox {
    let local_center = (min + max) * 0.5 * scale;
    let rot = Quat::from_rotation_y(transform.yaw);
    TreeBox {
        entity,
        center: transform.translation + rot * local_center,
        half_extents: (max - min) * 0.5 * scale,
        yaw: transform.yaw,
    }
}

impl SpatialIndex {
    /// Marks the tree structure for a rebuild before the next query.
    ///
    /// Every system that adds, removes or moves a tree calls this (a tree being dragged or moved
    /// with the touchpad once, when the move ends), so [`SpatialIndex::tree_changes`] tells
    /// readers whether the trees can have changed.
    pub fn mark_trees_dirty(&mut self) {
        self.trees_dirty = true;
        self.tree_changes += 1;
    }

    /// How often the trees were marked changed: equal counts mean that no tree was added,
    /// removed or moved in between, except a tree still being dragged or moved with the touchpad.
    pub fn tree_changes(&self) -> u64 {
        self.tree_changes
    }

    /// Marks the plane structure for a rebuild before the next query.
    pub fn mark_planes_dirty(&mut self) {
        self.planes_dirty = true;
    }

    /// Rebuilds whatever is dirty (everything on first use) from the world.
    pub fn refresh(&mut self, world: &World, catalogue: &Catalogue) {
        let rebuilt = self.planes_dirty || self.trees_dirty;
        if !self.built_once || self.planes_dirty {
            self.planes.clear();
            for (e, plane) in world.query::<(Entity, &Plane)>().iter() {
                if let Some(mesh) = shared_plane_mesh(plane) {
                    self.planes.push((e, mesh));
                }
            }
            self.planes.sort_by_key(|(e, _)| e.to_bits());
            self.planes_dirty = false;
        }
        if !self.built_once || self.trees_dirty {
            self.trees.clear();
            // Ray boxes and pick shapes include the wind's largest possible sway, so that a
            // swaying crown is always inside the shape that picks it (a constant pad, so picking
            // never flickers).
            let wind = world.query::<&Wind>().iter().next().copied();
            let mut found: Vec<(TreeBox, Option<TreePick>)> = Vec::new();
            for (e, t, s, tree) in world.query::<(Entity, &Transform, &Scale, &Tree)>().iter() {
                if let Some(m) = catalogue.get(tree.model) {
                    let mut b = tree_box(e, t, s.0, m.bounds_min, m.bounds_max);
                    let mut pads = [0.0; PICK_BANDS];
                    if let Some(w) = &wind {
                        let sway = max_sway(w, w.model, SwayExtent::from_bounds(m.height(), m.crown_radius, s.0));
                        b.half_extents += Vec3::new(sway, 0.0, sway);
                        if let Some(p) = &m.pick {
                            // A band sways at most as far as a tree as tall as the band's top
                            // and as wide as the band.
                            let h = p.band_height();
                            for (i, pad) in pads.iter_mut().enumerate() {
                                let height = (p.bottom + h * (i + 1) as f32 - m.bounds_min.y).max(0.0);
                                *pad = max_sway(w, w.model, SwayExtent::from_bounds(height, p.radii[i], s.0));
                            }
                        }
                    }
                    let pick = m.pick.map(|shape| TreePick::new(shape, t, s.0, pads));
                    found.push((b, pick));
                }
            }
            found.sort_by_key(|(b, _)| b.entity.to_bits());
            self.picks = found.iter().map(|(_, p)| *p).collect();
            self.trees = found.into_iter().map(|(b, _)| b).collect();
            let leaves: Vec<Aabb> = self.trees.iter().map(box_aabb).collect();
            self.tree_bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves);
            let mut ray_leaves = Vec::with_capacity(leaves.len());
            self.ray_leaf_tree.clear();
            for (i, (pick, aabb)) in self.picks.iter().zip(&leaves).enumerate() {
                match pick {
                    Some(p) => p.band_aabbs(|a| {
                        ray_leaves.push(a);
                        self.ray_leaf_tree.push(i as u32);
                    }),
                    None => {
                        ray_leaves.push(*aabb);
                        self.ray_leaf_tree.push(i as u32);
                    }
                }
            }
            self.ray_bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &ray_leaves);
            self.trees_dirty = false;
        }
        if !self.built_once || rebuilt {
            self.generation += 1;
        }
        self.built_once = true;
    }

    /// A number that changes whenever the index is rebuilt.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Number of trees in the index.
    pub fn tree_count(&self) -> usize {
        self.trees.len()
    }

    /// The nearest tree hit along a ray found by testing every tree in turn (no BVH): the
    /// reference that [`SpatialIndex::cast_trees`] must agree with. Among trees hit at the same
    /// distance it returns the first in index order.
    pub fn cast_trees_plain(&self, origin: Vec3, dir: Vec3, max_dist: f32, exclude: Option<Entity>) -> Option<RayHit> {
        let mut best: Option<(usize, f32)> = None;
        for (i, b) in self.trees.iter().enumerate() {
            if Some(b.entity) == exclude {
                continue;
            }
            let inside = match &self.picks[i] {
                Some(p) => p.contains(origin),
                None => box_contains(b, origin),
            };
            let t = if inside {
                Some(0.0)
            } else {
                match &self.picks[i] {
                    Some(p) => p.ray(origin, dir, max_dist),
                    None => box_ray(b, origin, dir, max_dist),
                }
            };
            if let Some(t) = t.filter(|t| inside || *t < max_dist) {
                if best.is_none_or(|(_, d)| t < d) {
                    best = Some((i, t));
                }
            }
        }
        let (i, toi) = best?;
        let b = &self.trees[i];
        let point = origin + dir * toi;
        let normal = match &self.picks[i] {
            Some(p) => p.normal(point),
            None => box_normal(b, point),
        };
        Some(RayHit { entity: b.entity, distance: toi, point, normal })
    }

    /// The nearest plane hit along a ray, if any, within `max_dist`. Each plane's triangles are
    /// found through its grid of cells ([`PlaneMesh::cast`]), with the very result of parry's
    /// BVH search ([`SpatialIndex::cast_planes_plain`]).
    pub fn cast_planes(&self, origin: Vec3, dir: Vec3, max_dist: f32) -> Option<RayHit> {
        self.cast_planes_with(origin, dir, max_dist, PlaneMesh::cast)
    }

    /// [`SpatialIndex::cast_planes`] through parry's BVH search of each plane alone: the
    /// reference the grid must agree with.
    pub fn cast_planes_plain(&self, origin: Vec3, dir: Vec3, max_dist: f32) -> Option<RayHit> {
        self.cast_planes_with(origin, dir, max_dist, PlaneMesh::cast_plain)
    }

    fn cast_planes_with(
        &self,
        origin: Vec3,
        dir: Vec3,
        max_dist: f32,
        cast: impl Fn(&PlaneMesh, &Ray, f32) -> Option<RayIntersection>,
    ) -> Option<RayHit> {
        let ray = Ray::new(origin, dir);
        let mut best: Option<RayHit> = None;
        for (e, mesh) in &self.planes {
            let limit = best.map_or(max_dist, |b| b.distance);
            if let Some(hit) = cast(mesh, &ray, limit) {
                let mut n = hit.normal.normalize_or(Vec3::Y);
                if n.dot(dir) > 0.0 {
                    n = -n;
                }
                best = Some(RayHit {
                    entity: *e,
                    distance: hit.time_of_impact,
                    point: origin + dir * hit.time_of_impact,
                    normal: n,
                });
            }
        }
        best
    }

    /// The nearest tree hit along a ray, if any, within `max_dist`, skipping `exclude`.
    pub fn cast_trees(&self, origin: Vec3, dir: Vec3, max_dist: f32, exclude: Option<Entity>) -> Option<RayHit> {
        if self.trees.is_empty() {
            return None;
        }
        // A ray that starts inside a tree (its pick shape, or its box if it has none) hits it at
        // distance 0. A point query finds such a tree in one descent, which in a dense forest is
        // much cheaper than the search below. It descends the tighter leaves: a point at head
        // height lies inside the boxes of every crown around it, but only inside the leaves of
        // the bands at its height, so the query meets far fewer boxes there (in the benchmark's
        // forest of 10k trees on 30 × 30 m, about 90 nodes and 3 leaves against 290 and 75).
        // Every point inside a pick shape is inside one of its leaves (they are grown by a
        // margin). Inside several trees, the first tree the query meets is named.
        let inside = self
            .ray_bvh
            .leaves(|node| {
                let a = node.aabb();
                origin.cmpge(a.mins).all() && origin.cmple(a.maxs).all()
            })
            .map(|leaf| self.ray_leaf_tree[leaf as usize])
            .find(|&i| {
                let b = &self.trees[i as usize];
                Some(b.entity) != exclude
                    && match &self.picks[i as usize] {
                        Some(p) => p.contains(origin),
                        None => box_contains(b, origin),
                    }
            });
        if let Some(i) = inside {
            let b = &self.trees[i as usize];
            let normal = match &self.picks[i as usize] {
                Some(p) => p.normal(origin),
                None => box_normal(b, origin),
            };
            return Some(RayHit { entity: b.entity, distance: 0.0, point: origin, normal });
        }
        // Best-first search with each node's ray entry distance clamped at 0. (Bvh::cast_ray
        // scores a node that contains the ray origin by a negative entry distance, so once a
        // hit at distance 0 is found it still visits every box around the origin; in a dense
        // forest that is dozens of boxes per ray.)
        let inv = dir.recip();
        let node_cost = |node: &BvhNode, _best: f32| {
            let a = node.aabb();
            let (t1, t2) = ((a.mins - origin) * inv, (a.maxs - origin) * inv);
            let tmin = t1.min(t2).max_element().max(0.0);
            let tmax = t1.max(t2).min_element();
            if tmax >= tmin { tmin } else { f32::MAX }
        };
        let tree_ray = |i: u32, best: f32| {
            let b = &self.trees[i as usize];
            if Some(b.entity) == exclude {
                return None;
            }
            match &self.picks[i as usize] {
                Some(p) => p.ray(origin, dir, best),
                None => box_ray(b, origin, dir, best),
            }
        };
        // The search over the tighter leaves. It also notes whether a second tree is hit at
        // exactly the nearest distance: which of tied trees is named depends on the order the
        // search meets them, so then the search is run again over one box per tree, as before
        // the tighter leaves, to name the same tree as ever.
        let best_tree = std::cell::Cell::new(u32::MAX);
        let tie_at = std::cell::Cell::new(f32::NAN);
        let (leaf, toi) = self.ray_bvh.find_best(max_dist, node_cost, |leaf, best| {
            let i = self.ray_leaf_tree[leaf as usize];
            let t = tree_ray(i, best)?;
            if t < best {
                best_tree.set(i);
            } else if t == best && i != best_tree.get() {
                tie_at.set(t);
            }
            Some(t)
        })?;
        let (leaf, toi) = if tie_at.get() == toi {
            let (i, t) = self.tree_bvh.find_best(max_dist, node_cost, tree_ray)?;
            (i, t)
        } else {
            (self.ray_leaf_tree[leaf as usize], toi)
        };
        let b = &self.trees[leaf as usize];
        let point = origin + dir * toi;
        let normal = match &self.picks[leaf as usize] {
            Some(p) => p.normal(point),
            None => box_normal(b, point),
        };
        Some(RayHit { entity: b.entity, distance: toi, point, normal })
    }

    /// The nearest hit on a plane or a tree.
    pub fn cast(&self, origin: Vec3, dir: Vec3, max_dist: f32, exclude: Option<Entity>) -> Option<RayHit> {
        nearest(self.cast_trees(origin, dir, max_dist, exclude), |limit| self.cast_planes(origin, dir, limit), max_dist)
    }

    /// The plane directly below `point` (casting straight down from `lift` metres above it), as
    /// the hit on that plane. `None` over a hole or off every plane's edge.
    pub fn ground_below(&self, point: Vec3, lift: f32) -> Option<RayHit> {
        let origin = point + Vec3::Y * lift;
        self.cast_planes(origin, Vec3::NEG_Y, 1.0e4)
    }
}

/// The nearer of a tree hit and the plane hit that `planes` finds within a limit: the planes are
/// cast only up to the tree hit (trees are cheap to test and often near), and a tree wins a tie.
/// A tree hit at distance 0 (the ray starts inside it) cannot be beaten, so then the planes are
/// not cast at all (a plane cast with a limit of 0 still costs about as much as a full one).
pub fn nearest(tree: Option<RayHit>, planes: impl FnOnce(f32) -> Option<RayHit>, max_dist: f32) -> Option<RayHit> {
    if let Some(t) = tree.filter(|t| t.distance <= 0.0) {
        return Some(t);
    }
    let p = planes(tree.map_or(max_dist, |t| t.distance));
    match (tree, p) {
        (Some(t), Some(p)) if p.distance < t.distance => Some(p),
        (Some(t), _) => Some(t),
        (None, p) => p,
    }
}

/// A tree's pick shape placed in the world: the model-space bands grown by the wind's sway, and
/// the tree's position, yaw and scale.
#[derive(Clone, Copy, Debug)]
pub struct TreePick {
    shape: PickShape,
    base: Vec3,
    yaw: f32,
    /// The rotation from world to model axes (about +Y by minus the yaw), kept so that each
    /// ray test does not rebuild it.
    inv_rot: Quat,
    scale: f32,
    /// Per band, the sway pad in model units.
    pads: [f32; PICK_BANDS],
}

impl TreePick {
    /// Places `shape` at a tree's transform and scale; `pads` are the wind's largest sway of
    /// each band, world metres.
    pub fn new(shape: PickShape, t: &Transform, scale: f32, pads: [f32; PICK_BANDS]) -> TreePick {
        let scale = if scale.is_finite() && scale > 1e-6 { scale } else { 1e-6 };
        TreePick {
            shape,
            base: t.translation,
            yaw: t.yaw,
            inv_rot: Quat::from_rotation_y(-t.yaw),
            scale,
            pads: pads.map(|p| p / scale),
        }
    }

    /// A world point in model space.
    fn local(&self, p: Vec3) -> Vec3 {
        self.inv_rot * (p - self.base) / self.scale
    }

    /// Calls `leaf` with world-space boxes that together bound the shape: one per run of
    /// non-empty bands of similar width (each band's radius, pad included, within a factor of
    /// two of the run's narrowest), grown by a small margin so that rounding never lets the
    /// shape poke out of them.
    pub fn band_aabbs(&self, mut leaf: impl FnMut(Aabb)) {
        let s = &self.shape;
        let h = s.band_height();
        let mut emit = |first: usize, last: usize, r: f32| {
            let y0 = s.bottom + h * first as f32;
            let y1 = s.bottom + h * (last + 1) as f32;
            let (r, y0, y1) = (r * self.scale, y0 * self.scale, y1 * self.scale);
            let margin = 1e-3 + 1e-4 * (r + y0.abs().max(y1.abs()) + self.base.abs().max_element());
            let mins = self.base + Vec3::new(-r, y0, -r) - Vec3::splat(margin);
            let maxs = self.base + Vec3::new(r, y1, r) + Vec3::splat(margin);
            leaf(Aabb::new(mins, maxs));
        };
        // The current run: first band, last band, narrowest and widest radius.
        let mut run: Option<(usize, usize, f32, f32)> = None;
        for i in 0..PICK_BANDS {
            let r = s.radii[i] + self.pads[i];
            if s.radii[i] <= 0.0 {
                if let Some((a, b, _, w)) = run.take() {
                    emit(a, b, w);
                }
                continue;
            }
            run = match run {
                Some((a, _, n, w)) if r <= 2.0 * n && r >= 0.5 * w => Some((a, i, n.min(r), w.max(r))),
                Some((a, b, _, w)) => {
                    emit(a, b, w);
                    Some((i, i, r, r))
                }
                None => Some((i, i, r, r)),
            };
        }
        if let Some((a, b, _, w)) = run {
            emit(a, b, w);
        }
    }

    /// Whether a world point is inside.
    pub fn contains(&self, p: Vec3) -> bool {
        self.shape.contains(self.local(p), &self.pads)
    }

    /// The first distance along the ray (world units, `dir` as given) at which it enters the
    /// shape, within `max`.
    pub fn ray(&self, origin: Vec3, dir: Vec3, max: f32) -> Option<f32> {
        // In model space with the direction scaled too, distances along the ray are unchanged.
        let rot = self.inv_rot;
        let o = rot * (origin - self.base) / self.scale;
        let d = rot * dir / self.scale;
        let s = &self.shape;
        let h = s.band_height();
        let (lo, hi) = y_span(o.y, d.y, s.bottom, s.top)?;
        let (lo, hi) = (lo.max(0.0), hi.min(max));
        if lo > hi {
            return None;
        }
        // Only the bands the ray passes through while inside the shape's height.
        let (ya, yb) = (o.y + d.y * lo, o.y + d.y * hi);
        let band_of = |y: f32| (((y - s.bottom) / h).max(0.0) as usize).min(PICK_BANDS - 1);
        let (first, last) = (band_of(ya.min(yb)), band_of(ya.max(yb)));
        let mut best: Option<f32> = None;
        for i in first..=last {
            if s.radii[i] <= 0.0 {
                continue;
            }
            let y0 = s.bottom + h * i as f32;
            let Some((b0, b1)) = y_span(o.y, d.y, y0, y0 + h) else { continue };
            let Some((c0, c1)) = cylinder_span(o, d, s.radii[i] + self.pads[i]) else { continue };
            let t0 = b0.max(c0).max(lo);
            let t1 = b1.min(c1).min(hi);
            if t0 <= t1 && best.is_none_or(|b| t0 < b) {
                best = Some(t0);
            }
        }
        best
    }

    /// The outward normal (world space) at a point on the shape: along the radius, or up or
    /// down at the top or bottom of a band.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        let l = self.local(p);
        let radial = Vec3::new(l.x, 0.0, l.z);
        let n = match self.shape.band(l.y) {
            Some(i) if radial.length() < (self.shape.radii[i] + self.pads[i]) * 0.999 => {
                if l.y > (self.shape.bottom + self.shape.top) * 0.5 { Vec3::Y } else { Vec3::NEG_Y }
            }
            _ => radial.normalize_or(Vec3::X),
        };
        Quat::from_rotation_y(self.yaw) * n
    }
}

/// The ray parameters for which `oy + t dy` lies in `[lo, hi]`.
fn y_span(oy: f32, dy: f32, lo: f32, hi: f32) -> Option<(f32, f32)> {
    if dy.abs() < 1e-12 {
        return (oy >= lo && oy <= hi).then_some((f32::NEG_INFINITY, f32::INFINITY));
    }
    let (a, b) = ((lo - oy) / dy, (hi - oy) / dy);
    Some((a.min(b), a.max(b)))
}

/// The ray parameters inside the vertical infinite cylinder of radius `r` around the Y axis.
fn cylinder_span(o: Vec3, d: Vec3, r: f32) -> Option<(f32, f32)> {
    let a = d.x * d.x + d.z * d.z;
    let c = o.x * o.x + o.z * o.z - r * r;
    if a <= 1e-12 {
        // Parallel to the axis: inside all along, or never.
        return (c <= 0.0).then_some((f32::NEG_INFINITY, f32::INFINITY));
    }
    let b = o.x * d.x + o.z * d.z;
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    let q = disc.sqrt();
    Some(((-b - q) / a, (-b + q) / a))
}

fn box_aabb(b: &TreeBox) -> Aabb {
    let (s, c) = libm::sincosf(b.yaw);
    let hx = b.half_extents.x * c.abs() + b.half_extents.z * s.abs();
    let hz = b.half_extents.x * s.abs() + b.half_extents.z * c.abs();
    let h = Vec3::new(hx, b.half_extents.y, hz);
    Aabb::new(b.center - h, b.center + h)
}

fn box_ray(b: &TreeBox, origin: Vec3, dir: Vec3, max: f32) -> Option<f32> {
    let inv = Quat::from_rotation_y(-b.yaw);
    let local = Ray::new(inv * (origin - b.center), inv * dir);
    Cuboid::new(b.half_extents).cast_local_ray(&local, max, true)
}

fn box_contains(b: &TreeBox, point: Vec3) -> bool {
    let local = Quat::from_rotation_y(-b.yaw) * (point - b.center);
    local.abs().cmple(b.half_extents).all()
}

fn box_normal(b: &TreeBox, point: Vec3) -> Vec3 {
    let rot = Quat::from_rotation_y(b.yaw);
    let local = rot.inverse() * (point - b.center);
    let rel = local / b.half_extents.max(Vec3::splat(1e-6));
    let a = rel.abs();
    let n = if a.x >= a.y && a.x >= a.z {
        Vec3::X * rel.x.signum()
    } else if a.y >= a.z {
        Vec3::Y * rel.y.signum()
    } else {
        Vec3::Z * rel.z.signum()
    };
    rot * n
}
