//! Raycast system: casts the controller ray and keeps the hit marker at the nearest hit.
//!
//! Reads: `Controller` (ray), `Selection` (the selected tree), `Water`, `Tree`, `Transform`, `Scale`
//! (of the selected tree, for its handles), `Resources::interaction` (the dragged tree),
//! `Resources::config` (`max_ray_length`, `handle_radius`), `Resources::catalogue`,
//! `Resources::task` (a room layout's scale, which scales the handle radius: `task::layout_scale`).
//! Writes: `Resources::spatial` (rebuilt if marked dirty), `HitMarker`.
//!
//! The ray is tested against the planes' triangle meshes (so it passes through holes, which
//! have no triangles), against the water surfaces (a water hit is `HitTarget::Water`, nearer
//! than the pond's bed below it), against the trees through the spatial index's BVH (skipping a tree that
//! is being dragged), and, when a tree is selected and not being dragged, against its 12
//! bounding-box handles (spheres of radius `handle_radius`). The nearest hit wins, except that
//! a handle also wins over a hit up to one handle radius in front of it, so that a handle
//! sitting on the box surface or on the ground can always be grabbed, and over any hit on the
//! selected tree itself, whose ray box is padded by the wind's sway and so encloses the handles.
//!
//! The hit depends only on the ray, the index, the dragged tree, the selected tree's box and two
//! config values. When none of them changed since the last tick, the cast is skipped and the
//! marker keeps its value: the same result, without the work, while the controller is still.

use hecs::World;

use crate::components::{Controller, HitMarker, HitTarget};
use crate::interact;
use crate::resources::Resources;
use crate::single;
use crate::spatial::RayKey;

/// Runs the raycast system.
pub fn run(world: &mut World, res: &mut Resources) {
    res.spatial.refresh(world, &res.catalogue);
    let Some(c) = single::get::<Controller>(world, &res.singles) else { return };
    let (origin, dir) = (c.ray_origin(), c.ray_dir());
    let max = res.config.max_ray_length;
    let dragged = res.interaction.drag.and_then(|d| interact::entity(d.tree));

    let selected = interact::selected_tree(world, &res.singles).and_then(interact::entity);
    let selected_box = match (selected, dragged) {
        (Some(sel), None) => interact::tree_box_of(world, &res.catalogue, &res.boxes, sel),
        _ => None,
    };
    let key = RayKey {
        origin,
        dir,
        generation: res.spatial.generation(),
        dragged: dragged.map(|e| e.to_bits().get()),
        selected: selected_box.map(|b| (b.entity.to_bits().get(), b.center, b.half_extents, b.yaw)),
        limits: (max, res.config.handle_radius * crate::task::layout_scale(res.task.as_ref())),
    };
    if res.spatial.last_ray == Some(key) {
        return;
    }
    res.spatial.last_ray = Some(key);

    let mut marker = HitMarker::default();
    let tree = res.spatial.cast_trees(origin, dir, max, dragged);
    let nearest = crate::spatial::nearest(tree, |limit| res.spatial.cast_planes(origin, dir, limit), max);
    let mut hit = nearest.map(|h| {
        let id = h.entity.to_bits().get();
        (h, if tree.is_some_and(|t| t.entity == h.entity) { HitTarget::Tree(id) } else { HitTarget::Plane(id) })
    });
    // Water is tested after the trees and planes, only up to their hit: a tree or a shore
    // nearer than the surface wins, and in a world without water nothing changes.
    let water = single::water(world, &res.singles);
    if let Some(w) = crate::water::cast(&water, origin, dir, hit.map_or(max, |(h, _)| h.distance)) {
        hit = Some((w, HitTarget::Water(w.entity.to_bits().get())));
    }
    if let Some((hit, target)) = hit {
        marker = HitMarker { visible: true, position: hit.point, normal: hit.normal, distance: hit.distance, target };
    }

    if let Some(b) = selected_box {
        let radius = res.config.handle_radius * crate::task::layout_scale(res.task.as_ref());
        // The handles sit on the selected tree's own box, which lies inside its (sway-padded)
        // ray box: a hit on that tree never hides its handles.
        let own_tree = marker.target == HitTarget::Tree(b.entity.to_bits().get());
        let limit = if marker.visible && !own_tree { (marker.distance + radius).min(max) } else { max };
        if let Some((handle, center, d)) = interact::nearest_handle(origin, dir, &b, radius, limit, &res.boxes) {
            let point = origin + dir * d;
            marker = HitMarker {
                visible: true,
                position: point,
                normal: (point - center).normalize_or(-dir),
                distance: d,
                target: HitTarget::Handle(handle),
            };
        }
    }

    single::for_each_mut::<HitMarker>(world, &res.singles, |m| *m = marker);
}
