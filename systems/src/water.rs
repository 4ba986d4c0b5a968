//! Water bodies: a scene's ponds, their `Water` component and the geometry the interaction
//! systems ask of them.
//!
//! A water body is a simple polygon in the XZ plane at a fixed surface height, with a depth and
//! a colour. It is an entity with a [`Water`] component, part of the world hash (a world without
//! water hashes exactly as before water existed, see `hash.rs`). The controller ray hits the
//! surface ([`cast`]); water is not ground: planting on it is refused, and a tree above it has no
//! ground to snap to ([`dry_ground`]).
//!
//! Units: metres; polygon vertices are (X, Z) pairs; +Y up. The surface is horizontal.

use glam::{Vec2, Vec3};
use hecs::{Entity, World};
use serde::{Deserialize, Serialize};

use crate::limits::{self, MAX_COORD, RAISE};
use crate::spatial::RayHit;

/// A water body in a scene file (`water: [...]` in docs/scenes.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaterDef {
    /// A name, e.g. "pond".
    pub name: String,
    /// The outline, (X, Z) metres, a simple polygon of at least 3 vertices in either winding.
    pub polygon: Vec<Vec2>,
    /// The height of the surface, metres.
    pub height: f32,
    /// The deepest point below the surface, metres; the renderer darkens the water towards it.
    pub depth: f32,
    /// The colour of deep water, linear RGB, each 0..=1.
    pub colour: [f32; 3],
    /// Strength of the ripples' normal maps, 0 (a still mirror) ..= 4. Default 1.
    #[serde(default = "default_ripples")]
    pub ripples: f32,
    /// How fast the ripple patterns drift, metres per second, 0 ..= 10. Default 0.05.
    #[serde(default = "default_ripple_speed")]
    pub ripple_speed: f32,
}

fn default_ripples() -> f32 {
    1.0
}

fn default_ripple_speed() -> f32 {
    0.05
}

/// A water body in the world: the scene's definition, checked. Hashed from its postcard bytes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Water {
    /// The name from the scene.
    pub name: String,
    /// The outline, (X, Z) metres.
    pub polygon: Vec<Vec2>,
    /// The surface height, metres.
    pub height: f32,
    /// The deepest point below the surface, metres.
    pub depth: f32,
    /// The colour of deep water, linear RGB.
    pub colour: [f32; 3],
    /// Ripple strength, 0 = still.
    pub ripples: f32,
    /// Ripple drift speed, metres per second.
    pub ripple_speed: f32,
}

impl From<&WaterDef> for Water {
    fn from(d: &WaterDef) -> Water {
        Water {
            name: d.name.clone(),
            polygon: d.polygon.clone(),
            height: d.height,
            depth: d.depth,
            colour: d.colour,
            ripples: d.ripples,
            ripple_speed: d.ripple_speed,
        }
    }
}

impl WaterDef {
    /// Checks one water body; the message names it and the first problem.
    pub fn validate(&self) -> Result<(), crate::limits::InvalidScene> {
        self.validate_message().map_err(crate::limits::InvalidScene)
    }

    fn validate_message(&self) -> Result<(), String> {
        let what = format!("water '{}'", self.name.escape_debug());
        let n = self.polygon.len();
        if n < 3 {
            return Err(format!("{what}: its polygon has {n} vertices; a water body needs at least 3"));
        }
        if n > limits::MAX_WATER_VERTICES {
            return Err(format!(
                "{what}: {n} polygon vertices is more than the limit of {} ({RAISE})",
                limits::MAX_WATER_VERTICES
            ));
        }
        for (i, v) in self.polygon.iter().enumerate() {
            if !v.is_finite() {
                return Err(format!("{what}: polygon vertex {i} has a NaN or infinite number"));
            }
            if v.abs().max_element() > MAX_COORD {
                return Err(format!("{what}: polygon vertex {i} is beyond the limit of ±{MAX_COORD:e} m"));
            }
        }
        if !(self.height.is_finite() && self.height.abs() <= MAX_COORD) {
            return Err(format!("{what}: height {} must be a finite number within ±{MAX_COORD:e} m", self.height));
        }
        if !(self.depth.is_finite() && self.depth > 0.0 && self.depth <= 1.0e4) {
            return Err(format!("{what}: depth {} must be in (0, 10000] metres", self.depth));
        }
        if let Some(c) = self.colour.iter().find(|c| !(0.0..=1.0).contains(*c)) {
            return Err(format!("{what}: colour component {c} is outside 0..=1 (linear RGB)"));
        }
        if !(0.0..=4.0).contains(&self.ripples) {
            return Err(format!("{what}: ripples {} is outside 0..=4", self.ripples));
        }
        if !(0.0..=10.0).contains(&self.ripple_speed) {
            return Err(format!("{what}: ripple_speed {} is outside 0..=10 metres per second", self.ripple_speed));
        }
        if let Some((a, b)) = crossing_edges(&self.polygon) {
            return Err(format!("{what}: polygon edges {a} and {b} cross; the outline must be a simple polygon"));
        }
        if signed_area(&self.polygon).abs() < 1.0e-6 {
            return Err(format!("{what}: its polygon has no area"));
        }
        Ok(())
    }
}

/// Checks a scene's water list: the count limit, then each body.
pub fn validate_all(water: &[WaterDef]) -> Result<(), crate::limits::InvalidScene> {
    validate_all_message(water).map_err(crate::limits::InvalidScene)
}

fn validate_all_message(water: &[WaterDef]) -> Result<(), String> {
    if water.len() > limits::MAX_WATER_BODIES {
        return Err(format!(
            "{} water bodies is more than the limit of {} per scene ({RAISE})",
            water.len(),
            limits::MAX_WATER_BODIES
        ));
    }
    Ok(water.iter().try_for_each(WaterDef::validate)?)
}

/// Twice the signed area of a polygon (shoelace), positive when counter-clockwise in (X, Z).
pub fn signed_area(p: &[Vec2]) -> f32 {
    let n = p.len();
    (0..n).map(|i| p[i].perp_dot(p[(i + 1) % n])).sum::<f32>() * 0.5
}

/// The first pair of non-adjacent edges that touch or cross, by edge index (edge `i` runs from
/// vertex `i` to vertex `i + 1`), or `None` for a simple polygon. Quadratic in the vertices,
/// which [`limits::MAX_WATER_VERTICES`] bounds.
pub fn crossing_edges(p: &[Vec2]) -> Option<(usize, usize)> {
    let n = p.len();
    let edge = |i: usize| (p[i], p[(i + 1) % n]);
    for i in 0..n {
        for j in i + 1..n {
            // Adjacent edges share a vertex; that is not a crossing.
            if j == i + 1 || (i == 0 && j == n - 1) {
                continue;
            }
            let (a, b) = edge(i);
            let (c, d) = edge(j);
            if segments_touch(a, b, c, d) {
                return Some((i, j));
            }
        }
    }
    None
}

fn segments_touch(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> bool {
    let orient = |p: Vec2, q: Vec2, r: Vec2| (q - p).perp_dot(r - p);
    let (d1, d2, d3, d4) = (orient(c, d, a), orient(c, d, b), orient(a, b, c), orient(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0)) {
        return true;
    }
    let on = |p: Vec2, q: Vec2, r: Vec2| {
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    (d1 == 0.0 && on(c, d, a)) || (d2 == 0.0 && on(c, d, b)) || (d3 == 0.0 && on(a, b, c)) || (d4 == 0.0 && on(a, b, d))
}

/// Whether the point (X, Z) lies inside the polygon (even-odd rule; a point on an edge may go
/// either way).
pub fn contains(polygon: &[Vec2], p: Vec2) -> bool {
    let n = polygon.len();
    let mut inside = false;
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[j]);
        if (a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x {
            inside = !inside;
        }
        j = i;
    }
    inside
}

impl Water {
    /// Whether the point lies over or under this water's surface, within its outline.
    pub fn covers_xz(&self, p: Vec3) -> bool {
        contains(&self.polygon, Vec2::new(p.x, p.z))
    }

    /// The distance along a ray (`dir` unit length) to this surface within `max`, from either
    /// side; `None` for a ray parallel to it or one that meets the plane outside the outline.
    pub fn ray(&self, origin: Vec3, dir: Vec3, max: f32) -> Option<f32> {
        if dir.y.abs() < 1.0e-7 {
            return None;
        }
        let t = (self.height - origin.y) / dir.y;
        if !(t >= 0.0 && t < max) {
            return None;
        }
        self.covers_xz(origin + dir * t).then_some(t)
    }
}

/// The water bodies of a world, copied, sorted by entity: the few, small outlines the
/// interaction systems test against. Empty (and no allocation) in a world without water.
pub fn bodies(world: &World) -> Vec<(Entity, Water)> {
    let mut v: Vec<(Entity, Water)> = world.query::<(Entity, &Water)>().iter().map(|(e, w)| (e, w.clone())).collect();
    v.sort_by_key(|(e, _)| e.to_bits());
    v
}

/// The nearest water surface the ray meets within `max`, as a hit whose normal faces the ray's
/// origin. Ties go to the body with the lower entity id.
pub fn cast(bodies: &[(Entity, Water)], origin: Vec3, dir: Vec3, max: f32) -> Option<RayHit> {
    let mut best: Option<RayHit> = None;
    for (e, w) in bodies {
        let limit = best.map_or(max, |b| b.distance);
        if let Some(t) = w.ray(origin, dir, limit) {
            let normal = if dir.y < 0.0 { Vec3::Y } else { Vec3::NEG_Y };
            best = Some(RayHit { entity: *e, distance: t, point: origin + dir * t, normal });
        }
    }
    best
}

/// Whether a ground point lies under water: inside a body's outline and below its surface.
pub fn is_wet(bodies: &[(Entity, Water)], ground: Vec3) -> bool {
    bodies.iter().any(|(_, w)| ground.y < w.height && w.covers_xz(ground))
}

/// Ground that a tree may stand on: `ground` unless it lies under water. A tree above a pond
/// finds the pond's bed below it, which is not a place to snap to.
pub fn dry_ground(bodies: &[(Entity, Water)], ground: Option<RayHit>) -> Option<RayHit> {
    ground.filter(|g| !is_wet(bodies, g.point))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(h: f32) -> Water {
        let polygon = vec![Vec2::new(0.0, 0.0), Vec2::new(4.0, 0.0), Vec2::new(4.0, 4.0), Vec2::new(0.0, 4.0)];
        Water {
            name: "sq".into(),
            polygon,
            height: h,
            depth: 1.0,
            colour: [0.1, 0.2, 0.3],
            ripples: 1.0,
            ripple_speed: 0.05,
        }
    }

    #[test]
    fn points_inside_and_outside_a_concave_outline() {
        // An L shape: the notch at (3, 3) is outside.
        let l = [
            Vec2::new(0.0, 0.0),
            Vec2::new(4.0, 0.0),
            Vec2::new(4.0, 2.0),
            Vec2::new(2.0, 2.0),
            Vec2::new(2.0, 4.0),
            Vec2::new(0.0, 4.0),
        ];
        assert!(contains(&l, Vec2::new(1.0, 1.0)));
        assert!(contains(&l, Vec2::new(1.0, 3.0)));
        assert!(contains(&l, Vec2::new(3.0, 1.0)));
        assert!(!contains(&l, Vec2::new(3.0, 3.0)));
        assert!(!contains(&l, Vec2::new(-1.0, 1.0)));
        // Area of the L: 4 × 2 + 2 × 2 = 12, counter-clockwise in (X, Z).
        assert!((signed_area(&l) - 12.0).abs() < 1e-6);
    }

    #[test]
    fn a_ray_meets_the_surface_inside_the_outline_only() {
        let w = square(0.5);
        // From (2, 2.5, 2) straight down: 2 m to the surface.
        assert_eq!(w.ray(Vec3::new(2.0, 2.5, 2.0), Vec3::NEG_Y, 100.0), Some(2.0));
        assert_eq!(w.ray(Vec3::new(2.0, 2.5, 2.0), Vec3::NEG_Y, 1.5), None, "beyond the limit");
        assert_eq!(w.ray(Vec3::new(5.0, 2.5, 2.0), Vec3::NEG_Y, 100.0), None, "outside the outline");
        assert_eq!(w.ray(Vec3::new(2.0, 2.5, 2.0), Vec3::X, 100.0), None, "parallel");
        assert_eq!(w.ray(Vec3::new(2.0, 2.5, 2.0), Vec3::Y, 100.0), None, "pointing away");
        // A slanted ray 45° down from 1 m above the surface meets it √2 m away.
        let d = Vec3::new(1.0, -1.0, 0.0).normalize();
        let t = w.ray(Vec3::new(1.0, 1.5, 2.0), d, 100.0).unwrap();
        assert!((t - 2f32.sqrt()).abs() < 1e-5);
    }

    #[test]
    fn crossing_and_degenerate_outlines_are_found() {
        // A bow tie: edges 0 and 2 cross.
        let bow = [Vec2::new(0.0, 0.0), Vec2::new(2.0, 2.0), Vec2::new(2.0, 0.0), Vec2::new(0.0, 2.0)];
        assert_eq!(crossing_edges(&bow), Some((0, 2)));
        let sq = square(0.0).polygon;
        assert_eq!(crossing_edges(&sq), None);
        let flat = [Vec2::ZERO, Vec2::X, Vec2::new(2.0, 0.0)];
        assert!(signed_area(&flat).abs() < 1e-9);
    }

    #[test]
    fn ground_under_the_surface_is_wet_and_above_it_is_dry() {
        let bodies = vec![(Entity::DANGLING, square(0.0))];
        assert!(is_wet(&bodies, Vec3::new(2.0, -0.4, 2.0)));
        assert!(!is_wet(&bodies, Vec3::new(2.0, 0.1, 2.0)), "an island above the surface");
        assert!(!is_wet(&bodies, Vec3::new(6.0, -0.4, 2.0)), "outside the outline");
    }
}
