//! The tree ray cast (a BVH with a leaf per run of similar bands of each pick shape, searched
//! nearest first) finds the same tree at the same distance as a plain test of every tree.

use glam::Vec3;
use grove_systems::Sim;
use grove_systems::scene::Scene;

/// A splitmix64 step, mapped to [0, 1).
fn unit(state: &mut u64) -> f32 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
}

#[test]
fn the_fast_tree_cast_agrees_with_testing_every_tree() {
    let mut sim = Sim::from_scene(&Scene::builtin("study").unwrap(), 7).unwrap();
    sim.scatter_trees(400);
    sim.set_up().refresh_spatial();
    let (mut min, mut max) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    sim.for_each_plane(|_, p| {
        for v in &p.vertices {
            min = min.min(*v);
            max = max.max(*v);
        }
    });
    let spatial = sim.spatial();
    assert!(spatial.tree_count() > 300, "{}", spatial.tree_count());
    let mut state = 99u64;
    let (mut hits, mut zero, mut ties) = (0, 0, 0);
    for k in 0..4_000 {
        let point =
            |y: f32, s: &mut u64| Vec3::new(min.x + (max.x - min.x) * unit(s), y, min.z + (max.z - min.z) * unit(s));
        // Eyes at head height, among the crowns and above them, aimed at the ground or across it.
        let eye = [12.0 * unit(&mut state), 40.0, 1.7][k % 3];
        let from = point(eye, &mut state);
        let aim = if k % 2 == 0 { 0.0 } else { 6.0 * unit(&mut state) };
        let to = point(aim, &mut state);
        let dir = (to - from).normalize_or(Vec3::NEG_Y);
        let max_dist = if k % 5 == 0 { 8.0 } else { 200.0 };
        let fast = spatial.cast_trees(from, dir, max_dist, None);
        let plain = spatial.cast_trees_plain(from, dir, max_dist, None);
        match (fast, plain) {
            (Some(f), Some(p)) => {
                hits += 1;
                zero += (p.distance == 0.0) as usize;
                assert_eq!(f.distance.to_bits(), p.distance.to_bits(), "ray {k}: {f:?} vs {p:?}");
                if f.entity != p.entity {
                    // Two trees hit at exactly the same distance (in a dense forest, a ray
                    // starting inside two overlapping crowns): either may be named, but the
                    // other must really be hit there too.
                    ties += 1;
                    if f.distance == 0.0 {
                        // Inside several trees: the BVH's point query names one of them (that
                        // part of the search is not the one under test).
                        continue;
                    }
                    let other = spatial.cast_trees_plain(from, dir, max_dist, Some(p.entity)).unwrap();
                    assert_eq!((other.entity, other.distance.to_bits()), (f.entity, f.distance.to_bits()), "ray {k}");
                    continue;
                }
                assert_eq!(f.point, p.point, "ray {k}");
                assert_eq!(f.normal, p.normal, "ray {k}");
                // Excluding the tree hit gives the same answer both ways too.
                let fx = spatial.cast_trees(from, dir, max_dist, Some(f.entity));
                let px = spatial.cast_trees_plain(from, dir, max_dist, Some(f.entity));
                // (Among trees tied at one distance, only the distance is compared.)
                let key = |h: grove_systems::spatial::RayHit| h.distance.to_bits();
                assert_eq!(fx.map(key), px.map(key), "ray {k} excluding");
            }
            (None, None) => {}
            other => panic!("ray {k}: fast and plain disagree: {other:?}"),
        }
    }
    // The rays are a real test: many hit a tree.
    assert!(hits > 400, "{hits} hits");
    eprintln!("{hits} hits, {zero} from inside a tree, {ties} ties");
}
