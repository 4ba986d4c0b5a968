//! `grove aerial synth | segment | scene | eval` end to end, TIFF input, and bad input: one line
//! on stderr, exit code 2, nothing overwritten.

use crate::common;

use std::path::Path;

use common::{assert_one_line_error, grove};

fn ok(args: &[&str]) -> String {
    let out = grove(args);
    assert!(out.status.success(), "grove {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).to_string()
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

fn synth(dir: &Path, size: u32) {
    ok(&["aerial", "synth", "--size", &size.to_string(), "--seed", "4", "--gsd", "0.2", "--out", &s(dir)]);
}

#[test]
fn synth_segment_scene_and_eval() {
    let tmp = tempfile::tempdir().unwrap();
    let pair = tmp.path().join("pair");
    synth(&pair, 256);
    for f in ["summer.png", "winter.png", "truth.csv", "distractors.csv"] {
        assert!(pair.join(f).is_file(), "{f}");
    }
    let summer = image::open(pair.join("summer.png")).unwrap();
    assert_eq!((summer.width(), summer.height()), (256, 256));
    let truth = std::fs::read_to_string(pair.join("truth.csv")).unwrap();
    assert!(truth.starts_with("id,species,kind,x_px,y_px,radius_px,x_m,y_m,radius_m,height_m"), "{truth}");
    assert!(truth.contains("deciduous") && truth.contains("evergreen"));

    let seg = tmp.path().join("seg");
    let text = ok(&[
        "aerial",
        "segment",
        "--summer",
        &s(&pair.join("summer.png")),
        "--winter",
        &s(&pair.join("winter.png")),
        "--gsd",
        "0.2",
        "--out",
        &s(&seg),
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["width"], 256);
    assert!(v["crowns"].as_u64().unwrap() > 0, "{v}");
    assert!(v["seconds"]["segment"].as_f64().unwrap() >= 0.0);
    let mask = image::open(seg.join("mask.png")).unwrap().to_luma8();
    assert!(mask.pixels().all(|p| p.0[0] == 0 || p.0[0] == 255));
    assert_eq!(mask.pixels().filter(|p| p.0[0] == 255).count() as u64, v["treetop_texels"].as_u64().unwrap());
    let crowns = std::fs::read_to_string(seg.join("crowns.csv")).unwrap();
    assert!(crowns.starts_with("id,x_px,y_px,area_px,radius_px,x_m,y_m,area_m2,radius_m"));
    assert_eq!(crowns.lines().count() as u64, v["crowns"].as_u64().unwrap() + 1);

    // The scene loads in scene check and in the simulation.
    let scene = tmp.path().join("aerial.ron");
    ok(&["aerial", "scene", "--crowns", &s(&seg.join("crowns.csv")), "--out", &s(&scene)]);
    let check = ok(&["scene", "check", &s(&scene)]);
    assert!(check.contains("plane 'ground'") && check.contains("x -25.6..25.6 m"), "{check}");
    let sim = ok(&["sim", "--scene", &s(&scene), "--ticks", "3", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&sim).unwrap();
    assert!(v["entities"]["trees"].as_u64().unwrap() > 0, "{v}");

    // Eval prints a row per equalisation and k.
    let table = ok(&["aerial", "eval", "--pair", &s(&pair), "--k", "1,3"]);
    assert_eq!(table.lines().filter(|l| l.starts_with("| yes |") || l.starts_with("| no |")).count(), 4, "{table}");
}

#[test]
fn tiff_input_gives_the_same_mask_as_png() {
    let tmp = tempfile::tempdir().unwrap();
    let pair = tmp.path().join("pair");
    synth(&pair, 64);
    for season in ["summer", "winter"] {
        let im = image::open(pair.join(format!("{season}.png"))).unwrap().to_rgb8();
        im.save(pair.join(format!("{season}.tif"))).unwrap();
    }
    let run = |ext: &str, out: &str| {
        let out = tmp.path().join(out);
        ok(&[
            "aerial",
            "segment",
            "--summer",
            &s(&pair.join(format!("summer.{ext}"))),
            "--winter",
            &s(&pair.join(format!("winter.{ext}"))),
            "--k",
            "5",
            "--out",
            &s(&out),
        ]);
        std::fs::read(out.join("crowns.csv")).unwrap()
    };
    assert_eq!(run("png", "a"), run("tif", "b"));
}

#[test]
fn bad_inputs_are_one_line_and_exit_2() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    synth(&a, 32);
    synth(&b, 48);
    let out = s(&tmp.path().join("out"));
    let seg = |summer: &Path, winter: &Path, extra: &[&str]| {
        let mut args = vec![
            "aerial".to_string(),
            "segment".into(),
            "--summer".into(),
            s(summer),
            "--winter".into(),
            s(winter),
            "--out".into(),
            out.clone(),
        ];
        args.extend(extra.iter().map(|x| x.to_string()));
        grove(&args.iter().map(|x| x.as_str()).collect::<Vec<_>>())
    };
    let (sa, wa) = (a.join("summer.png"), a.join("winter.png"));
    assert_one_line_error(&seg(&sa, &b.join("winter.png"), &[]), 2, "32 x 32 but the winter image is 48 x 48");
    assert_one_line_error(&seg(&sa, &tmp.path().join("missing.png"), &[]), 2, "no such file");
    let text = tmp.path().join("notes.png");
    std::fs::write(&text, "not an image").unwrap();
    assert_one_line_error(&seg(&text, &wa, &[]), 2, "not a PNG or TIFF image");
    let rgba = tmp.path().join("rgba.png");
    image::RgbaImage::new(32, 32).save(&rgba).unwrap();
    assert_one_line_error(&seg(&rgba, &wa, &[]), 2, "is 8-bit RGBA, not 8-bit RGB");
    let grey = tmp.path().join("grey.png");
    image::GrayImage::new(32, 32).save(&grey).unwrap();
    assert_one_line_error(&seg(&sa, &grey, &[]), 2, "8-bit grey, not 8-bit RGB");
    let truncated = tmp.path().join("cut.png");
    let bytes = std::fs::read(&sa).unwrap();
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    assert_eq!(
        grove(&["aerial", "segment", "--summer", &s(&truncated), "--winter", &s(&wa), "--out", &out]).status.code(),
        Some(2)
    );
    assert_one_line_error(&seg(&sa, &wa, &["--k", "4"]), 2, "--k 4 must be odd");
    assert_one_line_error(&seg(&sa, &wa, &["--s", "1.5"]), 2, "--s 1.5 must be a fraction");
    assert_one_line_error(
        &seg(&sa, &wa, &["--gsd", "0"]),
        2,
        "--gsd 0 must be between 0.0001 and 1000 metres per pixel",
    );
    assert!(!tmp.path().join("out").exists(), "no output from failed runs");

    // An existing output is never overwritten without --force.
    let out_dir = tmp.path().join("out");
    assert!(seg(&sa, &wa, &[]).status.success());
    let before = std::fs::read(out_dir.join("mask.png")).unwrap();
    assert_one_line_error(&seg(&sa, &wa, &["--k", "7"]), 2, "already exists; pass --force");
    assert_eq!(std::fs::read(out_dir.join("mask.png")).unwrap(), before);
    assert!(seg(&sa, &wa, &["--k", "7", "--force"]).status.success());
    let leftovers: Vec<_> = std::fs::read_dir(&out_dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
        .collect();
    assert!(leftovers.is_empty(), "no temporary files left");

    // Synth and scene refuse to overwrite too; bad sizes and crowns files are one line.
    let truth_before = std::fs::read(a.join("truth.csv")).unwrap();
    let again = grove(&["aerial", "synth", "--size", "40", "--out", &s(&a)]);
    assert_one_line_error(&again, 2, "already exists; pass --force");
    assert_eq!(std::fs::read(a.join("truth.csv")).unwrap(), truth_before);
    assert_one_line_error(
        &grove(&["aerial", "synth", "--size", "8", "--out", &s(&tmp.path().join("tiny"))]),
        2,
        "--size 8 must be between",
    );
    let scene = s(&tmp.path().join("s.ron"));
    assert_one_line_error(
        &grove(&["aerial", "scene", "--crowns", &s(&a.join("truth.csv")), "--out", &scene]),
        2,
        "summary.json",
    );
    let bad = tmp.path().join("bad");
    std::fs::create_dir_all(&bad).unwrap();
    std::fs::copy(out_dir.join("summary.json"), bad.join("summary.json")).unwrap();
    std::fs::write(
        bad.join("crowns.csv"),
        "id,x_px,y_px,area_px,radius_px,x_m,y_m,area_m2,radius_m\n1,2,3,4,5,NaN,1,1,1\n",
    )
    .unwrap();
    assert_one_line_error(
        &grove(&["aerial", "scene", "--crowns", &s(&bad.join("crowns.csv")), "--out", &scene]),
        2,
        "row 2",
    );
    assert!(!tmp.path().join("s.ron").exists());
}
