//! The input surfaces added after the first hostile-input work (issue #32): scatters, grammars,
//! aerial photographs, crowns, study folders, generated models and argument errors. Each case
//! must end with exit 2 and one line on stderr within 2 s and 200 MB, a pipe or a device must be
//! refused without blocking, and a failed command must leave no file.

use crate::common;

use std::path::{Path, PathBuf};

use common::bounded::{refused_within_bounds, refused_writing_nothing};
use common::{grove, root};

fn mkfifo(path: &Path) {
    let ok = std::process::Command::new("mkfifo").arg(path).status().map(|s| s.success()).unwrap_or(false);
    assert!(ok, "mkfifo {} failed", path.display());
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The study scene with `extra` fields inserted before its closing parenthesis.
fn study_scene_with(extra: &str) -> String {
    let text = std::fs::read_to_string(root().join("assets/scenes/study.ron")).unwrap();
    let end = text.rfind(')').unwrap();
    format!("{}{extra}\n{}", &text[..end], &text[end..])
}

fn scatter(boundary: &str, spacing: &str, more: &str) -> String {
    format!("(models: [\"broadleaf\"], boundary: [{boundary}], spacing: {spacing}, seed: 1{more}),")
}

const SQUARE: &str = "(0.0, 0.0), (20.0, 0.0), (20.0, 20.0), (0.0, 20.0)";

#[test]
fn hostile_scatters_are_refused_before_they_allocate() {
    let dir = tempfile::tempdir().unwrap();
    let cases: Vec<(String, &str)> = vec![
        (scatter("(0.0, 0.0), (1000.0, 0.0), (2000.0, 0.0)", "1e-9", ""), "spacing"),
        (scatter("(0.0, 0.0), (1000.0, 0.0), (2000.0, 0.0)", "1.0", ""), "encloses no area"),
        (scatter(SQUARE, "1.0", ", feature: 1e-30"), "feature"),
        (scatter(SQUARE, "1.0", ", scale: (1e30, 1e30)"), "scale"),
        (scatter("(0.0, 0.0), (10000.0, 10000.0), (10000.0, 10000.01)", "0.05", ""), "cells"),
        (
            scatter("(0.0, 0.0), (200.0, 0.0), (200.0, 200.0), (0.0, 200.0)", "1.5", "").repeat(20),
            "more than the limit of 100000 trees",
        ),
        (scatter(SQUARE, "1.0", "").repeat(600), "scatters is more than the limit"),
    ];
    for (i, (scatters, needle)) in cases.iter().enumerate() {
        let p = dir.path().join(format!("scatter{i}.ron"));
        std::fs::write(&p, study_scene_with(&format!("scatter: [{scatters}],"))).unwrap();
        refused_within_bounds(&["scene", "check", s(&p)], needle);
        refused_within_bounds(&["sim", "--scene", s(&p), "--ticks", "1"], needle);
    }
}

#[test]
fn pipes_and_devices_named_as_inputs_are_refused_without_blocking() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.png");
    mkfifo(&fifo);
    let out = dir.path().join("out");
    refused_within_bounds(&["lsystem", "derive", "--grammar", s(&fifo)], "not a regular file");
    refused_within_bounds(&["lsystem", "derive", "--grammar", "/dev/zero"], "not a regular file");
    refused_within_bounds(
        &["aerial", "segment", "--summer", s(&fifo), "--winter", s(&fifo), "--out", s(&out)],
        "not a regular file",
    );
    refused_within_bounds(&["aerial", "tile", s(&fifo), "--out", s(&out)], "not a regular file");
    refused_within_bounds(&["aerial", "tile", "/dev/zero", "--out", s(&out)], "not a regular file");
    // A crowns file that is a pipe, with a valid summary beside it.
    let crowns_dir = dir.path().join("crowns");
    std::fs::create_dir(&crowns_dir).unwrap();
    std::fs::write(crowns_dir.join("summary.json"), SUMMARY).unwrap();
    mkfifo(&crowns_dir.join("crowns.csv"));
    refused_within_bounds(
        &["aerial", "scene", "--crowns", s(&crowns_dir.join("crowns.csv")), "--out", s(&dir.path().join("a.ron"))],
        "not a regular file",
    );
    // A recording in a study folder that is a pipe.
    let replays = dir.path().join("replays");
    std::fs::create_dir(&replays).unwrap();
    std::fs::copy(root().join("replays/study/P01-ray-casting-7.jsonl"), replays.join("P01-ray-casting-7.jsonl"))
        .unwrap();
    mkfifo(&replays.join("P01-manual-7.jsonl"));
    refused_within_bounds(
        &["study", "--replays", s(&replays), "--out", s(&dir.path().join("study"))],
        "not a regular file",
    );
    // An aerial photograph named by a scene.
    let scene = dir.path().join("aerial.ron");
    std::fs::write(
        &scene,
        study_scene_with("aerial: Some((summer: \"pipe.png\", winter: \"pipe.png\", gsd_m: 0.1, origin: (0.0, 0.0))),"),
    )
    .unwrap();
    refused_writing_nothing(
        &["render", "--scene", s(&scene), "--out", s(&dir.path().join("r.png")), "--width", "64", "--height", "36"],
        "not a regular file",
        dir.path(),
    );
}

const SUMMARY: &str = r#"{"width": 1000, "height": 1000, "gsd_m": 0.1, "k": 3, "s": 0.5, "w": 0.5, "equalize": true, "treetop_texels": 0, "crowns": 0}"#;

#[test]
fn an_oversized_grammar_is_refused_before_it_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("big.lsys");
    let f = std::fs::File::create(&p).unwrap();
    f.set_len(2 << 30).unwrap(); // a sparse 2 GiB file: reading it would take seconds and memory
    refused_within_bounds(&["lsystem", "derive", "--grammar", s(&p)], "larger than the limit");
}

#[test]
fn a_grammar_of_zero_length_segments_writes_no_model() {
    let dir = tempfile::tempdir().unwrap();
    let g = dir.path().join("flat.lsys");
    std::fs::write(&g, "axiom: F(1)\nrule: F(x) -> F(0)[+F(0)]\n").unwrap();
    let out = dir.path().join("out");
    refused_writing_nothing(
        &["lsystem", "model", "--grammar", s(&g), "--n", "3", "--out", s(&out)],
        "zero length",
        dir.path(),
    );
    // A name too long for a model: refused before anything is written.
    let long = "a".repeat(300);
    refused_writing_nothing(
        &["lsystem", "model", "--preset", "bush2", "--n", "2", "--name", &long, "--out", s(&out)],
        "must be 1 to 64",
        dir.path(),
    );
}

#[test]
fn a_model_written_then_refused_later_leaves_nothing() {
    // An existing model of the same name: refused; the folder keeps exactly its old files.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let ok = grove(&["lsystem", "model", "--preset", "bush2", "--n", "2", "--out", s(&out)]);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    let first: Vec<PathBuf> = std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().path()).collect();
    assert!(first.iter().any(|p| p.extension().is_some_and(|e| e == "gltf")), "{first:?}");
    refused_writing_nothing(
        &["lsystem", "model", "--preset", "bush2", "--n", "2", "--out", s(&out)],
        "already exists",
        dir.path(),
    );
}

#[test]
fn an_aerial_scene_that_no_command_could_load_is_not_written() {
    let dir = tempfile::tempdir().unwrap();
    let crowns = dir.path().join("crowns.csv");
    let mut text = String::from("id,x_px,y_px,area_px,radius_px,x_m,y_m,area_m2,radius_m\n");
    for i in 0..99_999u32 {
        let (x, y) = (5 + (i % 316) * 3, 5 + (i / 316) * 3);
        text.push_str(&format!("{},{x}.5,{y}.5,28,3.0,{:.2},{:.2},0.28,3.0\n", i + 1, x as f64 * 0.1, y as f64 * 0.1));
    }
    std::fs::write(&crowns, text).unwrap();
    std::fs::write(dir.path().join("summary.json"), SUMMARY).unwrap();
    let out = dir.path().join("scene.ron");
    refused_writing_nothing(
        &["aerial", "scene", "--crowns", s(&crowns), "--out", s(&out), "--min-radius", "0"],
        "bytes, over the limit of 8388608 bytes",
        dir.path(),
    );
}

#[test]
fn a_ground_resolution_that_overflows_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("seg");
    let png = root().join("docs/aerial-pair.png");
    refused_writing_nothing(
        &["aerial", "segment", "--summer", s(&png), "--winter", s(&png), "--gsd", "1e308", "--out", s(&out)],
        "--gsd",
        dir.path(),
    );
}

#[test]
fn argument_errors_are_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = s(&out);
    let png = root().join("docs/aerial-pair.png");
    let p = s(&png);
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["lsystem", "derive", "--preset", "bush2", "--n", "-1"], "--n"),
        (vec!["lsystem", "derive", "--preset", "bush2", "--n", "18446744073709551616"], "--n"),
        (vec!["lsystem", "derive", "--preset", "bush2", "--seed", "18446744073709551616"], "--seed"),
        (vec!["aerial", "segment", "--summer", p, "--winter", p, "--k", "-1", "--out", o], "--k"),
        (vec!["aerial", "segment", "--summer", p, "--winter", p, "--gsd", "-1", "--out", o], "--gsd"),
        (vec!["lsystem", "model", "--preset", "bush2", "--height", "-1", "--out", o], "height"),
        (vec!["aerial", "tile", p, "--out", o, "--tile", "4294967296"], "--tile"),
        (vec!["study", "--no-such-flag"], "--no-such-flag"),
    ];
    for (args, needle) in cases {
        refused_writing_nothing(&args, needle, dir.path());
    }
}

/// A textured triangle as the mutation run builds it, with `edit` applied to its JSON.
fn triangle_model(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let model = dir.join("model");
    std::fs::create_dir_all(model.join("tex")).unwrap();
    let mut bin: Vec<u8> = Vec::new();
    for c in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 1.0, 1.0, 1.0, 0.0, 0.0] {
        bin.extend(c.to_le_bytes());
    }
    std::fs::write(model.join("tri.bin"), &bin).unwrap();
    image::RgbaImage::from_pixel(4, 4, image::Rgba([40, 160, 60, 255])).save(model.join("tex/leaf.png")).unwrap();
    let json = r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}],
 "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], "textures": [{"source": 0}],
 "images": [{"uri": "tex/leaf.png"}], "buffers": [{"uri": "tri.bin", "byteLength": 60}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 2, 0]},
  {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}]}"#;
    let file = model.join("tri.gltf");
    std::fs::write(&file, edit(json.to_string())).unwrap();
    file
}

#[test]
fn gltf_mutants_the_mutation_run_found_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let bank = dir.path().join("bank");
    // The unchanged triangle is accepted, so the refusals below come from the edits.
    let ok = grove(&["models", "add", s(&triangle_model(dir.path(), |j| j)), "--bank", s(&bank), "--name", "tri"]);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    let cases: [(fn(String) -> String, &str); 2] = [
        // A POSITION accessor past the accessors (the gltf crate's validation indexed it unchecked).
        (|j| j.replace(r#""POSITION": 0"#, r#""POSITION": 2000"#), "POSITION"),
        // Fewer texture coordinates than positions (the tangents were computed before the check).
        (
            |j| j.replace(r#""count": 3, "type": "VEC2""#, r#""count": 0, "type": "VEC2""#),
            "attributes of different lengths",
        ),
    ];
    for (i, (edit, needle)) in cases.into_iter().enumerate() {
        let d = dir.path().join(format!("case{i}"));
        let file = triangle_model(&d, edit);
        refused_writing_nothing(
            &["models", "add", s(&file), "--bank", s(&bank), "--name", &format!("m{i}")],
            needle,
            dir.path(),
        );
    }
}
