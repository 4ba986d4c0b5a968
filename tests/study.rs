//! The study: `grove study` over the committed synthetic recordings, `grove synth`, what-if runs
//! and bad input.

mod common;

use common::{assert_one_line_error, grove, root};

fn study_json(extra: &[&str], out: &std::path::Path) -> (std::process::Output, serde_json::Value) {
    let mut args = vec!["study", "--json", "--out", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let o = grove(&args);
    let v = serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("bad JSON ({e}); stderr: {}", String::from_utf8_lossy(&o.stderr)));
    (o, v)
}

#[test]
fn the_study_reproduces_the_papers_finding() {
    let dir = tempfile::tempdir().unwrap();
    let (out, v) = study_json(&[], dir.path());
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let trials = v["trials"].as_array().unwrap();
    assert_eq!(trials.len(), 24);
    for t in trials {
        assert_eq!(t["status"], "verified", "{}", t["file"]);
        assert!(t["synthetic"].as_bool().unwrap());
        let task = &t["task"];
        assert_eq!(task["completed"], true, "{}", t["file"]);
        assert_eq!(task["trees"].as_array().unwrap().len(), 7, "{}", t["file"]);
        assert!(task["model_types"].as_u64().unwrap() >= 2);
        assert!(task["time_s"].as_f64().unwrap() > 5.0);
    }
    let s = &v["summary"];
    assert_eq!(s["participants"], 12);
    assert_eq!(s["ray_casting_faster_for_all"], true);
    for p in s["per_participant"].as_array().unwrap() {
        assert!(p["ray_casting_s"].as_f64().unwrap() < p["manual_s"].as_f64().unwrap(), "{p}");
    }
    // The files.
    let csv = std::fs::read_to_string(dir.path().join("trial_results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 25, "a header and 24 rows");
    assert!(csv.lines().next().unwrap().starts_with("experiment,ppid,session_num,trial_num"));
    let trees = std::fs::read_to_string(dir.path().join("trees.csv")).unwrap();
    assert_eq!(trees.lines().count(), 1 + 24 * 7);
    let summary: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.path().join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["summary"]["trials"], 24);
    let png = image::open(dir.path().join("ablation.png")).unwrap().to_rgb8();
    assert!(png.width() >= 800 && png.height() >= 400);
    // A real chart: the two bar colours cover a good share of the image.
    let count = |c: [u8; 3]| png.pixels().filter(|p| p.0 == c).count();
    let (blue, orange) = (count([46, 134, 193]), count([230, 126, 34]));
    assert!(blue > 5_000 && orange > blue, "bars: blue {blue}, orange {orange}");
}

#[test]
fn the_table_has_the_researchers_columns() {
    let dir = tempfile::tempdir().unwrap();
    let out = grove(&["study", "--out", dir.path().to_str().unwrap()]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let header = text.lines().next().unwrap();
    for col in ["participant", "task", "mode", "time_s", "trees", "errors", "verified"] {
        assert!(header.contains(col), "{header}");
    }
    assert_eq!(text.lines().filter(|l| l.starts_with('P')).count(), 24);
}

#[test]
fn a_what_if_run_re_evaluates_the_same_input() {
    let dir = tempfile::tempdir().unwrap();
    let (out, v) = study_json(&["--set", "snap_threshold=0.05"], dir.path());
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let trials = v["trials"].as_array().unwrap();
    assert!(trials.iter().all(|t| t["status"] == "what-if"));
    assert_eq!(v["summary"]["overrides"]["snap_threshold"], "0.05");
    // A much tighter threshold means drags that used to snap now stay green in manual mode.
    let manual_done = trials.iter().filter(|t| t["task"]["mode"] == "manual" && t["task"]["completed"] == true).count();
    assert!(manual_done < 12, "with a 5 cm threshold some manual trials no longer complete");
}

#[test]
fn bad_study_input_gives_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = grove(&["study", "--replays", dir.path().to_str().unwrap(), "--out", dir.path().join("o").to_str().unwrap()]);
    assert_one_line_error(&out, 2, "no recordings");
    let out = grove(&["study", "--set", "snap_treshold=0.1", "--out", dir.path().join("o").to_str().unwrap()]);
    assert_one_line_error(&out, 2, "unknown parameter 'snap_treshold'");
    let out = grove(&["study", "--replays", "replays/nope", "--out", dir.path().join("o").to_str().unwrap()]);
    assert_one_line_error(&out, 2, "no such folder");
}

#[test]
fn one_bad_file_is_a_failed_trial_and_the_rest_still_run() {
    let dir = tempfile::tempdir().unwrap();
    let rec = dir.path().join("rec");
    std::fs::create_dir(&rec).unwrap();
    for f in ["P01-ray-casting-7.jsonl", "P01-manual-7.jsonl"] {
        std::fs::copy(root().join("replays/study").join(f), rec.join(f)).unwrap();
    }
    std::fs::write(rec.join("P99-broken.jsonl"), b"{\"type\":\"header\"}\n").unwrap();
    let (out, v) = study_json(&["--replays", rec.to_str().unwrap()], &dir.path().join("o"));
    assert_eq!(out.status.code(), Some(1));
    let trials = v["trials"].as_array().unwrap();
    assert_eq!(trials.len(), 3);
    assert_eq!(trials.iter().filter(|t| t["status"] == "verified").count(), 2);
    let failed: Vec<_> = trials.iter().filter(|t| t["status"] == "failed").collect();
    assert_eq!(failed.len(), 1);
    assert!(failed[0]["error"].as_str().unwrap().contains("P99-broken.jsonl:1"));
}

#[test]
fn synth_is_deterministic_and_matches_the_committed_study() {
    let dir = tempfile::tempdir().unwrap();
    let out = grove(&["synth", "--participants", "1", "--out", dir.path().to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for f in ["P01-ray-casting-7.jsonl", "P01-manual-7.jsonl"] {
        let fresh = std::fs::read(dir.path().join(f)).unwrap();
        // The committed study stays in format version 1 while the recorder writes version 2:
        // the committed file, upgraded, must be exactly what synth writes now.
        let committed_v1 = std::fs::read(root().join("replays/study").join(f)).unwrap();
        let mut committed = Vec::new();
        grove_systems::replay::upgrade(&committed_v1[..], f, &mut committed).unwrap();
        assert!(fresh == committed, "{f}: regenerate the study with `cargo run --release -- synth --force`");
        let text = String::from_utf8(fresh).unwrap();
        assert!(text.lines().next().unwrap().contains("\"synthetic\":true"));
    }
    // It never overwrites existing recordings without --force.
    let again = grove(&["synth", "--participants", "1", "--out", dir.path().to_str().unwrap()]);
    assert_one_line_error(&again, 2, "already exists");
}
