//! Techniques as plug-ins through the app: `grove synth --techniques` with the gaze-dwell
//! example crate, `grove study` over three conditions (Friedman, post-hoc, order effects), and
//! the refusal of recordings whose technique is not registered. The statistics themselves are
//! checked against published examples in `src/study/friedman.rs`.

use crate::common;

use std::path::Path;

use common::{assert_one_line_error, grove, grove_with};
use grove_systems::replay::rechain;

fn synth(out: &Path, participants: &str, techniques: &str) {
    let o = grove(&[
        "synth",
        "--participants",
        participants,
        "--techniques",
        techniques,
        "--out",
        &out.display().to_string(),
    ]);
    assert!(o.status.success(), "synth: {}", String::from_utf8_lossy(&o.stderr));
}

fn lines(path: &Path) -> Vec<String> {
    std::fs::read_to_string(path).unwrap().lines().map(str::to_string).collect()
}

#[test]
fn twelve_participants_by_three_techniques_give_a_friedman_analysis() {
    let dir = tempfile::tempdir().unwrap();
    let rec = dir.path().join("rec");
    synth(&rec, "12", "ray-casting,manual,gaze-dwell");
    // Each participant does each technique once, in a balanced Latin square order: every
    // technique is first for 4 of the 12.
    let mut first = std::collections::BTreeMap::new();
    for p in 1..=12 {
        for t in ["ray-casting-7", "manual-7", "gaze-dwell"] {
            let header: serde_json::Value =
                serde_json::from_str(&lines(&rec.join(format!("P{p:02}-{t}.jsonl")))[0]).unwrap();
            if header["block"] == 1 {
                *first.entry(t).or_insert(0) += 1;
            }
            let named = header.get("technique").map(|t| (t["name"].clone(), t["version"].clone()));
            if t == "gaze-dwell" {
                assert_eq!(
                    named,
                    Some(("gaze-dwell".into(), 1.into())),
                    "the header names the plug-in and its version"
                );
            } else {
                assert_eq!(named, None, "a built-in technique's header is as before");
            }
        }
    }
    assert_eq!(first.values().copied().collect::<Vec<i32>>(), vec![4, 4, 4], "{first:?}");

    let out = dir.path().join("out");
    let o = grove(&["study", "--replays", &rec.display().to_string(), "--out", &out.display().to_string(), "--json"]);
    assert!(o.status.success(), "study: {}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let k = &v["summary"]["conditions"];
    assert_eq!(k["conditions"], serde_json::json!(["ray-casting", "manual", "gaze-dwell"]));
    assert_eq!(k["complete_participants"], 12);
    let f = &k["analysis"]["friedman"];
    assert_eq!((f["n"].as_u64(), f["k"].as_u64(), f["df"].as_u64()), (Some(12), Some(3), Some(2)));
    let (chi, p) = (f["chi_squared"].as_f64().unwrap(), f["p"].as_f64().unwrap());
    assert!(chi > 0.0 && (0.0..=1.0).contains(&p));
    // Mean ranks of n participants over 3 conditions sum to 1 + 2 + 3.
    let ranks: f64 = f["mean_ranks"].as_array().unwrap().iter().map(|r| r.as_f64().unwrap()).sum();
    assert!((ranks - 6.0).abs() < 1e-9);
    let pairs = k["analysis"]["pairs"].as_array().unwrap();
    assert_eq!(pairs.len(), 3);
    for pair in pairs {
        let (raw, holm) = (pair["stats"]["wilcoxon_p"].as_f64().unwrap(), pair["p_holm"].as_f64().unwrap());
        assert!(holm >= raw && holm <= 1.0, "{pair}");
        assert!(pair["stats"]["ci95_low"].as_f64().unwrap() <= pair["stats"]["ci95_high"].as_f64().unwrap());
    }
    // Order effects: three blocks of twelve trials.
    let blocks: Vec<u64> = k["by_block"].as_array().unwrap().iter().map(|b| b["n"].as_u64().unwrap()).collect();
    assert_eq!(blocks, vec![12, 12, 12]);
    // The paired two-condition analysis is still there, unchanged in form.
    assert_eq!(v["summary"]["paired"]["difference"], "manual − ray-casting");
    // The terminal report prints the section.
    let o = grove(&[
        "study",
        "--replays",
        &rec.display().to_string(),
        "--out",
        &dir.path().join("out2").display().to_string(),
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("Friedman test over 12 participants: χ²(2)")
            && text.contains("p (Holm)")
            && text.contains("gaze-dwell − ray-casting"),
        "{text}"
    );
}

#[test]
fn a_recording_whose_technique_is_not_registered_ends_with_exit_2_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let rec = dir.path().join("rec");
    synth(&rec, "1", "gaze-dwell");
    let original = lines(&rec.join("P01-gaze-dwell.jsonl"));
    let o = grove_with(&["replay"], &rec.join("P01-gaze-dwell.jsonl"));
    assert!(o.status.success(), "the plug-in's own recording replays: {}", String::from_utf8_lossy(&o.stderr));

    let forge = |from: &str, to: &str, name: &str| {
        let edited: Vec<String> = original.iter().map(|l| l.replace(from, to)).collect();
        let path = dir.path().join(name);
        std::fs::write(&path, rechain(&edited).unwrap().join("\n") + "\n").unwrap();
        path
    };
    let other = forge("gaze-dwell", "grid-snap", "other.jsonl");
    assert_one_line_error(&grove_with(&["replay"], &other), 2, "technique 'grid-snap' is not registered");
    let newer = forge("\"version\":1}", "\"version\":7}", "newer.jsonl");
    assert_one_line_error(&grove_with(&["replay"], &newer), 2, "technique 'gaze-dwell' version 7");
}

#[test]
fn unknown_techniques_on_the_command_line_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x").display().to_string();
    assert_one_line_error(
        &grove(&["synth", "--techniques", "ray-casting,grid-snap", "--out", &out]),
        2,
        "technique 'grid-snap' is not registered",
    );
    assert_one_line_error(&grove(&["synth", "--techniques", "manual,manual", "--out", &out]), 2, "twice");
    assert_one_line_error(&grove(&["synth", "--techniques", "gaze-dwell"]), 2, "--out");
    assert_one_line_error(&grove(&["play", "--technique", "grid-snap"]), 2, "technique 'grid-snap' is not registered");
    assert!(!dir.path().join("x").exists(), "nothing written");
}

#[test]
fn a_scenario_file_switches_to_a_plug_in_technique_by_name() {
    let dir = tempfile::tempdir().unwrap();
    // The head 1.7 m above (1, 0, -4), looking straight down (−90° about +X): the gaze rests on
    // the ground for 60 ticks (1 s), longer than the 0.8 s dwell, and plants once.
    let file = dir.path().join("gaze.ron");
    std::fs::write(
        &file,
        r#"Scenario(
    scene: "study",
    seed: 3,
    steps: [
        SwitchTechnique("gaze-dwell"),
        Head(position: (1.0, 1.7, -4.0), rotation: (-0.70710677, 0.0, 0.0, 0.70710677)),
        Wait(60),
    ],
    expect: [
        Logged(kind: "technique_changed", count: 1),
        Logged(kind: "planted", count: 1),
        TreeNear(model: "broadleaf-mesh", point: (1.0, 0.0, -4.0), within: 0.2),
    ],
)
"#,
    )
    .unwrap();
    let o = grove_with(&["test"], &file);
    assert!(o.status.success(), "{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));

    let bad = dir.path().join("bad.ron");
    std::fs::write(&bad, std::fs::read_to_string(&file).unwrap().replace("\"gaze-dwell\"", "\"grid-snap\"")).unwrap();
    let o = grove_with(&["test"], &bad);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("known: ray-casting, manual, gaze-dwell"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The plug-in's committed synthetic recordings (`techniques/gaze-dwell/replays/`) replay to
/// their checkpoints, and `grove synth` writes them again byte for byte. After an intended
/// change, regenerate them with `grove synth --participants 2 --techniques gaze-dwell --out
/// techniques/gaze-dwell/replays --force`.
#[test]
fn the_committed_gaze_dwell_recordings_replay_and_regenerate_unchanged() {
    let committed = common::root().join("techniques/gaze-dwell/replays");
    let dir = tempfile::tempdir().unwrap();
    synth(dir.path(), "2", "gaze-dwell");
    for name in ["P01-gaze-dwell.jsonl", "P02-gaze-dwell.jsonl"] {
        let o = grove_with(&["replay"], &committed.join(name));
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(
            o.status.success() && text.contains("verified, complete") && text.contains("(gaze-dwell): completed"),
            "{name}: {text}{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(
            std::fs::read(committed.join(name)).unwrap() == std::fs::read(dir.path().join(name)).unwrap(),
            "{name} differs from a fresh grove synth"
        );
    }
}
