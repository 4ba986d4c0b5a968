//! Real-world glTF (issue #41): the small Khronos samples in `tests/fixtures/khronos/` (their
//! licences in its README) and tiny files built here for the features no small sample covers.
//! Every file is either drawn as its name says — a golden image at 160×120, a property of the
//! image that holds whatever the golden says, and bounds equal to the file's own positions
//! after morphing and node transforms, read here with the `gltf` crate's importer — or refused
//! with exit 2 and one line naming the feature. No file is accepted with a feature dropped.
//!
//! Goldens are `tests/snapshots/gltf-*.png`; regenerate with
//! `UPDATE_SNAPSHOTS=1 cargo test --test integration gltf_corpus::` and look at them before committing.

use crate::common;
use crate::gltf_build as build;
use crate::shared_gpu;

use std::path::{Path, PathBuf};

use build::{Buffer, f32s, float_accessor, index_accessor, position_accessor, u16s};
use common::{assert_one_line_error, grove, root};
use glam::{Mat4, Vec2, Vec3};
use grove::models::{ModelData, load_model};
use grove::render::RenderOptions;
use grove::render::offscreen;
use image::RgbaImage;

const W: u32 = 160;
const H: u32 = 120;
const KHRONOS: &str = "tests/fixtures/khronos";

/// An empty scratch folder, removed when the test ends.
fn temp_dir(tag: &str) -> common::Scratch {
    common::scratch(&format!("gltf-corpus-{tag}"))
}

fn khronos(name: &str) -> PathBuf {
    root().join(KHRONOS).join(format!("{name}.gltf"))
}

/// Every drawn vertex of the default scene in model space, read with the `gltf` crate's own
/// importer, independently of grove's loader: node matrices multiplied down the hierarchy
/// (a skinned mesh's node transform ignored: its bind pose), morph targets added with the
/// node's or mesh's default weights.
fn reference_vertices(path: &Path) -> Vec<Vec3> {
    let (doc, buffers, _) = gltf::import(path).expect("the file imports");
    let mut out = Vec::new();
    fn walk(node: gltf::Node, parent: Mat4, buffers: &[gltf::buffer::Data], out: &mut Vec<Vec3>) {
        let m = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            let weights = node.weights().or(mesh.weights()).unwrap_or(&[]).to_vec();
            let place = if node.skin().is_some() { Mat4::IDENTITY } else { m };
            for p in mesh.primitives() {
                let r = p.reader(|b| Some(&buffers[b.index()]));
                let mut pos: Vec<Vec3> = r.read_positions().unwrap().map(Vec3::from).collect();
                for (k, (dp, _, _)) in r.read_morph_targets().enumerate() {
                    if let Some(dp) = dp {
                        for (q, d) in pos.iter_mut().zip(dp) {
                            *q += weights.get(k).copied().unwrap_or(0.0) * Vec3::from(d);
                        }
                    }
                }
                out.extend(pos.into_iter().map(|q| place.transform_point3(q)));
            }
        }
        for c in node.children() {
            walk(c, m, buffers, out);
        }
    }
    let scene = doc.default_scene().or_else(|| doc.scenes().next()).unwrap();
    for n in scene.nodes() {
        walk(n, Mat4::IDENTITY, &buffers, &mut out);
    }
    out
}

fn bounds_of(v: &[Vec3]) -> (Vec3, Vec3) {
    (v.iter().fold(Vec3::splat(f32::MAX), |a, p| a.min(*p)), v.iter().fold(Vec3::splat(f32::MIN), |a, p| a.max(*p)))
}

fn assert_bounds(what: &str, got: (Vec3, Vec3), want: (Vec3, Vec3)) {
    assert!(
        (got.0 - want.0).abs().max_element() < 1e-5 && (got.1 - want.1).abs().max_element() < 1e-5,
        "{what}: bounds {got:?}, the file says {want:?}"
    );
}

/// Loads a file, checks its bounds against [`reference_vertices`] and returns it.
fn load_checked_bounds(path: &Path) -> ModelData {
    let data = load_model(path).unwrap_or_else(|e| panic!("{e}"));
    assert_bounds(&path.display().to_string(), data.bounds, bounds_of(&reference_vertices(path)));
    data
}

/// `grove models add` of a file into a fresh bank: exit 0, and the catalogued bounds are the
/// loaded ones. Returns stdout.
fn added(path: &Path, tag: &str, want: (Vec3, Vec3)) -> String {
    let dir = temp_dir(&format!("bank-{tag}"));
    let out =
        grove(&["models", "add", path.to_str().unwrap(), "--bank", dir.join("bank").to_str().unwrap(), "--name", tag]);
    assert!(out.status.success(), "models add {}: {}", path.display(), String::from_utf8_lossy(&out.stderr));
    let bank = grove_systems::bank::Bank::open(&dir.join("bank")).unwrap();
    let m = bank.get(tag).unwrap();
    assert_bounds(tag, (m.bounds_min, m.bounds_max), want);
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// `models add` and `render --model` both refuse `path` with exit 2 and one line holding `needle`.
fn refused(path: &Path, needle: &str) {
    let dir = temp_dir("refused");
    let out = grove(&["models", "add", path.to_str().unwrap(), "--bank", dir.join("bank").to_str().unwrap()]);
    assert_one_line_error(&out, 2, needle);
    let png = dir.join("x.png");
    let out = grove(&["render", "--model", path.to_str().unwrap(), "--out", png.to_str().unwrap()]);
    assert_one_line_error(&out, 2, needle);
    assert!(!png.exists());
}

fn render(path: &Path) -> RgbaImage {
    let _guard = shared_gpu::LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let gpu = shared_gpu::shared_gpu("glTF corpus goldens");
    offscreen::render_model_file(gpu, path, W, H, RenderOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// Compares with `tests/snapshots/<name>.png`: mean absolute difference per channel at most 3,
/// at most 2 % of pixels off by more than 40 in a channel (the model goldens' tolerance).
fn compare(name: &str, img: &RgbaImage) {
    let path = root().join("tests/snapshots").join(format!("{name}.png"));
    if std::env::var("UPDATE_SNAPSHOTS").is_ok_and(|v| v == "1") {
        img.save(&path).unwrap();
        return;
    }
    let want = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; create it with UPDATE_SNAPSHOTS=1", path.display()))
        .to_rgba8();
    assert_eq!(want.dimensions(), img.dimensions(), "{name}: size");
    let (mut sum, mut over) = (0u64, 0u64);
    for (a, b) in want.pixels().zip(img.pixels()) {
        let d = (0..3).map(|c| a.0[c].abs_diff(b.0[c])).collect::<Vec<_>>();
        sum += d.iter().map(|&x| x as u64).sum::<u64>();
        over += u64::from(d.iter().any(|&x| x > 40));
    }
    let n = (W * H) as f64;
    let (mean, percent) = (sum as f64 / (n * 3.0), over as f64 * 100.0 / n);
    if mean > 3.0 || percent > 2.0 {
        let dir = root().join("target/snapshot-failures");
        let _ = std::fs::create_dir_all(&dir);
        let _ = img.save(dir.join(format!("{name}.png")));
        panic!(
            "{name}: differs from its golden (mean {mean:.2}, {percent:.2}% over 40); actual image in target/snapshot-failures/"
        );
    }
}

/// The pixels of `img` that differ from `reference` (the same view of the model without the
/// feature, so only the model's pixels count) and whose channels differ by more than 60
/// (strongly coloured), by dominant channel (red, green, blue).
fn coloured_pixels(img: &RgbaImage, reference: &RgbaImage) -> [usize; 3] {
    let mut n = [0; 3];
    for (p, q) in img.pixels().zip(reference.pixels()) {
        if (0..3).all(|c| p.0[c].abs_diff(q.0[c]) <= 30) {
            continue;
        }
        let c = [p.0[0] as i32, p.0[1] as i32, p.0[2] as i32];
        let (hi, lo) = (*c.iter().max().unwrap(), *c.iter().min().unwrap());
        if hi - lo > 60 {
            n[c.iter().position(|&x| x == hi).unwrap()] += 1;
        }
    }
    n
}

#[test]
fn box_vertex_colors_is_drawn_in_its_colours() {
    let path = khronos("BoxVertexColors");
    let data = load_checked_bounds(&path);
    // The file's own accessor min/max, with an identity node.
    assert_bounds("BoxVertexColors", data.bounds, (Vec3::ZERO, Vec3::ONE));
    let colours: std::collections::HashSet<[u8; 4]> =
        data.primitives.iter().flat_map(|p| p.vertices.iter().map(|v| v.color)).collect();
    assert!(colours.len() >= 6, "the vertex colours are read: {colours:?}");
    added(&path, "box", (Vec3::ZERO, Vec3::ONE));
    // The bank's thumbnail (drawn on the CPU) shows the colours too.
    let thumb = grove::bank::thumbnail::draw(&data);
    let strong =
        thumb.chunks_exact(4).filter(|p| p[..3].iter().max().unwrap() - p[..3].iter().min().unwrap() > 60).count();
    assert!(strong > 100, "the thumbnail is coloured: {strong} strongly coloured pixels");
    let img = render(&path);
    // The same cube with its colours renamed to an attribute grove ignores: a white cube.
    let dir = temp_dir("box-white");
    let white = dir.join("BoxWhite.gltf");
    std::fs::write(&white, std::fs::read_to_string(&path).unwrap().replace(r#""COLOR_0" : 3"#, r#""_UNUSED" : 3"#))
        .unwrap();
    let [r, g, b] = coloured_pixels(&img, &render(&white));
    assert!(
        r > 50 && g > 50 && b > 50,
        "a multicoloured cube, not a white one: red {r}, green {g}, blue {b} strongly coloured pixels"
    );
    compare("gltf-box-vertex-colors", &img);
}

#[test]
fn simple_morph_is_drawn_and_measured_with_its_default_weights() {
    let path = khronos("SimpleMorph");
    let data = load_checked_bounds(&path);
    // Base (0.5, 0.5) + 0.5 × (−1, 1) + 0.5 × (1, 1) = (0.5, 1.5): the model is 1.5 m tall.
    let want = (Vec3::ZERO, Vec3::new(1.0, 1.5, 0.0));
    assert_bounds("SimpleMorph", data.bounds, want);
    let out = added(&path, "morph", want);
    assert!(out.contains("1.50 m tall") && out.contains("1 animation shown at the rest pose"), "{out}");
    compare("gltf-simple-morph", &render(&path));
}

#[test]
fn cameras_and_an_animated_triangle_are_drawn_at_rest() {
    let path = khronos("Cameras");
    let data = load_checked_bounds(&path);
    assert_eq!(data.triangles(), 2);
    added(&path, "cameras", data.bounds);
    compare("gltf-cameras", &render(&path));
    let path = khronos("AnimatedTriangle");
    let data = load_checked_bounds(&path);
    assert_bounds("AnimatedTriangle", data.bounds, (Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0)));
    let out = added(&path, "animated", data.bounds);
    assert!(out.contains("1 animation shown at the rest pose"), "{out}");
    compare("gltf-animated-triangle", &render(&path));
}

#[test]
fn a_sparse_accessor_is_drawn_with_its_substitutions() {
    let path = khronos("SimpleSparseAccessor");
    let data = load_checked_bounds(&path);
    // The accessor's own min and max hold only with the three substituted positions (up to 4 m).
    assert_bounds("SimpleSparseAccessor", data.bounds, (Vec3::ZERO, Vec3::new(6.0, 4.0, 0.0)));
    added(&path, "sparse", data.bounds);
    compare("gltf-simple-sparse-accessor", &render(&path));
}

/// A file of one mesh with `prims` (JSON of primitives) over `buf`, with extra top-level JSON.
fn write_model(dir: &Path, name: &str, buf: &Buffer, accessors: &[String], prims: &str, extra: &str) -> PathBuf {
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},{},"accessors":[{}],"meshes":[{{"primitives":[{prims}]}}],"nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}],"scene":0{extra}}}"#,
        buf.json_embedded(),
        accessors.join(",")
    );
    let f = dir.join(format!("{name}.gltf"));
    std::fs::write(&f, json).unwrap();
    f
}

/// A unit quad (x 0..1, y 0..1) as a strip (0,1,2,3 zig-zag) and, shifted by 2 m, as a fan.
#[test]
fn strips_and_fans_are_drawn_as_triangles_and_points_and_lines_refused() {
    let dir = temp_dir("modes");
    let mut b = Buffer::default();
    let (sp, fp) = (
        [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0],
        [2.0, 0.0, 0.0, 3.0, 0.0, 0.0, 3.0, 1.0, 0.0, 2.0, 1.0, 0.0],
    );
    let (strip, fan) = (b.view(&f32s(&sp)), b.view(&f32s(&fp)));
    let acc = [position_accessor(strip, &sp), position_accessor(fan, &fp)];
    let f = write_model(
        &dir,
        "modes",
        &b,
        &acc,
        r#"{"attributes":{"POSITION":0},"mode":5},{"attributes":{"POSITION":1},"mode":6}"#,
        "",
    );
    let data = load_checked_bounds(&f);
    assert_eq!(data.triangles(), 4, "two triangles from the strip, two from the fan");
    // Both quads face +Z (counter-clockwise seen from +Z), as glTF winds strips and fans.
    for p in &data.primitives {
        for t in p.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| Vec3::from(p.vertices[i as usize].position));
            assert!((b - a).cross(c - a).z > 0.0, "triangle {t:?} faces −Z");
        }
    }
    added(&f, "modes", (Vec3::ZERO, Vec3::new(3.0, 1.0, 0.0)));
    compare("gltf-strip-fan", &render(&f));
    for (mode, needle) in [(0, "draws points"), (1, "draws lines"), (2, "draws lines"), (3, "draws lines")] {
        let f = write_model(
            &dir,
            &format!("mode{mode}"),
            &b,
            &acc,
            &format!(r#"{{"attributes":{{"POSITION":0}},"mode":4}},{{"attributes":{{"POSITION":1}},"mode":{mode}}}"#),
            "",
        );
        refused(&f, &format!("mesh 0 primitive 1 {needle}"));
    }
}

/// A quad whose TEXCOORD_0 is all zero and TEXCOORD_1 spans the texture, with `texture_info`
/// as the material's base colour texture, and an 8×8 texture in quadrants (red, green / blue,
/// white).
fn textured_quad(dir: &Path, name: &str, texture_info: &str, extra: &str) -> PathBuf {
    let img = image::RgbaImage::from_fn(8, 8, |x, y| {
        image::Rgba(
            [[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255], [255, 255, 255, 255]]
                [((y / 4) * 2 + x / 4) as usize],
        )
    });
    img.save(dir.join("quad.png")).unwrap();
    let mut b = Buffer::default();
    let p = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0];
    let pos = b.view(&f32s(&p));
    let uv0 = b.view(&f32s(&[0.0; 8]));
    let uv1 = b.view(&f32s(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0]));
    let idx = b.view(&u16s(&[0, 1, 2, 0, 2, 3]));
    let acc = [
        position_accessor(pos, &p),
        float_accessor(uv0, 4, "VEC2"),
        float_accessor(uv1, 4, "VEC2"),
        index_accessor(idx, 6),
    ];
    let extra = format!(
        r#","images":[{{"uri":"quad.png"}}],"samplers":[{{"magFilter":9728,"minFilter":9728}}],"textures":[{{"source":0,"sampler":0}}],"materials":[{{"name":"quad","pbrMetallicRoughness":{{"baseColorTexture":{texture_info}}}}}]{extra}"#
    );
    write_model(
        dir,
        name,
        &b,
        &acc,
        r#"{"attributes":{"POSITION":0,"TEXCOORD_0":1,"TEXCOORD_1":2},"indices":3,"material":0}"#,
        &extra,
    )
}

fn uvs(data: &ModelData) -> Vec<Vec2> {
    data.primitives[0].vertices.iter().map(|v| Vec2::from(v.uv)).collect()
}

#[test]
fn each_texture_reads_its_own_set_with_its_transform() {
    let dir = temp_dir("uv");
    let set1 = textured_quad(&dir, "set1", r#"{"index":0,"texCoord":1}"#, "");
    let data = load_checked_bounds(&set1);
    assert_eq!(
        uvs(&data),
        vec![Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 0.0)],
        "TEXCOORD_1, not TEXCOORD_0"
    );
    added(&set1, "set1", data.bounds);
    let img = render(&set1);
    // Through TEXCOORD_0 (all zero) the quad is one colour; through TEXCOORD_1 the quadrants
    // that differ from it show.
    let set0 = textured_quad(&dir, "set0", r#"{"index":0}"#, "");
    let one_colour = render(&set0);
    let [_, g, b] = coloured_pixels(&img, &one_colour);
    assert!(
        g > 20 && b > 20,
        "the green and blue quadrants show, as TEXCOORD_1 spreads the texture: green {g}, blue {b}"
    );
    compare("gltf-texcoord-1", &img);
    // KHR_texture_transform (required): scale 0.5 and offset (0.5, 0): u' = 0.5 u + 0.5, v' = 0.5 v,
    // the quad shows the top right quadrant of the texture: green.
    let tt = textured_quad(
        &dir,
        "transform",
        r#"{"index":0,"texCoord":1,"extensions":{"KHR_texture_transform":{"offset":[0.5,0.0],"scale":[0.5,0.5]}}}"#,
        r#","extensionsUsed":["KHR_texture_transform"],"extensionsRequired":["KHR_texture_transform"]"#,
    );
    let data = load_checked_bounds(&tt);
    assert_eq!(uvs(&data), vec![Vec2::new(0.5, 0.5), Vec2::new(1.0, 0.5), Vec2::new(1.0, 0.0), Vec2::new(0.5, 0.0)]);
    added(&tt, "transform", data.bounds);
    let img = render(&tt);
    let [r, g, b] = coloured_pixels(&img, &one_colour);
    assert!(g > 20 && g > 4 * (r + b), "the green quadrant fills the quad: red {r} green {g} blue {b}");
    compare("gltf-texture-transform", &img);
    // A rotation by 90°: (u, v) → (−v, u), as the extension's matrix says.
    let rot = textured_quad(
        &dir,
        "rotation",
        r#"{"index":0,"texCoord":1,"extensions":{"KHR_texture_transform":{"rotation":1.5707964}}}"#,
        r#","extensionsUsed":["KHR_texture_transform"]"#,
    );
    let got = uvs(&load_model(&rot).unwrap());
    let want = [Vec2::new(-1.0, 0.0), Vec2::new(-1.0, 1.0), Vec2::new(0.0, 1.0), Vec2::new(0.0, 0.0)];
    assert!(got.iter().zip(want).all(|(a, b)| (*a - b).length() < 1e-6), "{got:?}");
}

#[test]
fn textures_of_one_material_on_different_sets_are_refused_by_name() {
    let dir = temp_dir("uvmix");
    let f = textured_quad(&dir, "mix", r#"{"index":0,"texCoord":1}"#, "");
    let text = std::fs::read_to_string(&f)
        .unwrap()
        .replace(r#""name":"quad","#, r#""name":"quad","normalTexture":{"index":0,"texCoord":0},"#);
    std::fs::write(&f, text).unwrap();
    refused(&f, "material 'quad' reads its normal texture through TEXCOORD_0");
}

#[test]
fn unknown_extensions_are_refused_when_required_and_named_in_a_warning_when_used() {
    let dir = temp_dir("ext");
    let req = textured_quad(
        &dir,
        "req",
        r#"{"index":0}"#,
        r#","extensionsUsed":["EXT_made_up"],"extensionsRequired":["EXT_made_up"]"#,
    );
    refused(&req, "requires the extension EXT_made_up");
    let used = textured_quad(&dir, "used", r#"{"index":0}"#, r#","extensionsUsed":["EXT_made_up"]"#);
    let out = grove(&["models", "add", used.to_str().unwrap(), "--bank", dir.join("bank").to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        stderr.lines().filter(|l| l.starts_with("warning:") && l.contains("EXT_made_up")).count(),
        1,
        "{stderr}"
    );
}

/// A quad (x −0.5..0.5, y 0..2) skinned to two joints, its node moved 5 m along x (which a
/// skinned mesh ignores), its joints in the bind pose: drawn where its positions are.
#[test]
fn a_skinned_mesh_is_drawn_in_its_bind_pose() {
    let dir = temp_dir("skin");
    let mut b = Buffer::default();
    let p = [-0.5, 0.0, 0.0, 0.5, 0.0, 0.0, 0.5, 2.0, 0.0, -0.5, 2.0, 0.0];
    let pos = b.view(&f32s(&p));
    let joints = b.view(&u16s(&[0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0]));
    let weights = b.view(&f32s(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]));
    let ibm = b.view(&f32s(&[
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 1.0,
    ]));
    let idx = b.view(&u16s(&[0, 1, 2, 0, 2, 3]));
    let acc = [
        position_accessor(pos, &p),
        format!(r#"{{"bufferView":{joints},"componentType":5123,"count":4,"type":"VEC4"}}"#),
        float_accessor(weights, 4, "VEC4"),
        float_accessor(ibm, 2, "MAT4"),
        index_accessor(idx, 6),
    ];
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},{},"accessors":[{}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"JOINTS_0":1,"WEIGHTS_0":2}},"indices":4}}]}}],
        "skins":[{{"inverseBindMatrices":3,"joints":[1,2]}}],
        "nodes":[{{"mesh":0,"skin":0,"translation":[5,0,0]}},{{"children":[2]}},{{"translation":[0,1,0]}}],"scenes":[{{"nodes":[0,1]}}],"scene":0}}"#,
        b.json_embedded(),
        acc.join(",")
    );
    let f = dir.join("skin.gltf");
    std::fs::write(&f, json).unwrap();
    let data = load_checked_bounds(&f);
    assert_bounds("skin", data.bounds, (Vec3::new(-0.5, 0.0, 0.0), Vec3::new(0.5, 2.0, 0.0)));
    assert!(data.notes.iter().any(|n| n.contains("bind pose")), "{:?}", data.notes);
    let out = added(&f, "skin", data.bounds);
    assert!(out.contains("skinned mesh drawn in its bind pose"), "{out}");
    compare("gltf-skin-bind-pose", &render(&f));
}
