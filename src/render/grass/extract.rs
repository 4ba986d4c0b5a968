//! The grass's extract: the patches' key, and the patches with their ground triangles and
//! blades (placed by the simulation's pure placement function) when the key differs from the
//! one the grass was built from, a blade lawn's blades faded along its edge (`edges.rs`); the
//! controller's hit point, which the blades bend away from.

use glam::Vec3;
use grove_systems::Sim;
use grove_systems::components::Grass;
use grove_systems::grass::{GrassKind, patch_triangles, place_blades};

use super::data::GrassPatch;
use super::edges;

/// Identifies the grass: every plane's hash (`grove_systems::hash::plane_hash`: its name,
/// vertices and triangles) and every patch (entity bits and component), sorted by entity. The
/// grass buffers are rebuilt only when this changes.
pub(crate) type GrassKey = (Vec<(u64, u64)>, Vec<(u64, Grass)>);

/// The grass's data of a frame.
pub(crate) struct Patches {
    /// The patches' key.
    pub key: GrassKey,
    /// The patches with their triangles and blades; only when `key` differs from the one the
    /// grass already has.
    pub patches: Option<Vec<GrassPatch>>,
    /// The controller's hit point when the hit marker is shown.
    pub hit: Option<Vec3>,
}

/// Copies the grass patches from `sim` when the world's key differs from `have` (the key
/// of the grass buffers the renderer already has): each patch's ground triangles and its
/// blades, placed by the simulation's pure placement function (a blade lawn's faded along its
/// edge when `fade`).
pub(crate) fn patches(sim: &Sim, have: &GrassKey, fade: bool) -> Patches {
    let hit = Some(sim.hit_marker()).filter(|h| h.visible).map(|h| h.position);
    let patches = sim.grass_patches();
    // Without patches the planes do not matter (and are not hashed every frame).
    let mut planes: Vec<(u64, u64)> = Vec::new();
    if !patches.is_empty() {
        sim.for_each_plane(|id, p| planes.push((id, grove_systems::hash::plane_hash(p))));
    }
    planes.sort_unstable();
    let key = (planes, patches);
    if &key == have {
        return Patches { key, patches: None, hit };
    }
    let mut planes: Vec<(u64, String, Vec<Vec3>, Vec<[u32; 3]>)> = Vec::new();
    sim.for_each_plane(|id, p| planes.push((id, p.name.clone(), p.vertices.clone(), p.triangles.clone())));
    planes.sort_by_key(|p| p.0);
    let views: Vec<(&str, &[Vec3], &[[u32; 3]])> =
        planes.iter().map(|p| (p.1.as_str(), p.2.as_slice(), p.3.as_slice())).collect();
    let out = key.1.iter().map(|(_, g)| {
        let shells = g.def.kind == GrassKind::Shells;
        let triangles = patch_triangles(g, &views);
        let mut blades = place_blades(g, &views);
        // A blade lawn fades into the ground along its edge (the simulation's blades are untouched).
        if fade {
            edges::fade_blades(&triangles, &mut blades);
        }
        GrassPatch {
            shells,
            triangles: if shells { triangles } else { Vec::new() },
            blades,
            root: g.def.base_color,
            tip: g.def.tip_color,
            height: g.def.height,
            density: g.def.density,
            layers: g.def.shells,
        }
    });
    let patches = Some(out.collect());
    Patches { key, patches, hit }
}
