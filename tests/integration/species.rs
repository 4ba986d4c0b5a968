//! `grove trees generate`: Weber–Penn trees from species presets (docs/species.md). Determinism,
//! the Khronos validator, wind channels, bad presets, and the shapes that tell the species apart.

use crate::common;

use std::path::Path;
use std::sync::OnceLock;

use glam::{Vec2, Vec3, Vec4};
use grove::species::output::{self, Model};
use grove::species::preset;
use grove_systems::wind_model::{WindParams, WindResponse, displace_hierarchical};

use common::{assert_one_line_error, grove, root, validate_gltf_dir};

const SPECIES: [&str; 6] = ["oak", "birch", "beech", "scots_pine", "norway_spruce", "shrub"];
const BROADLEAF: [&str; 3] = ["oak", "birch", "beech"];

fn model(name: &str) -> &'static Model {
    static MODELS: OnceLock<Vec<Model>> = OnceLock::new();
    let all = MODELS.get_or_init(|| {
        SPECIES
            .iter()
            .map(|s| {
                let (n, p) = preset::load(s).unwrap_or_else(|e| panic!("{s}: {e}"));
                output::model(&n, &p, 7).unwrap_or_else(|e| panic!("{s}: {e}"))
            })
            .collect()
    });
    &all[SPECIES.iter().position(|s| *s == name).expect("a shipped species")]
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
        .collect();
    v.sort();
    v
}

#[test]
fn the_same_species_and_seed_give_the_same_bytes_and_another_seed_others() {
    let dir = tempfile::tempdir().unwrap();
    let run = |seed: &str, sub: &str| {
        let out = dir.path().join(sub);
        let o = grove(&["trees", "generate", "--species", "shrub", "--seed", seed, "--out", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        files(&out)
    };
    let (a, b, c) = (run("3", "a"), run("3", "b"), run("4", "c"));
    assert_eq!(
        a.len(),
        12,
        "three glTF files, three buffers, six textures: {:?}",
        a.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    assert!(a == b, "the same seed wrote different bytes");
    let bin = |v: &[(String, Vec<u8>)]| v.iter().find(|f| f.0 == "shrub.bin").unwrap().1.clone();
    assert_ne!(bin(&a), bin(&c), "another seed wrote the same geometry");
    // Writing again into a folder that has the model refuses, and changes nothing.
    let out = dir.path().join("a");
    let o = grove(&["trees", "generate", "--species", "shrub", "--seed", "9", "--out", out.to_str().unwrap()]);
    assert_one_line_error(&o, 2, "already exists");
    assert!(files(&out) == a);
}

#[test]
fn every_species_passes_the_gltf_validator() {
    let dir = tempfile::tempdir().unwrap();
    for s in SPECIES {
        let o = grove(&["trees", "generate", "--species", s, "--out", dir.path().to_str().unwrap()]);
        assert!(o.status.success(), "{s}: {}", String::from_utf8_lossy(&o.stderr));
        let (doc, _, _) = gltf::import(dir.path().join(format!("{s}.gltf"))).unwrap_or_else(|e| panic!("{s}: {e}"));
        let leaf = doc
            .materials()
            .find(|m| m.alpha_mode() == gltf::material::AlphaMode::Mask)
            .expect("an alpha-clipped leaf material");
        assert!(leaf.double_sided(), "{s}: leaves are two-sided");
        for prim in doc.meshes().flat_map(|m| m.primitives().collect::<Vec<_>>()) {
            assert!(prim.get(&gltf::Semantic::Colors(0)).is_some(), "{s}: vertex colours");
            assert!(
                prim.attributes().any(|(k, _)| matches!(k, gltf::Semantic::Extras(n) if n == "WIND")),
                "{s}: _WIND"
            );
        }
    }
    let text = validate_gltf_dir(dir.path());
    assert_eq!(text.matches(": 0 errors").count(), 3 * SPECIES.len(), "{text}");
}

#[test]
fn leaves_sway_more_than_the_trunk() {
    let r = WindResponse::default();
    let p = WindParams {
        direction: [1.0, 0.0],
        strength: 1.0,
        gust: 1.0,
        density: 0.1,
        noise_speed: r.noise_speed,
        noise_amplitude: r.noise_amplitude,
        time: 0.0,
        trunk_stiffness: r.trunk_stiffness,
        branch_stiffness: r.branch_stiffness,
        branch_frequency: r.branch_frequency,
        leaf_flutter: r.leaf_flutter,
        leaf_frequency: r.leaf_frequency,
        model: 1,
        pad: [0; 2],
    };
    for s in SPECIES {
        let m = model(s);
        let (wood, leaves) = (&m.lods[0].wood, &m.lods[0].leaves);
        // The trunk's vertices: no distance from the axis and none from a branch.
        let all_trunk: Vec<(Vec3, Vec4)> =
            wood.positions.iter().zip(&wood.wind).filter(|(_, w)| w.y == 0.0).map(|(p, w)| (*p, *w)).collect();
        assert!(all_trunk.len() > 20, "{s}: trunk vertices");
        // The crown reaches the trunk's top (a spruce's leader may stand a little above it).
        let top_leaf = leaves.positions.iter().map(|p| p.y).fold(f32::MIN, f32::max);
        let top_trunk = all_trunk.iter().map(|(p, _)| p.y).fold(f32::MIN, f32::max);
        assert!(
            top_trunk < top_leaf + 0.05 * m.bounds().1.y,
            "{s}: the trunk reaches {top_trunk} m, the leaves {top_leaf} m"
        );
        assert!(
            all_trunk.iter().all(|(_, w)| w.z == 0.0 && w.w == 0.0),
            "{s}: the trunk has no leaf distance and phase 0"
        );
        // Compared where both are: the trunk inside the crown's heights.
        let lowest_leaf = leaves.positions.iter().map(|p| p.y).fold(f32::MAX, f32::min);
        let trunk: Vec<(Vec3, Vec4)> = all_trunk.into_iter().filter(|(p, _)| p.y >= lowest_leaf).collect();
        assert!(!trunk.is_empty(), "{s}: trunk inside the crown");
        // The litter under a crown (flat on the ground, docs/species.md) does not sway.
        let litter = leaves.wind.iter().filter(|w| **w == Vec4::ZERO).count();
        assert!(
            leaves.positions.iter().zip(&leaves.wind).all(|(p, w)| *w != Vec4::ZERO || p.y < 0.05),
            "{s}: only the litter has no wind"
        );
        assert!(
            leaves.wind.iter().filter(|w| **w != Vec4::ZERO).all(|w| w.y > 0.0 && w.z > 0.0),
            "{s}: every leaf vertex is off the axis and off its branch"
        );
        // The sway of a vertex (RMS over a few instants, the trunk leaning by a bend), against
        // that of the trunk at the same height.
        let sway = |x: Vec3, w: Vec4| -> f32 {
            let mut sum = 0.0;
            for t in 0..8 {
                let q = WindParams { time: t as f32 * 0.37, ..p };
                sum += (displace_hierarchical(x, w, Vec2::new(0.02, 0.0), 1.0, 0.0, &q) - x).length_squared();
            }
            (sum / 8.0).sqrt()
        };
        for (x, w) in &trunk {
            let on_axis = sway(Vec3::new(0.0, x.y, 0.0), Vec4::new(w.x, 0.0, 0.0, 0.0));
            assert!((sway(*x, *w) - on_axis).abs() < 1e-4, "{s}: the trunk sways as the axis does");
        }
        let (mut more, mut leaf_sum, mut trunk_sum) = (0, 0.0, 0.0);
        for (x, w) in leaves.positions.iter().zip(&leaves.wind).filter(|(_, w)| **w != Vec4::ZERO) {
            let (a, b) = (sway(*x, *w), sway(Vec3::new(0.0, x.y, 0.0), Vec4::new(w.x, 0.0, 0.0, 0.0)));
            more += usize::from(a > b);
            leaf_sum += a;
            trunk_sum += b;
        }
        let n = leaves.positions.len() - litter;
        // A branch bobbing against the lean at these instants can sway less than the axis; most do not.
        assert!(
            more as f32 > 0.6 * n as f32,
            "{s}: only {more} of {n} leaf vertices sway more than the trunk at their height"
        );
        let (b, a) = (leaf_sum / n as f32, trunk_sum / n as f32);
        assert!(b > a * 1.02, "{s}: leaves sway {b} m, the trunk at their heights {a} m");
    }
}

#[test]
fn bad_presets_give_one_line_naming_the_field_and_its_range() {
    let dir = tempfile::tempdir().unwrap();
    let oak = std::fs::read_to_string(root().join("assets/species/oak.ron")).unwrap();
    let cases: Vec<(String, &str)> = vec![
        (
            oak.replacen("down_angle_deg: 55", "down_angle_deg: 200", 1),
            "levels[1].down_angle_deg = 200 is out of range; allowed -180 to 180 (degrees)",
        ),
        (oak.replace("height: 16.0", "height: 0.1"), "height = 0.1 is out of range; allowed 0.3 to 60 (metres)"),
        (
            oak.replace("leaf_bend: 0.4", "leaf_bend: 0.4,\n    bark_colour_v: 0.1"),
            "Unexpected field named `bark_colour_v`",
        ),
        (oak.replace("shape: Hemispherical", "shape: Blob"), "Blob"),
        (oak.replace("ao: 0.6,", "ao: 0.6"), "oak-bad"),
        (
            oak.replacen("leaf_colour: (0.22", "leaf_colour: (1.5", 1),
            "leaf_colour[0] = 1.5 is out of range; allowed 0 to 1",
        ),
    ];
    for (i, (text, needle)) in cases.iter().enumerate() {
        assert_ne!(text, &oak, "case {i} changed nothing");
        let p = dir.path().join(format!("oak-bad{i}.ron"));
        std::fs::write(&p, text).unwrap();
        let out = dir.path().join(format!("out{i}"));
        let o = grove(&["trees", "generate", "--species", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        assert_one_line_error(&o, 2, needle);
        assert_one_line_error(&o, 2, &format!("oak-bad{i}.ron"));
        assert!(!out.exists(), "case {i}: no output folder");
    }
    let o = grove(&["trees", "generate", "--species", "baobab", "--out", dir.path().join("x").to_str().unwrap()]);
    assert_one_line_error(&o, 2, "unknown species 'baobab'");
    let o = grove(&["trees", "generate", "--species", "oak", "--seed", "-1", "--out", "x"]);
    assert_one_line_error(&o, 2, "--seed");
    // Every shipped preset is in range.
    for s in SPECIES {
        preset::load(s).unwrap_or_else(|e| panic!("{s}: {e}"));
    }
}

/// The crown's widest horizontal radius among leaves in a band of heights (fractions of the
/// leaves' height range).
fn band_radius(m: &Model, lo: f32, hi: f32) -> f32 {
    let ys: Vec<f32> = m.tree.leaves.iter().map(|l| l.attach.y).collect();
    let (a, b) = (ys.iter().copied().fold(f32::MAX, f32::min), ys.iter().copied().fold(f32::MIN, f32::max));
    m.tree
        .leaves
        .iter()
        .filter(|l| (a + lo * (b - a)..=a + hi * (b - a)).contains(&l.attach.y))
        .map(|l| Vec2::new(l.attach.x, l.attach.z).length())
        .fold(0.0, f32::max)
}

#[test]
fn the_species_have_their_own_shapes() {
    // The spruce is a cone (its silhouette: species_leaves::conifer_silhouettes; the pine's
    // crown is high and irregular).
    let m = model("norway_spruce");
    let (top, bottom) = (band_radius(m, 0.8, 1.0), band_radius(m, 0.0, 0.4));
    assert!(top < 0.7 * bottom, "norway_spruce: crown top {top} m, bottom {bottom} m");
    let spruce = model("norway_spruce");
    let (lo, hi) = spruce.bounds();
    assert!(spruce.crown_radius() * 2.0 < 0.6 * (hi.y - lo.y), "spruce is slender");
    for s in BROADLEAF {
        let m = model(s);
        let (lo, hi) = m.bounds();
        let height = hi.y - lo.y;
        assert!((10.0..=25.0).contains(&height), "{s}: {height} m tall");
        let crown_height = height * (1.0 - preset::load(s).unwrap().1.base_size);
        assert!(
            2.0 * m.crown_radius() > 0.5 * crown_height,
            "{s}: crown {} m wide, {crown_height} m tall",
            2.0 * m.crown_radius()
        );
        let n = m.lods[0].leaf_count;
        assert!((3_000..=100_000).contains(&n), "{s}: {n} leaf cards");
    }
    let oak = model("oak");
    let birch = model("birch");
    assert!(
        oak.crown_radius() / oak.bounds().1.y > birch.crown_radius() / birch.bounds().1.y,
        "the oak is broader than the birch"
    );
    let shrub = model("shrub");
    assert!(shrub.bounds().1.y < 5.0, "the shrub is short: {}", shrub.bounds().1.y);
    let stems_at_root = shrub.tree.stems.iter().filter(|st| st.level == 0 && st.nodes[0].pos.length() < 1e-3).count();
    assert!(stems_at_root >= 4, "the shrub has several stems: {stems_at_root}");
    assert_eq!(
        model("oak").tree.stems.iter().filter(|st| st.level == 0 && st.nodes[0].pos.length() < 1e-3).count(),
        1,
        "one trunk"
    );
    for s in SPECIES {
        let m = model(s);
        let t = m.lods[0].triangles();
        assert!((5_000..=400_000).contains(&t), "{s}: {t} triangles");
        // Level 1 draws sprays of leaves at their size (its budget: species_leaves::), level 2
        // about 5 % of the triangles.
        let share = m.lods[1].triangles() as f32 / t as f32;
        assert!((0.05..0.35).contains(&share), "{s}: lod1 has {share} of the triangles");
        let share = m.lods[2].triangles() as f32 / t as f32;
        assert!((share - 0.05).abs() < 0.05 * 0.3, "{s}: lod2 has {share} of the triangles, not about 0.05");
        for k in [1, 2] {
            assert!(m.lods[k].leaf_count > 0 || m.lods[0].leaf_count == 0, "{s}: lod{k} keeps leaves");
        }
    }
}

#[test]
fn the_crown_is_darker_inside_and_leaves_vary_in_colour() {
    for s in BROADLEAF {
        let m = model(s);
        let l = &m.lods[0].leaves;
        let r = m.crown_radius();
        let mean = |inner: bool| {
            let v: Vec<f32> = l
                .positions
                .iter()
                .zip(&l.colors)
                .filter(|(p, _)| (Vec2::new(p.x, p.z).length() < 0.35 * r) == inner)
                .map(|(_, c)| c.y)
                .collect();
            assert!(v.len() > 50, "{s}: leaves {} the crown", if inner { "inside" } else { "outside" });
            v.iter().sum::<f32>() / v.len() as f32
        };
        let (inside, outside) = (mean(true), mean(false));
        assert!(inside < 0.92 * outside, "{s}: inside {inside}, outside {outside}");
        // Leaves at about the same place differ in colour: the spread of red/green across leaves.
        let ratios: Vec<f32> = l.colors.iter().step_by(4).map(|c| c.x / c.y.max(1e-3)).collect();
        let (min, max) = ratios.iter().fold((f32::MAX, f32::MIN), |(a, b), r| (a.min(*r), b.max(*r)));
        assert!(max - min > 0.1, "{s}: leaf colours vary {min}..{max}");
    }
}

/// Oak, beech and the shrub carry most of their leaves in clumps at the ends of the twigs: the
/// preset's share of leaves is clumped, a clump's inside is darker than its outside, and the
/// leaves of one clump are closer in colour than leaves of different clumps.
#[test]
fn broadleaf_crowns_grow_in_clumps_darker_inside_and_coloured_by_clump() {
    for s in ["oak", "beech", "shrub"] {
        let m = model(s);
        let p = preset::load(s).unwrap().1;
        let leaves = &m.tree.leaves;
        let clumped = leaves.iter().filter(|l| l.depth < 1.0).count() as f32 / leaves.len() as f32;
        assert!(
            p.leaf_clumps > 0.0 && (clumped - p.leaf_clumps).abs() < 0.1,
            "{s}: {clumped} of the leaves clumped, the preset asks {}",
            p.leaf_clumps
        );
        // Green of the vertex colour (the first vertex of each leaf card) by depth in the clump.
        let green: Vec<(f32, f32)> =
            leaves.iter().zip(m.lods[0].leaves.colors.iter().step_by(4)).map(|(l, c)| (l.depth, c.y)).collect();
        let mean = |lo: f32, hi: f32| {
            let v: Vec<f32> = green.iter().filter(|g| g.0 >= lo && g.0 < hi).map(|g| g.1).collect();
            assert!(v.len() > 100, "{s}: leaves at depth {lo}..{hi}");
            v.iter().sum::<f32>() / v.len() as f32
        };
        let (inner, outer) = (mean(0.0, 0.3), mean(0.7, 1.0));
        assert!(inner < 0.9 * outer, "{s}: clump inside {inner}, outside {outer}");
        // Neighbours in the list are mostly of one clump; leaves 997 apart of different ones.
        let tints: Vec<f32> = leaves.iter().filter(|l| l.depth < 1.0).map(|l| l.tint).collect();
        let spread = |k: usize| {
            tints.iter().zip(&tints[k..]).map(|(a, b)| (a - b).abs()).sum::<f32>() / (tints.len() - k) as f32
        };
        assert!(
            spread(1) < 0.8 * spread(997),
            "{s}: colour within clumps {} against between {}",
            spread(1),
            spread(997)
        );
    }
    // Presets without clumps keep their leaves spread along the twigs.
    assert!(model("birch").tree.leaves.iter().all(|l| l.depth == 1.0));
}

#[test]
fn generation_is_deterministic_in_the_library_too() {
    let (n, p) = preset::load("birch").unwrap();
    let a = output::model(&n, &p, 11).unwrap();
    let b = output::model(&n, &p, 11).unwrap();
    assert_eq!(a.lods[0].leaves.positions, b.lods[0].leaves.positions);
    assert_eq!(a.lods[2].wood.positions, b.lods[2].wood.positions);
    let c = output::model(&n, &p, 12).unwrap();
    assert_ne!(a.lods[0].wood.positions, c.lods[0].wood.positions);
}

#[test]
fn shape_ratios_follow_weber_and_penn() {
    use grove::species::preset::Shape::*;
    use grove::species::stems::shape_ratio;
    let (_, p) = preset::load("oak").unwrap();
    // The paper's formulas at chosen points, by hand.
    let cases = [
        (Conical, 0.5, 0.6),
        (Spherical, 0.5, 1.0),
        (Spherical, 0.0, 0.2),
        (Hemispherical, 1.0, 1.0),
        (Cylindrical, 0.3, 1.0),
        (TaperedCylindrical, 0.0, 0.5),
        (Flame, 0.7, 1.0),
        (Flame, 0.35, 0.5),
        (Flame, 1.0, 0.0),
        (InverseConical, 1.0, 0.2),
        (TendFlame, 1.0, 0.5),
    ];
    for (shape, r, want) in cases {
        let got = shape_ratio(shape, r, &p);
        assert!((got - want).abs() < 1e-5, "{shape:?} at {r}: {got}, want {want}");
    }
}

#[test]
fn pruning_keeps_branches_inside_the_envelope() {
    let (_, mut p) = preset::load("oak").unwrap();
    // A straight trunk on the axis (the trunk itself is never pruned).
    p.levels[0].curve_v_deg = 0.0;
    p.levels[0].seg_splits = 0.0;
    let free = output::model("oak", &p, 3).unwrap();
    p.prune_ratio = 1.0;
    p.prune_width = 0.25;
    p.prune_width_peak = 0.5;
    p.prune_power_low = 1.0;
    p.prune_power_high = 1.0;
    let pruned = output::model("oak", &p, 3).unwrap();
    let limit = 0.25 * pruned.tree.scale;
    let nodes: Vec<Vec3> =
        pruned.tree.stems.iter().filter(|s| s.level >= 1).flat_map(|s| s.nodes.iter().map(|n| n.pos)).collect();
    let outside = nodes.iter().filter(|q| Vec2::new(q.x, q.z).length() > limit * 1.001).count();
    assert!(outside * 100 < nodes.len(), "{outside} of {} branch points outside a {limit} m envelope", nodes.len());
    let widest = |m: &Model| {
        m.tree
            .stems
            .iter()
            .flat_map(|s| s.nodes.iter())
            .map(|n| Vec2::new(n.pos.x, n.pos.z).length())
            .fold(0.0, f32::max)
    };
    assert!(widest(&free) > limit * 1.2, "the unpruned oak reaches past the envelope ({} m)", widest(&free));
}
