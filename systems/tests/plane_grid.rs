//! The plane ray cast through a grid of cells (`plane_grid`) gives parry's triangle-mesh BVH
//! search's very result, bit for bit, on the shipped scenes' planes (regular grids with holes and
//! unevenness, a raised terrace, a pond's bed as a ring mesh) and on odd grids (far from the
//! origin, fine, steep), for rays of every kind: aimed at
//! the ground as a controller is, straight down as the ground search casts them, along cell edges
//! and through vertices, level with the ground, from below, long and short.

use std::path::Path;

use glam::{Vec2, Vec3};
use grove_systems::Sim;
use grove_systems::components::Plane;
use grove_systems::holes::Hole;
use grove_systems::plane_geometry::plane_geometry;
use grove_systems::plane_grid::PlaneMesh;
use grove_systems::scene::{PlaneShape, Scene};
use parry3d::query::{Ray, RayIntersection};

/// A splitmix64 step, mapped to [0, 1).
fn unit(state: &mut u64) -> f32 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
}

fn scenes() -> Vec<(String, Scene)> {
    let mut all = vec![("study".to_string(), Scene::builtin("study").unwrap())];
    for name in ["park", "pond", "forest", "garden"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../assets/scenes/{name}.ron"));
        all.push((name.to_string(), Scene::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"))));
    }
    all
}

fn planes(scene: &Scene) -> Vec<Plane> {
    let sim = Sim::from_scene(scene, 1).unwrap();
    let mut planes = Vec::new();
    sim.for_each_plane(|_, p| planes.push(p.clone()));
    planes
}

/// Grid planes unlike the shipped ones: far from the origin and high up (where single precision
/// is coarse), finely divided, and steep with cells that do not divide the rectangle evenly.
fn odd_planes() -> Vec<Plane> {
    let grid = |name: &str, min: Vec2, size: Vec2, cell: f32, elevation: f32, unevenness: f32, holes: Vec<Hole>| {
        let (vertices, triangles) =
            plane_geometry(&PlaneShape::Grid { min, size, cell, elevation, unevenness, noise_seed: 3, holes });
        Plane { name: name.into(), vertices, triangles }
    };
    vec![
        grid(
            "far",
            Vec2::new(40_000.0, -60_000.0),
            Vec2::new(30.0, 30.0),
            1.0,
            1_200.0,
            0.5,
            vec![Hole { center: Vec2::new(40_010.0, -59_990.0), radius: 2.0 }],
        ),
        grid("fine", Vec2::new(-5.0, -5.0), Vec2::new(10.0, 10.0), 0.1, 0.0, 0.02, Vec::new()),
        grid(
            "steep",
            Vec2::new(0.0, 0.0),
            Vec2::new(20.0, 12.0),
            0.7,
            -3.0,
            3.0,
            vec![Hole { center: Vec2::new(10.0, 6.0), radius: 1.5 }],
        ),
    ]
}

/// The bits of a hit, to compare exactly.
fn bits(hit: Option<RayIntersection>) -> Option<(u32, [u32; 3], String)> {
    hit.map(|h| {
        (h.time_of_impact.to_bits(), h.normal.to_array().map(f32::to_bits), format!("{:?} {:?}", h.feature, h.subshape))
    })
}

#[derive(Default)]
struct Tally {
    rays: usize,
    hits: usize,
    by_grid: usize,
}

fn check(mesh: &PlaneMesh, ray: Ray, limit: f32, what: &str, tally: &mut Tally) {
    let fast = mesh.cast(&ray, limit);
    let plain = mesh.cast_plain(&ray, limit);
    assert_eq!(bits(fast), bits(plain), "{what}: ray {:?} → {:?}, limit {limit}", ray.origin, ray.dir);
    tally.rays += 1;
    tally.hits += plain.is_some() as usize;
    tally.by_grid += mesh.cast_by_grid(&ray, limit).is_some() as usize;
}

#[test]
fn the_grid_cast_is_parrys_cast_bit_for_bit() {
    let mut state = 7u64;
    let (mut aimed, mut down, mut any, mut level, mut edges) = <(Tally, Tally, Tally, Tally, Tally)>::default();
    let mut meshes = 0;
    let all =
        scenes().into_iter().map(|(name, scene)| (name, planes(&scene))).chain([("odd".to_string(), odd_planes())]);
    for (name, planes) in all {
        for plane in planes {
            let Some(mesh) = PlaneMesh::new(&plane) else { continue };
            if !mesh.has_grid() {
                continue;
            }
            meshes += 1;
            let (lo, hi) = plane.vertices.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
            let what = format!("{name}/{}", plane.name);
            let r = |s: &mut u64, a: f32, b: f32| a + (b - a) * unit(s);
            for k in 0..3_000 {
                // Aimed at a point of the plane's box from above, as a hand controller points.
                let to = Vec3::new(r(&mut state, lo.x, hi.x), r(&mut state, lo.y, hi.y), r(&mut state, lo.z, hi.z));
                let from = to + Vec3::new(r(&mut state, -8.0, 8.0), r(&mut state, 0.3, 3.0), r(&mut state, -8.0, 8.0));
                let dir = (to - from).normalize();
                let limit = [100.0, 1.0e4, (to - from).length() * 1.5, 0.5][k % 4];
                check(&mesh, Ray::new(from, dir), limit, &what, &mut aimed);
                // Straight down, as the ground below a point is found.
                let p = Vec3::new(
                    r(&mut state, lo.x - 1.0, hi.x + 1.0),
                    hi.y + r(&mut state, -0.5, 2.0),
                    r(&mut state, lo.z - 1.0, hi.z + 1.0),
                );
                check(&mesh, Ray::new(p, Vec3::NEG_Y), 1.0e4, &what, &mut down);
                // Any direction from anywhere around the plane, below it too.
                let o = Vec3::new(
                    r(&mut state, lo.x - 5.0, hi.x + 5.0),
                    r(&mut state, lo.y - 2.0, hi.y + 10.0),
                    r(&mut state, lo.z - 5.0, hi.z + 5.0),
                );
                let d = Vec3::new(r(&mut state, -1.0, 1.0), r(&mut state, -1.0, 1.0), r(&mut state, -1.0, 1.0))
                    .normalize_or(Vec3::X);
                check(&mesh, Ray::new(o, d), [100.0, 3.0, 1.0e4][k % 3], &what, &mut any);
                // Level with the ground, inside its unevenness.
                let o = Vec3::new(
                    r(&mut state, lo.x - 2.0, hi.x + 2.0),
                    r(&mut state, lo.y, hi.y),
                    r(&mut state, lo.z - 2.0, hi.z + 2.0),
                );
                let a = r(&mut state, 0.0, std::f32::consts::TAU);
                check(&mesh, Ray::new(o, Vec3::new(a.cos(), 0.0, a.sin())), 100.0, &what, &mut level);
            }
            // Through vertices and along the edges between cells: straight down on a vertex,
            // on an edge's midpoint, and aimed at a vertex from above.
            for (i, v) in plane.vertices.iter().enumerate().step_by(3) {
                check(&mesh, Ray::new(*v + Vec3::Y, Vec3::NEG_Y), 1.0e4, &what, &mut edges);
                if let Some(w) = plane.vertices.get(i + 1) {
                    let m = (*v + *w) * 0.5;
                    check(&mesh, Ray::new(Vec3::new(m.x, hi.y + 1.0, m.z), Vec3::NEG_Y), 1.0e4, &what, &mut edges);
                    // Along the line through two neighbouring vertices, just above it.
                    let d = (*w - *v).normalize_or(Vec3::X);
                    check(
                        &mesh,
                        Ray::new(*v - d * 3.0 + Vec3::Y * 0.5, (d - Vec3::Y * 0.1).normalize()),
                        100.0,
                        &what,
                        &mut edges,
                    );
                }
                let from = *v + Vec3::new(r(&mut state, -4.0, 4.0), r(&mut state, 0.5, 2.0), r(&mut state, -4.0, 4.0));
                check(&mesh, Ray::new(from, (*v - from).normalize()), 100.0, &what, &mut edges);
            }
        }
    }
    // The study's ground and terrace, the park's and the pond's, and the odd ones.
    assert!(meshes >= 7, "{meshes} meshes with a grid");
    // Most aimed rays hit, and the grid answers nearly all of them itself.
    assert!(aimed.hits * 2 > aimed.rays, "{} of {} aimed rays hit", aimed.hits, aimed.rays);
    assert!(aimed.by_grid * 100 >= aimed.rays * 95, "the grid answered {} of {} aimed rays", aimed.by_grid, aimed.rays);
    for (what, t) in [("straight down", &down), ("any direction", &any), ("level", &level)] {
        assert!(t.by_grid * 100 >= t.rays * 95, "{what}: the grid answered {} of {} rays", t.by_grid, t.rays);
    }
    // Rays through shared vertices and edges hit several triangles at the same distance: parry's
    // search, whose order names one of them, answers those.
    assert!(
        edges.by_grid > 0 && edges.by_grid * 2 < edges.rays,
        "the grid answered {} of {} rays through vertices and edges",
        edges.by_grid,
        edges.rays
    );
}

#[test]
fn the_spatial_index_casts_planes_as_parry_does() {
    let mut state = 3u64;
    for (name, scene) in scenes() {
        let sim = Sim::from_scene(&scene, 1).unwrap();
        let spatial = sim.spatial();
        for _ in 0..2_000 {
            let o = Vec3::new(30.0 * unit(&mut state) - 15.0, 3.0 * unit(&mut state), 30.0 * unit(&mut state) - 15.0);
            let to = Vec3::new(30.0 * unit(&mut state) - 15.0, -0.5, 30.0 * unit(&mut state) - 15.0);
            let d = (to - o).normalize_or(Vec3::NEG_Y);
            let (fast, plain) = (spatial.cast_planes(o, d, 100.0), spatial.cast_planes_plain(o, d, 100.0));
            let key = |h: Option<grove_systems::spatial::RayHit>| {
                h.map(|h| {
                    (
                        h.entity,
                        h.distance.to_bits(),
                        h.point.to_array().map(f32::to_bits),
                        h.normal.to_array().map(f32::to_bits),
                    )
                })
            };
            assert_eq!(key(fast), key(plain), "{name}: {o} → {d}");
            let below = Vec3::new(o.x, 5.0, o.z);
            assert_eq!(
                key(spatial.ground_below(below, 0.0)),
                key(spatial.cast_planes_plain(below, Vec3::NEG_Y, 1.0e4)),
                "{name}: below {below}"
            );
        }
    }
}
