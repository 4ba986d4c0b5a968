//! Tests of the wind maths: noise range, model agreement, sway bounds.

use glam::Vec4;

use super::*;

fn wind() -> Wind {
    Wind {
        direction: Vec3::new(0.8, 0.0, 0.6),
        strength: 1.3,
        density: 0.2,
        gust: Gust { average: 0.6, strength: 0.4, frequency: 0.2 },
        current: 0.6,
        model: WindModel::Hierarchical,
        response: WindResponse::default(),
    }
}

/// A small deterministic sequence in [0, 1) for test inputs.
fn seq(i: u32, salt: u32) -> f32 {
    (hash_u32(i.wrapping_mul(2654435761) ^ salt) >> 8) as f32 / (1u32 << 24) as f32
}

#[test]
fn noise_is_zero_on_the_lattice_and_stays_in_range() {
    for i in 0..50 {
        let p = Vec3::new(i as f32 - 25.0, (i * 7 % 11) as f32, (i * 3 % 5) as f32 - 2.0);
        assert_eq!(perlin3(p), 0.0, "lattice point {p}");
    }
    let (mut lo, mut hi) = (f32::MAX, f32::MIN);
    for i in 0..20_000 {
        let p = Vec3::new(seq(i, 1) * 40.0 - 20.0, seq(i, 2) * 40.0 - 20.0, seq(i, 3) * 40.0 - 20.0);
        let n = perlin3(p);
        lo = lo.min(n);
        hi = hi.max(n);
        assert!((0.0..=1.0).contains(&noise01(p)));
    }
    // Gradient noise should use most of its range, symmetric about zero.
    assert!(lo < -0.6 && hi > 0.6, "range {lo}..{hi}");
    assert!(lo > -1.1 && hi < 1.1, "range {lo}..{hi}");
}

#[test]
fn noise_is_continuous() {
    for i in 0..2000 {
        let p = Vec3::new(seq(i, 4) * 10.0, seq(i, 5) * 10.0, seq(i, 6) * 10.0);
        let q = p + Vec3::splat(1e-3);
        // The gradient of improved noise is bounded by a few units, so 1e-3 apart means close.
        assert!((perlin3(p) - perlin3(q)).abs() < 0.02, "jump at {p}");
    }
}

#[test]
fn wave_matches_sine_of_full_turns() {
    for i in 0..1000 {
        let c = seq(i, 7) * 200.0 - 100.0;
        let exact = libm::sin(std::f64::consts::TAU * c as f64) as f32;
        assert!((wave(c) - exact).abs() < 1e-4, "wave({c}) = {} vs {exact}", wave(c));
    }
}

#[test]
fn noise_displacement_is_along_the_wind_and_zero_at_the_attachment() {
    let dir = Vec2::new(0.6, -0.8);
    let v0 = Vec3::new(1.0, 2.0, 3.0);
    assert_eq!(displace_noise(v0, 0.0, 2.0, dir, 0.3, 3.0, 5.0), v0);
    let mut moved = 0;
    for i in 0..200 {
        let t = i as f32 * 0.1;
        let v = displace_noise(v0, 4.0, 0.5, dir, 0.3, 3.0, t);
        let dv = v - v0;
        assert_eq!(dv.y, 0.0);
        // Parallel to the wind: the cross product with (dir.x, dir.y) vanishes.
        assert!((dv.x * dir.y - dv.z * dir.x).abs() < 1e-6);
        assert!(dv.length() <= 0.5 * 0.5 * 4.0 + 1e-6);
        moved += (dv.length() > 1e-3) as u32;
    }
    assert!(moved > 100, "the noise field should move the vertex most of the time ({moved}/200)");
}

#[test]
fn hierarchical_parts_grow_with_their_channels() {
    let mut p = WindParams::from_wind(&wind(), 3.7);
    p.gust = 1.0;
    let v0 = Vec3::new(0.0, 1.0, 0.0);
    let bend = Vec2::new(0.02, 0.01);
    // Root: nothing moves.
    assert_eq!(displace_hierarchical(v0, Vec4::new(0.0, 0.0, 0.0, 0.3), bend, 1.0, 0.0, &p), v0);
    // Trunk only: along the bend, quadratic in height.
    let d1 = displace_hierarchical(v0, Vec4::new(2.0, 0.0, 0.0, 0.3), bend, 1.0, 0.0, &p) - v0;
    let d2 = displace_hierarchical(v0, Vec4::new(4.0, 0.0, 0.0, 0.3), bend, 1.0, 0.0, &p) - v0;
    assert!((d2.length() / d1.length() - 4.0).abs() < 1e-4);
    assert!((d1.x * bend.y - d1.z * bend.x).abs() < 1e-7);
    // A stiffer trunk bends less.
    let mut stiff = p;
    stiff.trunk_stiffness *= 2.0;
    let d3 = displace_hierarchical(v0, Vec4::new(4.0, 0.0, 0.0, 0.3), bend, 1.0, 0.0, &stiff) - v0;
    assert!((d3.length() * 2.0 - d2.length()).abs() < 1e-5);
    // Branch phase changes the branch and leaf motion.
    let a = displace_hierarchical(v0, Vec4::new(0.0, 1.5, 0.5, 0.1), bend, 1.0, 0.0, &p);
    let b = displace_hierarchical(v0, Vec4::new(0.0, 1.5, 0.5, 0.6), bend, 1.0, 0.0, &p);
    assert!((a - b).length() > 1e-3);
}

#[test]
fn displacement_never_exceeds_max_sway() {
    let mut w = wind();
    let extent = SwayExtent { height: 8.0, trunk_distance: 2.5, branch_distance: 0.8 };
    for model in [WindModel::Noise, WindModel::Hierarchical] {
        w.model = model;
        let bound = max_sway(&w, model, extent);
        assert!(bound > 0.0);
        let mut largest = 0.0f32;
        for i in 0..20_000 {
            let t = seq(i, 8) as f64 * 600.0;
            w.current = gust_at(&w.gust, t);
            let p = WindParams::from_wind(&w, t);
            let ch = Vec4::new(
                seq(i, 9) * extent.height,
                seq(i, 10) * extent.trunk_distance,
                seq(i, 11) * extent.branch_distance,
                seq(i, 12),
            );
            let gain = 0.5 + seq(i, 13);
            let phase = seq(i, 14) * TAU;
            let dir = Vec2::new(p.direction[0], p.direction[1]);
            let bend = tree_bend(dir, w.strength, w.current, gain, phase, (t % 2.0) as f32);
            let v0 = Vec3::new(seq(i, 15) * 60.0 - 30.0, ch.x, seq(i, 16) * 60.0 - 30.0);
            let d = (displace(model.code(), v0, ch, bend, gain, phase, &p) - v0).length();
            largest = largest.max(d);
            assert!(d <= bound, "{model:?}: {d} > {bound}");
        }
        // The bound should not be wildly loose either.
        assert!(largest > 0.3 * bound, "{model:?}: largest {largest}, bound {bound}");
    }
}

#[test]
fn params_bytes_follow_the_wgsl_layout() {
    let mut w = wind();
    w.model = WindModel::Noise;
    let p = WindParams::from_wind(&w, 12.5);
    let b = p.to_le_bytes();
    let f = |off: usize| f32::from_le_bytes(b[off..off + 4].try_into().unwrap());
    assert_eq!(f(0), 0.8);
    assert_eq!(f(4), 0.6);
    assert_eq!(f(8), 1.3);
    assert_eq!(f(28), 12.5);
    assert_eq!(f(32), w.response.trunk_stiffness);
    assert_eq!(f(48), w.response.leaf_frequency);
    assert_eq!(u32::from_le_bytes(b[52..56].try_into().unwrap()), 0);
    assert_eq!(std::mem::size_of::<WindParams>(), WindParams::SIZE);
}

#[test]
fn gain_varies_with_position_within_its_range() {
    let mut gains = Vec::new();
    for i in 0..400 {
        let p = Vec3::new((i % 20) as f32 * 1.7, 0.0, (i / 20) as f32 * 1.7);
        let g = position_gain(p, 0.15);
        assert!((0.5..=1.5).contains(&g));
        gains.push(g);
    }
    let mean = gains.iter().sum::<f32>() / gains.len() as f32;
    let var = gains.iter().map(|g| (g - mean) * (g - mean)).sum::<f32>() / gains.len() as f32;
    assert!(var.sqrt() > 0.05, "gains barely vary: sd {}", var.sqrt());
}
