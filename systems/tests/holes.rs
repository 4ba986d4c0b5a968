//! The hole mask of `holes.rs` against its definition: every grid triangle tested against every
//! hole.
use glam::Vec2;
use grove_systems::plane_geometry::plane_geometry;
use grove_systems::scene::{Hole, PlaneShape};

/// Every triangle tested against every hole: the definition the mask must match. Returns
/// the number of triangles kept.
fn brute_force(shape: &PlaneShape) -> usize {
    let PlaneShape::Grid { min, size, cell, elevation, unevenness, noise_seed, holes } = shape.clone() else {
        unreachable!()
    };
    let plain = PlaneShape::Grid { min, size, cell, elevation, unevenness, noise_seed, holes: vec![] };
    let (vertices, all) = plane_geometry(&plain);
    all.iter()
        .filter(|t| {
            let p = (vertices[t[0] as usize] + vertices[t[1] as usize] + vertices[t[2] as usize]) / 3.0;
            !holes.iter().any(|h| Vec2::new(p.x, p.z).distance(h.center) < h.radius)
        })
        .count()
}

#[test]
fn the_mask_matches_testing_every_triangle_against_every_hole() {
    // A small linear congruential generator, so the test needs no RNG crate.
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut rnd = || {
        x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (x >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut checked = 0;
    for case in 0..60 {
        let min = Vec2::new(rnd() * 200.0 - 100.0, rnd() * 200.0 - 100.0);
        // Wide, tall and square grids, so both line directions are exercised.
        let size = match case % 3 {
            0 => Vec2::new(5.0 + rnd() * 40.0, 2.0 + rnd() * 5.0),
            1 => Vec2::new(2.0 + rnd() * 5.0, 5.0 + rnd() * 40.0),
            _ => Vec2::splat(5.0 + rnd() * 20.0),
        };
        let cell = 0.1 + rnd() * 0.9;
        let holes: Vec<Hole> = (0..(case % 7) * 3)
            .map(|_| Hole {
                center: min + Vec2::new(rnd() * size.x * 1.4 - size.x * 0.2, rnd() * size.y * 1.4 - size.y * 0.2),
                radius: rnd() * rnd() * size.max_element() * 0.5,
            })
            .collect();
        let shape = PlaneShape::Grid { min, size, cell, elevation: 0.3, unevenness: 0.2, noise_seed: case, holes };
        let (_, kept) = plane_geometry(&shape);
        let expected = brute_force(&shape);
        assert_eq!(kept.len(), expected, "case {case}: {shape:?}");
        checked += expected;
    }
    assert!(checked > 1000, "the cases hold triangles");
}

#[test]
fn a_hole_larger_than_the_plane_removes_every_triangle_and_a_far_one_none() {
    let grid = |holes| PlaneShape::Grid {
        min: Vec2::new(-2.0, -3.0),
        size: Vec2::new(4.0, 6.0),
        cell: 0.5,
        elevation: 0.0,
        unevenness: 0.0,
        noise_seed: 0,
        holes,
    };
    let (_, t) = plane_geometry(&grid(vec![Hole { center: Vec2::ZERO, radius: 100.0 }]));
    assert!(t.is_empty());
    let (_, t) = plane_geometry(&grid(vec![Hole { center: Vec2::new(50.0, 0.0), radius: 10.0 }]));
    assert_eq!(t.len(), 8 * 12 * 2);
}

/// The rim vertices of a plane's holes (vertices of kept triangles on a boundary edge inside the
/// plane's outline): their distances from the nearest hole's circle, metres.
fn rim_offsets(vertices: &[glam::Vec3], triangles: &[[u32; 3]], holes: &[Hole], lo: Vec2, hi: Vec2) -> Vec<f32> {
    let mut count = std::collections::HashMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let inside = |q: Vec2| q.x > lo.x + 1e-3 && q.y > lo.y + 1e-3 && q.x < hi.x - 1e-3 && q.y < hi.y - 1e-3;
    let mut on: Vec<u32> = count.iter().filter(|(_, c)| **c == 1).flat_map(|((a, b), _)| [*a, *b]).collect();
    on.sort_unstable();
    on.dedup();
    on.iter()
        .map(|&i| Vec2::new(vertices[i as usize].x, vertices[i as usize].z))
        .filter(|&q| inside(q))
        .map(|q| holes.iter().map(|h| (q.distance(h.center) - h.radius).abs()).fold(f32::MAX, f32::min))
        .collect()
}

/// With `exact_holes` a pit's rim lies on its circle, every triangle still faces up, and the
/// plane keeps its triangles but a few slivers; without it (the default, as the study scene has it) the rim
/// follows the grid's triangles, up to most of a cell off the circle at the diagonals' spikes.
#[test]
fn exact_holes_put_the_rim_on_the_circle() {
    use grove_systems::plane_geometry::plane_geometry_cut;
    let (min, size) = (Vec2::new(-20.0, -15.0), Vec2::new(40.0, 30.0));
    let holes =
        vec![Hole { center: Vec2::new(-4.0, 2.0), radius: 2.5 }, Hole { center: Vec2::new(9.3, -4.1), radius: 4.2 }];
    let shape = PlaneShape::Grid {
        min,
        size,
        cell: 1.0,
        elevation: 0.0,
        unevenness: 0.05,
        noise_seed: 3,
        holes: holes.clone(),
    };
    let (v0, t0) = plane_geometry_cut(&shape, false);
    assert_eq!((v0.clone(), t0.clone()), plane_geometry(&shape), "off is the plane as it always was");
    let (v1, t1) = plane_geometry_cut(&shape, true);
    // Only slivers between a circle and its chords are left out.
    assert!(
        t1.iter().all(|t| t0.contains(t)) && t1.len() + 40 > t0.len(),
        "{} of {} triangles kept",
        t1.len(),
        t0.len()
    );
    let off = |v: &[glam::Vec3], t: &[[u32; 3]]| rim_offsets(v, t, &holes, min, min + size);
    let (jagged, exact) = (off(&v0, &t0), off(&v1, &t1));
    let worst = |o: &[f32]| o.iter().copied().fold(0.0, f32::max);
    assert!(exact.len() > 20 && jagged.len() > 20, "{} and {} rim vertices", exact.len(), jagged.len());
    assert!(worst(&exact) < 1e-4, "exact rims lie on their circles (worst {} m off)", worst(&exact));
    assert!(worst(&jagged) > 0.3, "the grid's rims stray from the circle (worst {} m)", worst(&jagged));
    for t in &t1 {
        let (a, b, c) = (v1[t[0] as usize], v1[t[1] as usize], v1[t[2] as usize]);
        assert!((b - a).cross(c - a).y > 1e-4, "a triangle of the cut plane faces down or has no area: {a} {b} {c}");
    }
}
