//! The model bank with a model the project did not make (`tests/fixtures/thirdparty/`, the
//! ez-tree flower, MIT): `grove models add` into a temporary bank, its bounds and lowest point
//! against the mesh as this test reads it with the `gltf` crate, planted and snapped in a script,
//! recorded, replayed to the same hash, and refused by name once its file changes.

use crate::common;

use std::path::{Path, PathBuf};

use common::{assert_one_line_error, grove};
use glam::{Mat4, Vec2, Vec3};
use grove_systems::Sim;
use grove_systems::bank::{Bank, Banks};
use grove_systems::catalogue::PICK_BANDS;
use grove_systems::input::Button;
use grove_systems::interact;
use grove_systems::replay::{Header, ReplayOptions, record_events_in, replay_file};
use grove_systems::scene::Scene;
use grove_systems::script::Script;

const FLOWER: &str = "tests/fixtures/thirdparty/flower_white.glb";

/// An empty scratch folder, removed when the test ends.
fn temp_dir(tag: &str) -> common::Scratch {
    common::scratch(&format!("bank-test-{tag}"))
}

/// Every triangle vertex of the default scene in model space, read independently of grove's
/// loader: the node matrices multiplied down the hierarchy, triangle primitives only.
fn mesh_vertices(path: &Path) -> Vec<Vec3> {
    let (doc, buffers, _) = gltf::import(path).expect("the fixture is valid glTF");
    let mut out = Vec::new();
    fn walk(node: gltf::Node, parent: Mat4, buffers: &[gltf::buffer::Data], out: &mut Vec<Vec3>) {
        let m = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            for p in mesh.primitives().filter(|p| p.mode() == gltf::mesh::Mode::Triangles) {
                let r = p.reader(|b| Some(&buffers[b.index()]));
                out.extend(r.read_positions().unwrap().map(|q| m.transform_point3(Vec3::from(q))));
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

/// Adds the flower to a new bank under the name "flower" and returns the bank folder.
/// A bank in a scratch folder (removed when the first is dropped) with the flower added.
fn bank_with_flower(tag: &str) -> (common::Scratch, PathBuf) {
    let dir = temp_dir(tag);
    let bank = dir.join("bank");
    let out =
        grove(&["models", "add", FLOWER, "--bank", bank.to_str().unwrap(), "--name", "flower", "--species", "flower"]);
    assert!(out.status.success(), "models add: {}", String::from_utf8_lossy(&out.stderr));
    (dir, bank)
}

#[test]
fn an_added_model_is_measured_from_its_own_mesh() {
    let (_dir, bank) = bank_with_flower("measure");
    let b = Bank::open(&bank).unwrap();
    let m = b.get("flower").expect("catalogued");
    assert_eq!(m.species, "flower");
    // Its files were copied in with it.
    assert!(b.file_of(m).is_file());
    assert!(bank.join(m.thumbnail.as_ref().unwrap()).is_file());

    let v = mesh_vertices(&common::root().join(FLOWER));
    assert!(v.len() > 100);
    let lo = v.iter().fold(Vec3::splat(f32::MAX), |a, p| a.min(*p));
    let hi = v.iter().fold(Vec3::splat(f32::MIN), |a, p| a.max(*p));
    assert!((m.bounds_min - lo).abs().max_element() < 1e-5, "{:?} vs {lo:?}", m.bounds_min);
    assert!((m.bounds_max - hi).abs().max_element() < 1e-5, "{:?} vs {hi:?}", m.bounds_max);
    // Not the birch's 8 m: the flower is under 2 m tall, its lowest point its own.
    assert!(m.bounds_max.y - m.bounds_min.y < 2.0);
    let info = m.info(grove_systems::catalogue::ModelId(8));
    assert_eq!(info.lowest_point(), lo.y);
    // The pick shape holds every vertex, spans the mesh's heights, and its widest band is as
    // wide as the mesh (to its rounding margin).
    let widest = v.iter().map(|p| Vec2::new(p.x, p.z).length()).fold(0.0, f32::max);
    let pick = m.pick;
    assert_eq!((pick.bottom, pick.top), (lo.y, hi.y));
    let none = [0.0; PICK_BANDS];
    assert!(v.iter().all(|p| pick.contains(*p, &none)));
    let max_r = pick.radii.iter().copied().fold(0.0, f32::max);
    assert!((max_r - widest).abs() <= widest * 2e-4, "{max_r} vs {widest}");
    assert!((m.crown_radius - widest).abs() < 1e-5);

    // Adding it again is a no-op; another file under the same name is refused.
    let again = grove(&["models", "add", FLOWER, "--bank", bank.to_str().unwrap(), "--name", "flower"]);
    assert!(again.status.success());
    let other =
        grove(&["models", "add", "assets/trees/shrub-mesh.gltf", "--bank", bank.to_str().unwrap(), "--name", "flower"]);
    assert_one_line_error(&other, 2, "different model named 'flower'");
    let check = grove(&["models", "check", "--bank", bank.to_str().unwrap()]);
    assert!(check.status.success(), "{}", String::from_utf8_lossy(&check.stdout));
    let list = grove(&["models", "list", "--json", "--bank", bank.to_str().unwrap()]);
    let listed: serde_json::Value = serde_json::from_slice(&list.stdout).unwrap();
    assert_eq!(listed[8]["name"], "flower");
    assert_eq!(listed[8]["id"], 8);
}

#[test]
fn a_planted_third_party_model_snaps_records_and_replays_and_a_changed_file_is_named() {
    let (_dir, bank) = bank_with_flower("replay");
    let banks = Banks::open(&[bank.clone()]).unwrap();
    let (catalogue, listed) = banks.session_catalogue().unwrap();
    let flower = catalogue.by_name("flower").unwrap().clone();
    let scene = Scene::builtin("study").unwrap();
    let mut s = Script::new(Sim::from_scene_with(&scene, 7, catalogue).unwrap());

    // Plant the flower by name with the ray.
    let ground =
        |s: &Script, x: f32, z: f32| Vec3::new(x, s.sim().ground_below(Vec3::new(x, 50.0, z), 0.0).unwrap().point.y, z);
    let p = ground(&s, 1.0, -2.0);
    s.choose_model("flower").point_at(p).press(Button::Trigger).wait(2);
    let id = *s.sim().tree_ids().last().unwrap();
    let t = s.sim().tree(id).unwrap();
    assert_eq!(t.tree.model, flower.id);
    // Planted with its origin at the hit point (as every model is).
    assert!((t.transform.translation - p).length() < 1e-4);

    // Drag it up and aside by the middle of its height, and release: it snaps down.
    let mid = t.transform.translation + Vec3::Y * (0.5 * flower.height());
    s.point_at(mid).hold(Button::Trigger);
    let mut pose = s.controller().pose;
    pose.position += Vec3::new(-0.8, 0.15, 0.0);
    s.move_controller(pose);
    let lifted = s.sim().tree(id).unwrap();
    assert!(!lifted.grounded.0, "the flower was picked by its pick shape and lifted");
    s.release(Button::Trigger).wait(5);
    let snapped = s.sim().tree(id).unwrap();
    let low = interact::lowest_point_y(snapped.transform.translation.y, flower.lowest_point(), snapped.scale.0);
    let g = ground(&s, snapped.transform.translation.x, snapped.transform.translation.z);
    assert!(snapped.grounded.0, "snapped");
    assert!((low - g.y).abs() < 1e-3, "lowest point {low} on the plane at {}", g.y);
    let final_hash = s.sim().hash().total;

    // Record with the bank model listed in the header, and replay to the same hash.
    let (sim, events) = s.into_parts();
    let mut header = Header::new("study", 7, scene.dt);
    header.models = listed;
    let bytes = record_events_in(Vec::new(), &header, &events, sim.tick(), serde_json::json!({}), &banks).unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    assert!(text.lines().next().unwrap().contains("\"models\":[{\"name\":\"flower\""), "the header lists the model");
    assert!(text.contains("\"model\":\"flower\""), "choose_model names the model");
    let file = bank.parent().unwrap().join("flower.jsonl");
    std::fs::write(&file, &bytes).unwrap();
    let options = ReplayOptions { banks: vec![bank.clone()], ..Default::default() };
    let o = replay_file(&file, &options).unwrap();
    assert!(o.first_divergence.is_none() && o.complete && o.checkpoints_checked > 0);
    assert_eq!(o.sim.hash().total, final_hash);
    let ok = grove(&["replay", file.to_str().unwrap(), "--bank", bank.to_str().unwrap()]);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));

    // Without the bank, and after the model's file changes, the replay names the model, exit 2.
    assert_one_line_error(&grove(&["replay", file.to_str().unwrap()]), 2, "model 'flower'");
    let glb = Bank::open(&bank).unwrap().get("flower").map(|m| bank.join(&m.file)).unwrap();
    let mut data = std::fs::read(&glb).unwrap();
    let last = data.len() - 1;
    data[last] ^= 0x20;
    std::fs::write(&glb, data).unwrap();
    let changed = grove(&["replay", file.to_str().unwrap(), "--bank", bank.to_str().unwrap()]);
    assert_one_line_error(&changed, 2, "model 'flower' has changed since the recording");
    let check = grove(&["models", "check", "--bank", bank.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&check.stdout).contains("CHANGED   flower"));
}

#[test]
fn unknown_names_list_the_known_ones() {
    let dir = temp_dir("names");
    let scene = dir.join("s.ron");
    let text = std::fs::read_to_string(common::root().join("assets/scenes/study.ron")).unwrap();
    // A tree of a model no bank has.
    let with_tree = text.replacen("trees: [", "trees: [(model: \"flower\", position: (1.0, 0.0, -2.0)),", 1);
    assert_ne!(with_tree, text, "the study scene has a trees list");
    std::fs::write(&scene, with_tree).unwrap();
    let out = grove(&["sim", "--scene", scene.to_str().unwrap(), "--ticks", "1"]);
    assert_one_line_error(&out, 2, "unknown model 'flower'; known models: broadleaf-mesh, conifer-mesh");
    // With the bank that has it, the same scene runs.
    let (_dir, bank) = bank_with_flower("names-bank");
    let ok = grove(&["sim", "--scene", scene.to_str().unwrap(), "--ticks", "1", "--bank", bank.to_str().unwrap()]);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
}

#[test]
fn compressed_geometry_is_refused_with_the_extension_and_a_conversion() {
    let dir = temp_dir("draco");
    let f = dir.join("draco.gltf");
    std::fs::write(&f, r#"{"asset":{"version":"2.0"},"extensionsUsed":["EXT_meshopt_compression"],"extensionsRequired":["EXT_meshopt_compression"]}"#).unwrap();
    let out = grove(&["models", "add", f.to_str().unwrap(), "--bank", dir.join("bank").to_str().unwrap()]);
    assert_one_line_error(&out, 2, "uses EXT_meshopt_compression");
    assert!(String::from_utf8_lossy(&out.stderr).contains("gltf-transform"));
    assert!(!dir.join("bank").join("draco").exists());
}

#[test]
fn a_quantized_model_is_read_with_its_node_scale_and_added() {
    // A quad of i16 normalised positions (KHR_mesh_quantization, required), scaled by its node:
    // 32767 is 1.0, so the corners lie at ±2 m across and 0 to 4 m high.
    let dir = temp_dir("quant");
    let q: [[i16; 3]; 4] = [[-32767, 0, 0], [32767, 0, 0], [32767, 32767, 0], [-32767, 32767, 0]];
    // Each 6-byte position padded to a stride of 8 bytes (32 bytes), then six u16 indices.
    let mut bin = Vec::new();
    for v in &q {
        bin.extend(v.iter().flat_map(|c| c.to_le_bytes()));
        bin.extend([0u8, 0]);
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend(i.to_le_bytes());
    }
    std::fs::write(dir.join("quad.bin"), &bin).unwrap();
    let gltf = format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsUsed":["KHR_mesh_quantization"],"extensionsRequired":["KHR_mesh_quantization"],
        "buffers":[{{"uri":"quad.bin","byteLength":{len}}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":32,"byteStride":8}},{{"buffer":0,"byteOffset":32,"byteLength":12}}],
        "accessors":[{{"bufferView":0,"componentType":5122,"normalized":true,"count":4,"type":"VEC3","min":[-32767,0,0],"max":[32767,32767,0]}},
                     {{"bufferView":1,"componentType":5123,"count":6,"type":"SCALAR"}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],
        "nodes":[{{"mesh":0,"scale":[2,4,2]}}],"scenes":[{{"nodes":[0]}}],"scene":0}}"#,
        len = bin.len()
    );
    let file = dir.join("quad.gltf");
    std::fs::write(&file, gltf).unwrap();
    let data = grove::models::load_model(&file).unwrap_or_else(|e| panic!("{e}"));
    let (lo, hi) = data.bounds;
    assert!(
        (lo - Vec3::new(-2.0, 0.0, 0.0)).length() < 1e-4 && (hi - Vec3::new(2.0, 4.0, 0.0)).length() < 1e-4,
        "{lo} {hi}"
    );
    let out = grove(&["models", "add", file.to_str().unwrap(), "--bank", dir.join("bank").to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let b = Bank::open(&dir.join("bank")).unwrap();
    assert_eq!(b.get("quad").unwrap().bounds_max.y, hi.y);
    assert_eq!(b.get("quad").unwrap().files, vec!["quad/quad.gltf".to_string(), "quad/quad.bin".to_string()]);
}

#[test]
fn a_webp_only_texture_is_decoded() {
    // A 2×2 lossless WebP written by the `image` crate, the only image of a texture that names it
    // through KHR_texture_webp (required), on a triangle with float positions.
    let dir = temp_dir("webp");
    let img = image::RgbaImage::from_fn(2, 2, |x, y| image::Rgba([200, (x * 100) as u8, (y * 50) as u8, 255]));
    img.save_with_format(dir.join("leaf.webp"), image::ImageFormat::WebP).unwrap();
    let pos: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let bin: Vec<u8> = pos.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    std::fs::write(dir.join("tri.bin"), &bin).unwrap();
    let gltf = r#"{"asset":{"version":"2.0"},"extensionsUsed":["KHR_texture_webp"],"extensionsRequired":["KHR_texture_webp"],
        "buffers":[{"uri":"tri.bin","byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],
        "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
        "images":[{"uri":"leaf.webp","mimeType":"image/webp"}],
        "textures":[{"extensions":{"KHR_texture_webp":{"source":0}}}],
        "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
        "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0}"#;
    let file = dir.join("tri.gltf");
    std::fs::write(&file, gltf).unwrap();
    let data = grove::models::load_model(&file).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(data.images.len(), 1);
    let im = &data.images[0];
    assert_eq!((im.width, im.height), (2, 2));
    // Texel (1, 1): red 200, green 100, blue 50, as written.
    assert_eq!(&im.rgba[12..16], &[200, 100, 50, 255]);
    assert_eq!(data.materials[0].albedo, Some(0));
    let out = grove(&["models", "add", file.to_str().unwrap(), "--bank", dir.join("bank").to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(dir.join("bank/tri/leaf.webp").is_file(), "the texture is copied with the model");
}

#[test]
fn an_lsystem_tree_added_to_a_bank_is_planted_and_snaps() {
    let dir = temp_dir("lsys");
    let bank = dir.join("bank");
    let out = grove(&[
        "lsystem",
        "model",
        "--preset",
        "birch",
        "--n",
        "7",
        "--seed",
        "3",
        "--height",
        "5",
        "--out",
        dir.join("out").to_str().unwrap(),
        "--name",
        "lsys-birch",
        "--add",
        "--bank",
        bank.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let b = Bank::open(&bank).unwrap();
    let m = b.get("lsys-birch").expect("added");
    assert_eq!(m.species, "lsystem-birch");
    assert_eq!(m.wind, grove_systems::bank::WindSource::Own, "the generator writes its own _WIND channels");
    // Its bounds are those of its mesh.
    let v = mesh_vertices(&b.file_of(m));
    let lo = v.iter().fold(Vec3::splat(f32::MAX), |a, p| a.min(*p));
    assert!((m.bounds_min - lo).abs().max_element() < 1e-5);

    let banks = Banks::open(&[bank.clone()]).unwrap();
    let (catalogue, _) = banks.session_catalogue().unwrap();
    let tree = catalogue.by_name("lsys-birch").unwrap().clone();
    let scene = Scene::builtin("study").unwrap();
    let mut s = Script::new(Sim::from_scene_with(&scene, 3, catalogue).unwrap());
    let p = Vec3::new(2.0, s.sim().ground_below(Vec3::new(2.0, 50.0, -3.0), 0.0).unwrap().point.y, -3.0);
    s.choose_model("lsys-birch").point_at(p).press(Button::Trigger).wait(2);
    let id = *s.sim().tree_ids().last().unwrap();
    assert_eq!(s.sim().tree(id).unwrap().tree.model, tree.id);
    // Aim at the trunk a quarter of the way up, lift it, release: it snaps.
    s.point_at(p + Vec3::Y * (0.25 * tree.height())).hold(Button::Trigger);
    let mut pose = s.controller().pose;
    pose.position += Vec3::new(0.5, 0.1, 0.0);
    s.move_controller(pose);
    assert!(!s.sim().tree(id).unwrap().grounded.0, "lifted by the drag");
    s.release(Button::Trigger).wait(2);
    let t = s.sim().tree(id).unwrap();
    let low = interact::lowest_point_y(t.transform.translation.y, tree.lowest_point(), t.scale.0);
    let g = s.sim().ground_below(t.transform.translation + Vec3::Y * 20.0, 0.0).unwrap().point.y;
    assert!(t.grounded.0 && (low - g).abs() < 1e-3, "snapped: lowest point {low}, ground {g}");
}

#[test]
fn a_model_without_wind_channels_sways_in_rendered_frames() {
    // The flower has no _WIND attribute; grove computes channels, so on the static stage (no sun
    // motion, nothing else moving) two frames a second apart differ only by the wind.
    let dir = temp_dir("frames");
    let out = grove(&[
        "render",
        "--model",
        FLOWER,
        "--frames",
        "2",
        "--fps",
        "1",
        "--width",
        "96",
        "--height",
        "72",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let a = image::open(dir.join("frame_00000.png")).unwrap().to_rgba8();
    let b = image::open(dir.join("frame_00001.png")).unwrap().to_rgba8();
    let moved = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
    assert!(moved > 20, "only {moved} pixels changed");
}

#[test]
fn a_recording_on_the_garden_replays_with_the_scenes_own_bank() {
    // The garden names L-system trees of assets/banks/lsystem through its `banks` field; a
    // recording on it lists them, and a replay finds them through the scene without --bank.
    let scene = Scene::load(&common::root().join("assets/scenes/garden.ron")).unwrap();
    let banks = Banks::open(&scene.bank_dirs()).unwrap();
    let (catalogue, listed) = banks.session_catalogue().unwrap();
    let names: Vec<&str> = listed.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        names[..3],
        ["lsys-broadleaf", "lsys-conifer", "lsys-birch"],
        "the L-system bank first, as the scene names it"
    );
    assert!(
        names[3..].iter().all(|n| n.ends_with("-lod1") || n.ends_with("-lod2")) && names.len() == 15,
        "then the species bank: {names:?}"
    );
    let mut s = Script::new(Sim::from_scene_with(&scene, scene.seed, catalogue.clone()).unwrap());
    let mut lsys = 0;
    s.sim().for_each_tree(|t| lsys += usize::from(catalogue.models[t.model.0 as usize].name.starts_with("lsys-")));
    assert_eq!(lsys, 6, "the garden's six L-system trees");
    let p = Vec3::new(0.0, s.sim().ground_below(Vec3::new(0.0, 50.0, 10.0), 0.0).unwrap().point.y, 10.0);
    s.choose_model("lsys-birch").point_at(p).press(Button::Trigger).wait(70);
    let hash = s.sim().hash().total;
    let (sim, events) = s.into_parts();
    let mut header = Header::new("assets/scenes/garden.ron", scene.seed, scene.dt);
    header.models = listed;
    let bytes =
        record_events_in(Vec::new(), &header, &events, sim.tick(), serde_json::json!({}), &Banks::default()).unwrap();
    let dir = temp_dir("garden");
    let file = dir.join("garden.jsonl");
    std::fs::write(&file, bytes).unwrap();
    let o = replay_file(&file, &ReplayOptions::default()).unwrap();
    assert!(o.first_divergence.is_none() && o.complete && o.checkpoints_checked > 0);
    assert_eq!(o.sim.hash().total, hash);
}

#[test]
fn bad_model_lists_in_headers_are_refused_in_one_line() {
    use grove_systems::bank::HeaderModel;
    use grove_systems::replay::{Line, encode_line};
    let dir = temp_dir("headers");
    let cases: Vec<(Vec<HeaderModel>, &str)> = vec![
        (vec![HeaderModel { name: "../etc".into(), hash: "0123456789abcdef".into() }], "plain name"),
        (vec![HeaderModel { name: "oak".into(), hash: "xyz".into() }], "16-hex-digit hash"),
        (vec![HeaderModel { name: "birch-mesh".into(), hash: "0123456789abcdef".into() }], "shipped name"),
        (
            (0..300).map(|i| HeaderModel { name: format!("m{i}"), hash: "0123456789abcdef".into() }).collect(),
            "more than",
        ),
        (vec![HeaderModel { name: "oak".into(), hash: "0123456789abcdef".into() }], "in no bank"),
    ];
    for (k, (models, needle)) in cases.into_iter().enumerate() {
        let mut h = Header::new("study", 1, 1.0 / 60.0);
        h.models = models;
        let f = dir.join(format!("h{k}.jsonl"));
        std::fs::write(&f, format!("{}\n", encode_line(&Line::Header(h)))).unwrap();
        assert_one_line_error(&grove(&["replay", f.to_str().unwrap()]), 2, needle);
    }
}

#[test]
fn a_far_model_must_already_be_in_the_bank() {
    let dir = temp_dir("far");
    let bank = dir.join("bank");
    let shrub = common::root().join("assets/trees/shrub-billboard.gltf");
    let add = |name: &str, far: Option<&str>| {
        let mut args = vec!["models", "add", shrub.to_str().unwrap(), "--bank", bank.to_str().unwrap(), "--name", name];
        if let Some(f) = far {
            args.extend(["--far", f]);
        }
        grove(&args)
    };
    assert_one_line_error(&add("near", Some("distant")), 2, "is not in this bank");
    assert!(add("distant", None).status.success());
    assert_one_line_error(&add("self", Some("self")), 2, "is not in this bank");
    let o = add("near", Some("distant"));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_one_line_error(&add("nearer", Some("near")), 2, "without a far model of its own");
    let text = std::fs::read_to_string(bank.join("catalogue.ron")).unwrap();
    assert!(text.contains("far: Some(\"distant\")"), "{text}");
}
