//! The generated assets: the catalogue agrees with the glTF files, the files carry what the
//! renderer and the wind shader need, and `grove assets` reproduces the committed output.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use grove_systems::catalogue::{Catalogue, ModelKind};

fn assets() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"))
}

/// Bounds, crown radius and triangle count recomputed from a glTF file.
fn measure(path: &Path) -> (Vec3, Vec3, f32, u32) {
    let (doc, buffers, _) = gltf::import(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (mut lo, mut hi, mut crown, mut tris) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN), 0.0f32, 0u32);
    for node in doc.nodes() {
        let m = glam::Mat4::from_cols_array_2d(&node.transform().matrix());
        let Some(mesh) = node.mesh() else { continue };
        for prim in mesh.primitives() {
            let r = prim.reader(|b| Some(&buffers[b.index()]));
            for p in r.read_positions().expect("positions") {
                let p = m.transform_point3(Vec3::from(p));
                lo = lo.min(p);
                hi = hi.max(p);
                crown = crown.max(Vec2::new(p.x, p.z).length());
            }
            tris += r.read_indices().expect("indices").into_u32().count() as u32 / 3;
        }
    }
    (lo, hi, crown, tris)
}

#[test]
fn catalogue_bounds_match_the_gltf_files() {
    let text = std::fs::read_to_string(assets().join("trees/catalogue.ron")).unwrap();
    let cat = Catalogue::from_ron(&text).unwrap();
    assert_eq!(cat.len(), 8);
    let names = [
        "broadleaf-mesh",
        "conifer-mesh",
        "birch-mesh",
        "shrub-mesh",
        "broadleaf-billboard",
        "conifer-billboard",
        "birch-billboard",
        "shrub-billboard",
    ];
    for (m, want) in cat.models.iter().zip(names) {
        assert_eq!(m.name, want);
        let (lo, hi, crown, tris) = measure(&assets().join(format!("trees/{}.gltf", m.name)));
        assert!(
            (lo - m.bounds_min).abs().max_element() < 1e-5,
            "{}: bounds_min {lo} vs catalogue {}",
            m.name,
            m.bounds_min
        );
        assert!(
            (hi - m.bounds_max).abs().max_element() < 1e-5,
            "{}: bounds_max {hi} vs catalogue {}",
            m.name,
            m.bounds_max
        );
        assert!((crown - m.crown_radius).abs() < 1e-5, "{}: crown {crown} vs {}", m.name, m.crown_radius);
        assert_eq!(tris, m.triangles, "{}", m.name);
    }
    // The embedded catalogue is the same file.
    assert_eq!(Catalogue::builtin(), cat);
}

#[test]
fn models_have_sizes_and_costs_in_range() {
    let cat = Catalogue::builtin();
    for m in &cat.models {
        match m.kind {
            ModelKind::Mesh => assert!((1000..=6000).contains(&m.triangles), "{}: {} triangles", m.name, m.triangles),
            ModelKind::Billboard => {
                assert!((100..=1000).contains(&m.triangles), "{}: {} triangles", m.name, m.triangles)
            }
        }
        assert!(m.bounds_min.y < 0.0 && m.bounds_min.y > -0.1, "{}: roots {}", m.name, m.bounds_min.y);
    }
    // The species differ visibly: the shrub is low, the conifer the tallest, the birch narrowest
    // of the trees.
    let h = |n: &str| cat.by_name(n).unwrap().height();
    let r = |n: &str| cat.by_name(n).unwrap().crown_radius;
    assert!(h("shrub-mesh") < 2.0);
    assert!(h("conifer-mesh") > h("broadleaf-mesh"));
    assert!(r("birch-mesh") < r("broadleaf-mesh"));
}

#[test]
fn models_carry_maps_alpha_mask_and_wind_channels() {
    for m in &Catalogue::builtin().models {
        let path = assets().join(format!("trees/{}.gltf", m.name));
        let (doc, buffers, images) = gltf::import(&path).unwrap();
        assert!(doc.extensions_used().any(|e| e == "KHR_materials_specular"));
        assert_eq!(images.len(), 6, "{}", m.name);
        let mut leaves = 0;
        for mat in doc.materials() {
            assert!(mat.pbr_metallic_roughness().base_color_texture().is_some());
            assert!(mat.normal_texture().is_some());
            assert!(mat.specular().and_then(|s| s.specular_texture()).is_some());
            if mat.alpha_mode() == gltf::material::AlphaMode::Mask {
                assert!(mat.double_sided());
                assert!(mat.alpha_cutoff().is_some());
                leaves += 1;
            }
        }
        assert_eq!(leaves, 1, "{}", m.name);
        for prim in doc.meshes().flat_map(|m| m.primitives().collect::<Vec<_>>()) {
            let wind = prim.get(&gltf::Semantic::Extras("WIND".into())).expect("_WIND attribute");
            assert_eq!(wind.dimensions(), gltf::accessor::Dimensions::Vec4);
            let r = prim.reader(|b| Some(&buffers[b.index()]));
            assert!(r.read_tangents().is_some());
            let values: Vec<[f32; 4]> =
                gltf::accessor::Iter::new(wind, |b| Some(buffers[b.index()].0.as_slice())).unwrap().collect();
            assert!(values.iter().all(|w| w[0] >= 0.0 && (0.0..=1.0).contains(&w[3])));
            // Height above the root follows the vertex height.
            for (w, p) in values.iter().zip(r.read_positions().unwrap()) {
                assert!((w[0] - p[1].max(0.0)).abs() < 1e-5);
            }
        }
    }
}

fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(files_under(&p));
        } else {
            out.push(p);
        }
    }
    out.sort();
    out
}

#[test]
fn generator_reproduces_the_committed_files_byte_for_byte() {
    let tmp = tempfile::tempdir().unwrap();
    let summary = grove::assetgen::generate(tmp.path()).unwrap();
    let files = files_under(tmp.path());
    assert_eq!(files.len(), summary.files);
    for f in files {
        let rel = f.strip_prefix(tmp.path()).unwrap();
        let committed =
            std::fs::read(assets().join(rel)).unwrap_or_else(|_| panic!("{} is not committed", rel.display()));
        assert!(
            std::fs::read(&f).unwrap() == committed,
            "{} differs from the committed file; run `grove assets`",
            rel.display()
        );
    }
}

/// Every vertex of a glTF file, in model space.
fn vertices(path: &Path) -> Vec<Vec3> {
    let (doc, buffers, _) = gltf::import(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut out = Vec::new();
    for node in doc.nodes() {
        let m = glam::Mat4::from_cols_array_2d(&node.transform().matrix());
        let Some(mesh) = node.mesh() else { continue };
        for prim in mesh.primitives() {
            let r = prim.reader(|b| Some(&buffers[b.index()]));
            out.extend(r.read_positions().expect("positions").map(|p| m.transform_point3(Vec3::from(p))));
        }
    }
    out
}

#[test]
fn pick_shapes_hold_every_vertex_and_are_tighter_than_the_bounds() {
    for m in &Catalogue::builtin().models {
        let pick = m.pick.unwrap_or_else(|| panic!("{} has no pick shape", m.name));
        let verts = vertices(&assets().join(format!("trees/{}.gltf", m.name)));
        let outside =
            verts.iter().filter(|p| !pick.contains(**p, &[1e-4; grove_systems::catalogue::PICK_BANDS])).count();
        assert_eq!(outside, 0, "{}: {outside} of {} vertices outside {pick:?}", m.name, verts.len());
        // Sample the bounds on a grid: a good share of the box must be outside the shape,
        // in particular next to the trunk below the crown.
        let (lo, hi) = (m.bounds_min, m.bounds_max);
        let mut inside = 0;
        let n = 20;
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let f = Vec3::new(i as f32 + 0.5, j as f32 + 0.5, k as f32 + 0.5) / n as f32;
                    if pick.contains(lo + (hi - lo) * f, &[0.0; grove_systems::catalogue::PICK_BANDS]) {
                        inside += 1;
                    }
                }
            }
        }
        let share = inside as f32 / (n * n * n) as f32;
        assert!(share < 0.75, "{}: the pick shape fills {:.0} % of the box", m.name, share * 100.0);
        // A point beside the trunk in the lowest band is outside, for the trees whose crown
        // starts high (a conifer's lowest branches and a shrub's leaves reach the ground).
        if m.species == "broadleaf" || m.species == "birch" {
            let beside_trunk = Vec3::new(hi.x * 0.7, lo.y + pick.band_height() * 0.5, 0.0);
            assert!(
                !pick.contains(beside_trunk, &[0.0; grove_systems::catalogue::PICK_BANDS]),
                "{}: {beside_trunk} beside the trunk is picked",
                m.name
            );
        }
    }
}
