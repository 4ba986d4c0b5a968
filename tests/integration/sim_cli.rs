//! `grove sim` and `grove scene check`: determinism, the pinned study hash and bad scenes.

use crate::common;

use common::{assert_one_line_error, grove, grove_with, root};

fn sim_json(args: &[&str]) -> serde_json::Value {
    let out = grove(args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The pinned hash of `grove sim --scene assets/scenes/study.ron --ticks 600`.
/// Regenerate after an intended simulation change with:
/// `UPDATE_PINS=1 cargo test --test integration sim_cli::`.
const PIN: &str = "tests/pinned/study-600.hash";

#[test]
fn the_study_hash_is_stable_and_pinned() {
    let args = ["sim", "--scene", "assets/scenes/study.ron", "--ticks", "600", "--json"];
    let a = sim_json(&args);
    let b = sim_json(&args);
    assert_eq!(a["hash"], b["hash"], "two runs give the same hash");
    assert_eq!(a["ticks"], 600);
    assert_eq!(a["entities"]["planes"], 2);
    let hash = a["hash"].as_str().unwrap().to_string();
    let pin = root().join(PIN);
    if std::env::var_os("UPDATE_PINS").is_some() {
        std::fs::write(&pin, format!("{hash}\n")).unwrap();
    }
    let pinned = std::fs::read_to_string(&pin).expect("pinned hash file; create it with UPDATE_PINS=1");
    assert_eq!(
        hash,
        pinned.trim(),
        "the study hash changed; if intended, run UPDATE_PINS=1 cargo test --test integration sim_cli::"
    );
}

#[test]
fn scattered_trees_run_and_are_counted() {
    let v = sim_json(&["sim", "--scene", "assets/scenes/study.ron", "--ticks", "5", "--trees", "2000", "--json"]);
    assert_eq!(v["entities"]["trees"], 2002);
    assert_eq!(v["ticks"], 5);
    assert!(v["wall_seconds"].as_f64().unwrap() >= 0.0);
}

#[test]
fn a_different_seed_changes_the_hash() {
    let a = sim_json(&["sim", "--scene", "assets/scenes/study.ron", "--ticks", "10", "--json"]);
    let b = sim_json(&["sim", "--scene", "assets/scenes/study.ron", "--ticks", "10", "--seed", "1", "--json"]);
    assert_ne!(a["hash"], b["hash"]);
}

#[test]
fn scene_check_summarises_the_study_scene() {
    let out = grove(&["scene", "check", "assets/scenes/study.ron"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("plane 'ground'") && text.contains("plane 'terrace'"), "{text}");
}

fn broken(name: &str, text: &str, needle: &str) {
    assert!(text != study(), "{name}: the mutation must change the scene");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("{name}.ron"));
    std::fs::write(&path, text).unwrap();
    let out = grove_with(&["scene", "check"], &path);
    assert_one_line_error(&out, 2, needle);
    assert!(String::from_utf8_lossy(&out.stderr).contains(&format!("{name}.ron")), "names the file");
}

fn study() -> String {
    std::fs::read_to_string(root().join("assets/scenes/study.ron")).unwrap()
}

#[test]
fn broken_scenes_give_one_line_errors() {
    broken("syntax", &study().replacen("planes: [", "planes: [[", 1), "line ");
    broken("unknown", &study().replacen("seed: 20190612,", "seed: 20190612, colour: 3,", 1), "colour");
    broken("nan", &study().replacen("strength: 0.5,", "strength: NaN,", 1), "NaN or infinite");
    broken("inf", &study().replacen("elevation: 0.8,", "elevation: inf,", 1), "NaN or infinite");
    broken("scale", &study().replacen("scale: 1.2", "scale: -1.2", 1), "scale must be positive");
    broken("latitude", &study().replacen("latitude_deg: 47.3769", "latitude_deg: 97.3", 1), "latitude");
    broken("date", &study().replacen("2026-06-21T09:30:00Z", "2026-13-45T09:30:00Z", 1), "RFC 3339");
}

#[test]
fn a_plane_with_fewer_than_three_vertices_is_rejected() {
    let text = r#"Scene(
        name: "tiny",
        planes: [(name: "bad", shape: Mesh(vertices: [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0)], triangles: [(0, 1, 1)]))],
        sun: (latitude_deg: 0.0, longitude_deg: 0.0, utc: "2026-01-01T12:00:00Z"),
        wind: (direction: (1.0, 0.0, 0.0), strength: 0.0, density: 0.1, gust_average: 0.0, gust_strength: 0.0, gust_frequency: 0.0),
        camera: (position: (0.0, 1.7, 5.0), look_at: (0.0, 0.0, 0.0)),
    )"#;
    broken("twoverts", text, "at least 3");
}

#[test]
fn a_missing_scene_file_is_an_error() {
    let out = grove(&["scene", "check", "assets/scenes/nope.ron"]);
    assert_one_line_error(&out, 2, "nope.ron: no such file");
    let out = grove(&["sim", "--scene", "assets/scenes/nope.ron", "--ticks", "1"]);
    assert_one_line_error(&out, 2, "no such file");
}

#[test]
fn help_lists_only_working_subcommands() {
    let out = grove(&["--help"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let listed: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(listed.contains(&"sim") && listed.contains(&"replay"), "{listed:?}");
    for cmd in listed {
        let out = grove(&[cmd, "--help"]);
        assert!(out.status.success(), "`grove {cmd} --help` works");
    }
}

/// A reader that closes the pipe early (`grove … | head`) ends grove quietly: no "internal
/// error" line, as with other command-line tools.
#[test]
fn a_closed_pipe_is_not_an_internal_error() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_grove"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["scene", "check", "assets/scenes/park.ron"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("internal error"), "{err}");
    assert!(err.is_empty(), "{err}");
}
