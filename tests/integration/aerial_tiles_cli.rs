//! `grove aerial tile` end to end: a synthetic photograph into a pyramid the reader opens, and
//! bad input: one line on stderr, exit code 2, nothing overwritten and nothing left behind.

use crate::common;

use std::path::Path;

use common::{assert_one_line_error, grove};
use grove::aerial::tiles::Pyramid;

fn s(p: &Path) -> String {
    p.display().to_string()
}

#[test]
fn tile_a_synthetic_photograph_and_refuse_bad_input() {
    let tmp = tempfile::tempdir().unwrap();
    let pair = tmp.path().join("pair");
    let out = grove(&["aerial", "synth", "--size", "200", "--seed", "3", "--out", &s(&pair)]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let summer = pair.join("summer.png");
    let pyr = tmp.path().join("summer");
    let out = grove(&["aerial", "tile", &s(&summer), "--out", &s(&pyr), "--tile", "64"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let p = Pyramid::open(&pyr).unwrap();
    // 200 → 100 → 50: three mips of tiles of 64.
    assert_eq!((p.meta().width, p.meta().height, p.meta().channels, p.meta().levels), (200, 200, 3, 3));
    let image = image::open(&summer).unwrap().to_rgb8();
    let tile = p.read_tile(0, 3, 1).unwrap();
    // Tile (3, 1) starts at texel (192, 64); its texel (7, 5) is the image's (199, 69).
    let px = image.get_pixel(199, 69).0;
    assert_eq!(&tile[(5 * 64 + 7) * 4..(5 * 64 + 7) * 4 + 4], &[px[0], px[1], px[2], 255]);

    let before = std::fs::read(pyr.join("pyramid.ron")).unwrap();
    assert_one_line_error(&grove(&["aerial", "tile", &s(&summer), "--out", &s(&pyr)]), 2, "--force");
    assert_eq!(std::fs::read(pyr.join("pyramid.ron")).unwrap(), before);
    let other = tmp.path().join("other");
    assert_one_line_error(
        &grove(&["aerial", "tile", &s(&summer), "--out", &s(&other), "--tile", "100"]),
        2,
        "power of two",
    );
    assert_one_line_error(
        &grove(&["aerial", "tile", &s(&pair.join("truth.csv")), "--out", &s(&other)]),
        2,
        "not a PNG or TIFF",
    );
    assert_one_line_error(
        &grove(&["aerial", "tile", &s(&tmp.path().join("none.png")), "--out", &s(&other)]),
        2,
        "none.png",
    );
    assert!(!other.exists());
    let names: Vec<String> =
        std::fs::read_dir(tmp.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(names.iter().all(|n| !n.starts_with('.')), "no temporary folder is left: {names:?}");

    // The flight benchmark over the pyramid, and its bad input.
    let out = grove(&[
        "aerial",
        "flight",
        "--pyramid",
        &s(&pyr),
        "--levels",
        "3",
        "--size",
        "64",
        "--frames",
        "40",
        "--fps",
        "200",
        "--gsd",
        "0.2",
        "--json",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["frames"], 40);
    // The first frame writes three whole windows of 64².
    assert_eq!(v["texels_per_frame"]["first"], 3 * 64 * 64);
    assert_eq!(v["tiles"]["failed"], 0);
    assert_one_line_error(&grove(&["aerial", "flight", "--pyramid", &s(&pair)]), 2, "pyramid.ron");
    assert_one_line_error(&grove(&["aerial", "flight", "--pyramid", &s(&pyr), "--size", "100"]), 2, "power of two");
    assert_one_line_error(&grove(&["aerial", "flight", "--pyramid", &s(&pyr), "--frames", "0"]), 2, "--frames");
}
