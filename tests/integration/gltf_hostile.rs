//! Hostile glTF files through the `grove` binary (issue #32): files named outside the model's
//! folder (a symbolic link in the folder, a symlinked folder, `/dev/zero`, `/etc/passwd` as a
//! buffer or a texture), `asset.version` 3.0, an index accessor of 2^32 − 1 elements over a
//! 6-byte view, and an all-zero node matrix. Each gives exit 2 and one line naming what is at
//! fault, within 2 s and 200 MB, from both `grove models add` and `grove render --model`, and
//! writes nothing: no bank entry, no folder in the bank, no image.

use crate::common;
use crate::gltf_build as build;

use std::path::{Path, PathBuf};

use build::{Buffer, f32s, u16s};
use common::assert_one_line_error;
use common::bounded::{MEMORY_BOUND_KB, TIME_BOUND, grove_bounded};

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("grove-gltf-hostile-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `models add` and `render --model` of `file` both refuse it with exit 2 and one line holding
/// `needle`, within the bounds, and write nothing.
fn refused_by_both(file: &Path, needle: &str) {
    let dir = file.parent().unwrap().parent().unwrap().to_path_buf();
    let bank = dir.join("bank");
    let png = dir.join("out.png");
    let f = file.to_str().unwrap();
    for args in [
        vec!["models", "add", f, "--bank", bank.to_str().unwrap(), "--name", "tri"],
        vec!["render", "--model", f, "--out", png.to_str().unwrap()],
    ] {
        let (out, took, rss_kb) = grove_bounded(&args);
        assert_one_line_error(&out, 2, needle);
        assert!(took < TIME_BOUND, "grove {args:?} took {took:?}");
        assert!(rss_kb < MEMORY_BOUND_KB, "grove {args:?} used {} MB", rss_kb / 1024);
    }
    assert!(!png.exists(), "no image is written");
    assert!(!bank.join("tri").exists(), "nothing is copied into the bank");
    let listed = std::fs::read_dir(&bank)
        .map(|d| d.filter_map(|e| e.ok()).map(|e| e.file_name().to_string_lossy().into_owned()).collect::<Vec<_>>())
        .unwrap_or_default();
    assert!(listed.iter().all(|n| n == "catalogue.ron"), "the bank holds only its catalogue: {listed:?}");
    if bank.join("catalogue.ron").exists() {
        assert!(!std::fs::read_to_string(bank.join("catalogue.ron")).unwrap().contains("tri"), "nothing is catalogued");
    }
}

/// A triangle 1 m tall whose positions are in `tri.bin` beside it, plus `extra` JSON members
/// (`buffers` gets a second buffer `extra_buffer` when given, `images` and `textures` when
/// `texture` is given). Returns the .gltf path inside `dir/model/`.
fn triangle_model(dir: &Path, extra_buffer: Option<&str>, texture: Option<&str>) -> PathBuf {
    let model = dir.join("model");
    std::fs::create_dir_all(&model).unwrap();
    let pos = f32s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    std::fs::write(model.join("tri.bin"), &pos).unwrap();
    let mut buffers = r#"{"uri":"tri.bin","byteLength":36}"#.to_string();
    if let Some(b) = extra_buffer {
        buffers.push_str(&format!(r#",{{"uri":"{b}","byteLength":4}}"#));
    }
    let (images, material) = match texture {
        Some(t) => (
            format!(
                r#","images":[{{"uri":"{t}"}}],"textures":[{{"source":0}}],"materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}]"#
            ),
            r#","material":0"#,
        ),
        None => (String::new(), ""),
    };
    let gltf = format!(
        r#"{{"asset":{{"version":"2.0"}},"buffers":[{buffers}],"bufferViews":[{{"buffer":0,"byteLength":36}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}]{images},
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}{material}}}]}}],"nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}],"scene":0}}"#
    );
    let file = model.join("tri.gltf");
    std::fs::write(&file, gltf).unwrap();
    file
}

#[test]
fn a_symbolic_link_out_of_the_models_folder_is_refused_and_nothing_is_copied() {
    let dir = temp_dir("link");
    std::fs::write(dir.join("secret.bin"), b"secret").unwrap();
    let file = triangle_model(&dir, Some("extra.bin"), None);
    std::os::unix::fs::symlink(dir.join("secret.bin"), dir.join("model/extra.bin")).unwrap();
    refused_by_both(&file, "'extra.bin'");
    // The same model with the link replaced by a regular file is accepted: the refusal was the
    // link's, not the model's.
    std::fs::remove_file(dir.join("model/extra.bin")).unwrap();
    std::fs::write(dir.join("model/extra.bin"), b"abcd").unwrap();
    let out = common::grove(&[
        "models",
        "add",
        file.to_str().unwrap(),
        "--bank",
        dir.join("bank").to_str().unwrap(),
        "--name",
        "tri",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(dir.join("bank/tri/extra.bin").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_texture_through_a_symlinked_folder_is_refused() {
    let dir = temp_dir("linkdir");
    let outside = dir.join("outside");
    std::fs::create_dir_all(&outside).unwrap();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([9, 9, 9, 255])).save(outside.join("leaf.png")).unwrap();
    let file = triangle_model(&dir, None, Some("tex/leaf.png"));
    std::os::unix::fs::symlink(&outside, dir.join("model/tex")).unwrap();
    refused_by_both(&file, "'tex/leaf.png'");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn dev_zero_as_a_buffer_is_refused_before_it_is_read() {
    let dir = temp_dir("devzero");
    let file = triangle_model(&dir, Some("/dev/zero"), None);
    refused_by_both(&file, "'/dev/zero'");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn etc_passwd_as_a_buffer_or_a_texture_is_refused_as_outside_not_decoded() {
    let dir = temp_dir("passwd-buf");
    let file = triangle_model(&dir, Some("/etc/passwd"), None);
    refused_by_both(&file, "'/etc/passwd'");
    let (out, _, _) =
        grove_bounded(&["render", "--model", file.to_str().unwrap(), "--out", dir.join("x.png").to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("outside"), "{}", String::from_utf8_lossy(&out.stderr));
    let dir2 = temp_dir("passwd-tex");
    let file = triangle_model(&dir2, None, Some("/etc/passwd"));
    refused_by_both(&file, "'/etc/passwd'");
    let (out, _, _) =
        grove_bounded(&["render", "--model", file.to_str().unwrap(), "--out", dir2.join("x.png").to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("outside") && !stderr.contains("decode"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&dir2);
}

/// A model embedded in one file: a triangle 1 m tall, with the JSON changed by `edit`.
fn embedded(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let model = dir.join("model");
    std::fs::create_dir_all(&model).unwrap();
    let mut b = Buffer::default();
    let pos = b.view(&f32s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]));
    let idx = b.view(&u16s(&[0, 1, 2])[..6]);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},{},"accessors":[{{"bufferView":{pos},"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},{{"bufferView":{idx},"componentType":5123,"count":3,"type":"SCALAR"}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],"nodes":[{{"mesh":0}}],"scenes":[{{"nodes":[0]}}],"scene":0}}"#,
        b.json_embedded()
    );
    let file = model.join("tri.gltf");
    std::fs::write(&file, edit(json)).unwrap();
    file
}

#[test]
fn the_unchanged_embedded_triangle_is_accepted() {
    // The base of the three cases below, so that each refusal is the change's.
    let dir = temp_dir("base");
    let file = embedded(&dir, |j| j);
    let out = common::grove(&[
        "models",
        "add",
        file.to_str().unwrap(),
        "--bank",
        dir.join("bank").to_str().unwrap(),
        "--name",
        "tri",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn asset_version_3_is_refused() {
    let dir = temp_dir("version");
    let file = embedded(&dir, |j| j.replace(r#""version":"2.0""#, r#""version":"3.0""#));
    refused_by_both(&file, "asset.version is \"3.0\"");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_index_accessor_of_2_pow_32_minus_1_over_6_bytes_is_refused() {
    let dir = temp_dir("count");
    let file = embedded(&dir, |j| {
        j.replace(r#""componentType":5123,"count":3"#, r#""componentType":5123,"count":4294967295"#)
    });
    refused_by_both(&file, "accessor 1");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_all_zero_node_matrix_is_refused_as_a_model_0_m_tall() {
    let dir = temp_dir("zero-matrix");
    let file = embedded(&dir, |j| {
        j.replace(r#""nodes":[{"mesh":0}]"#, r#""nodes":[{"mesh":0,"matrix":[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]}]"#)
    });
    refused_by_both(&file, "0 m tall");
    let _ = std::fs::remove_dir_all(&dir);
}
