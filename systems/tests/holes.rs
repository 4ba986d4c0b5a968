//! The hole mask of `holes.rs` against its definition: every grid triangle tested against every
//! hole.
use glam::Vec2;
use grove_systems::scene::{plane_geometry, Hole, PlaneShape};

/// Every triangle tested against every hole: the definition the mask must match. Returns
/// the number of triangles kept.
fn brute_force(shape: &PlaneShape) -> usize {
    let PlaneShape::Grid { min, size, cell, elevation, unevenness, noise_seed, holes } = shape.clone() else { unreachable!() };
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
            .map(|_| Hole { center: min + Vec2::new(rnd() * size.x * 1.4 - size.x * 0.2, rnd() * size.y * 1.4 - size.y * 0.2), radius: rnd() * rnd() * size.max_element() * 0.5 })
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
    let grid = |holes| PlaneShape::Grid { min: Vec2::new(-2.0, -3.0), size: Vec2::new(4.0, 6.0), cell: 0.5, elevation: 0.0, unevenness: 0.0, noise_seed: 0, holes };
    let (_, t) = plane_geometry(&grid(vec![Hole { center: Vec2::ZERO, radius: 100.0 }]));
    assert!(t.is_empty());
    let (_, t) = plane_geometry(&grid(vec![Hole { center: Vec2::new(50.0, 0.0), radius: 10.0 }]));
    assert_eq!(t.len(), 8 * 12 * 2);
}
