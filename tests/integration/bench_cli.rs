//! `grove bench --scene`: the benchmarks that take a scene run on the one given, and the flag
//! is refused where no chosen benchmark takes one. Each case fails on bad input before any
//! timing or device setup, so these runs are short.

use crate::common;

use common::{assert_one_line_error, grove};

#[test]
fn the_benchmarks_that_take_a_scene_read_the_one_given() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no-such-scene.ron");
    let missing = missing.to_str().unwrap();
    // Each of them reads the file named, and says so when it is not there (the park and the
    // forest once ran on their own scenes whatever --scene said).
    for which in ["sim", "raycast", "park", "render-forest"] {
        let out = grove(&["bench", which, "--scene", missing]);
        assert_one_line_error(&out, 2, "no-such-scene.ron");
        assert!(out.stdout.is_empty(), "{which}: no JSON on an error");
    }
    let broken = dir.path().join("broken.ron");
    std::fs::write(&broken, "Scene(name: \"broken\",").unwrap();
    let out = grove(&["bench", "park", "--scene", broken.to_str().unwrap()]);
    assert_one_line_error(&out, 2, "broken.ron");
}

#[test]
fn a_scene_no_chosen_benchmark_takes_is_refused() {
    for which in [&["water"][..], &["grass-goals", "render-reference"]] {
        let mut args = vec!["bench"];
        args.extend_from_slice(which);
        args.extend_from_slice(&["--scene", "assets/scenes/park.ron"]);
        let out = grove(&args);
        assert_one_line_error(&out, 2, "--scene is used only by");
    }
}
