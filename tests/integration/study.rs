//! The study: `grove study` over the committed synthetic recordings, `grove synth`, what-if runs
//! and bad input.

use crate::common;

use common::{assert_one_line_error, grove, root};

fn study_json(extra: &[&str], out: &std::path::Path) -> (std::process::Output, serde_json::Value) {
    let mut args = vec!["study", "--json", "--out", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let o = grove(&args);
    let v = serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("bad JSON ({e}); stderr: {}", String::from_utf8_lossy(&o.stderr)));
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
    let mut diffs = Vec::new();
    for p in s["per_participant"].as_array().unwrap() {
        assert!(p["ray_casting_s"].as_f64().unwrap() < p["manual_s"].as_f64().unwrap(), "{p}");
        diffs.push(p["manual_s"].as_f64().unwrap() - p["ray_casting_s"].as_f64().unwrap());
    }
    // The paired statistics are over the twelve differences; the mean and sd recomputed here.
    let paired = &s["paired"];
    assert_eq!(paired["n"], 12);
    assert_eq!(paired["df"], 11);
    let mean = diffs.iter().sum::<f64>() / 12.0;
    let sd = (diffs.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / 11.0).sqrt();
    assert!((paired["mean_difference"].as_f64().unwrap() - mean).abs() < 1e-9);
    assert!((paired["t"].as_f64().unwrap() - mean / (sd / 12f64.sqrt())).abs() < 1e-6);
    assert!(paired["t_test_p"].as_f64().unwrap() < 0.001);
    // Twelve positive differences: W− = 0 and the exact two-sided p is 2 / 2^12.
    assert_eq!(paired["wilcoxon_w_minus"], 0.0);
    assert_eq!(paired["wilcoxon_method"], "exact");
    assert!((paired["wilcoxon_p"].as_f64().unwrap() - 2.0 / 4096.0).abs() < 1e-15);
    assert!(v["note"].as_str().unwrap().contains("synthetic"));
    // Times are whole ticks / 60, and each participant's two trials follow each other in time.
    for t in trials {
        let k = &t["task"];
        let ticks = k["end_tick"].as_u64().unwrap() - k["start_tick"].as_u64().unwrap();
        // JSON parsing may be one unit in the last place off; summed f32 steps would be 1e-5 off.
        assert!((k["time_s"].as_f64().unwrap() - ticks as f64 / 60.0).abs() < 1e-9, "{k}");
    }
    for pair in trials.chunks(2) {
        assert_eq!(pair[0]["participant"], pair[1]["participant"]);
        assert_eq!((pair[0]["trial_num"].as_u64(), pair[1]["trial_num"].as_u64()), (Some(1), Some(2)));
        assert_eq!((pair[0]["block_num"].as_u64(), pair[1]["block_num"].as_u64()), (Some(1), Some(2)));
        assert!(pair[1]["start_time_s"].as_f64().unwrap() > pair[0]["end_time_s"].as_f64().unwrap());
    }
    // Counterbalanced: P01 starts with ray-casting, P02 with manual.
    assert_eq!(trials[0]["task"]["mode"], "ray-casting");
    assert_eq!(trials[2]["participant"], "P02");
    assert_eq!(trials[2]["task"]["mode"], "manual");
    // The files.
    let csv = std::fs::read_to_string(dir.path().join("trial_results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 25, "a header and 24 rows");
    assert!(csv.lines().next().unwrap().starts_with("experiment,ppid,session_num,trial_num"));
    let trees = std::fs::read_to_string(dir.path().join("trees.csv")).unwrap();
    assert_eq!(trees.lines().count(), 1 + 24 * 7);
    // Planting order: within a trial, times since the start grow, and each time since the
    // previous tree is the step between them.
    let rows: Vec<Vec<&str>> = trees.lines().skip(1).map(|l| l.split(',').collect()).collect();
    for trial in rows.chunks(7) {
        let mut previous = 0.0;
        for (i, r) in trial.iter().enumerate() {
            assert_eq!(r[4], (i + 1).to_string());
            let since_start: f64 = r[8].parse().unwrap();
            let since_previous: f64 = r[9].parse().unwrap();
            assert!(since_start >= previous);
            assert!((since_previous - (since_start - previous)).abs() < 2e-4, "{r:?}");
            previous = since_start;
        }
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("summary.json")).unwrap()).unwrap();
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

    // The baseline, the what-if and the difference, per trial and per mode.
    let w = &v["what_if"];
    assert_eq!(w["kind"], "replayed hands");
    assert_eq!(w["parameters"][0]["name"], "snap_threshold");
    assert_eq!(w["parameters"][0]["default_value"], "0.3");
    assert_eq!(w["parameters"][0]["new_value"], "0.05");
    let per_trial = w["per_trial"].as_array().unwrap();
    assert_eq!(per_trial.len(), 24);
    for c in per_trial {
        assert_eq!(c["baseline_status"], "verified");
        assert!(c["baseline_time_s"].as_f64().is_some(), "every baseline trial completes: {c}");
        match (c["what_if_time_s"].as_f64(), c["difference_s"].as_f64()) {
            (Some(wt), Some(d)) => assert!((d - (wt - c["baseline_time_s"].as_f64().unwrap())).abs() < 1e-9),
            (None, d) => assert!(d.is_none()),
            (Some(_), None) => panic!("a difference is missing: {c}"),
        }
    }
    let manual = &w["modes"]["manual"];
    assert_eq!(manual["pairs"].as_u64().unwrap() as usize, manual_done);
    assert_eq!(manual["unpaired"].as_u64().unwrap() as usize, 12 - manual_done);
    // Incomplete trials: counted, named, left out; the claim over every participant is open.
    let s = &v["summary"];
    assert_eq!(s["incomplete_count"].as_u64().unwrap() as usize, 12 - manual_done);
    assert!(
        s["incomplete"].as_array().unwrap().iter().all(|i| i["reason"] == "not completed" && i["task"] == "manual-7")
    );
    assert!(s["ray_casting_faster_for_all"].is_null());
    assert_eq!(s["missing_comparisons"].as_array().unwrap().len(), 12 - manual_done);
    // Paired statistics need two participants with both tasks.
    assert_eq!(s["paired"].is_null(), manual_done < 2, "{}", s["paired"]);
    assert_eq!(s["comparisons"].as_u64().unwrap() as usize, manual_done);
    // The CSV: an empty time for incomplete trials, and the what-if columns.
    let mut rdr = csv::Reader::from_path(dir.path().join("trial_results.csv")).unwrap();
    let head = rdr.headers().unwrap().clone();
    let col = |name: &str| head.iter().position(|h| h == name).unwrap();
    let mut empty = 0;
    for r in rdr.records() {
        let r = r.unwrap();
        assert_eq!(&r[col("what_if_kind")], "replayed hands");
        assert_eq!(
            (&r[col("parameter")], &r[col("default_value")], &r[col("new_value")]),
            ("snap_threshold", "0.3", "0.05")
        );
        if &r[col("completed")] == "false" {
            assert_eq!(&r[col("time_s")], "");
            assert_eq!(&r[col("difference_s")], "");
            empty += 1;
        }
    }
    assert_eq!(empty, 12 - manual_done);
    // The chart marks each missing bar with a red cross.
    let png = image::open(dir.path().join("ablation.png")).unwrap().to_rgb8();
    assert!(png.pixels().filter(|p| p.0 == [200, 30, 30]).count() > 20);
}

#[test]
fn a_sweep_writes_one_row_per_value_and_its_chart() {
    let dir = tempfile::tempdir().unwrap();
    let rec = dir.path().join("rec");
    std::fs::create_dir(&rec).unwrap();
    for f in ["P01-ray-casting-7.jsonl", "P01-manual-7.jsonl", "P02-ray-casting-7.jsonl", "P02-manual-7.jsonl"] {
        std::fs::copy(root().join("replays/study").join(f), rec.join(f)).unwrap();
    }
    let (out, v) = study_json(
        &["--replays", rec.to_str().unwrap(), "--set", "snap_threshold=0.05,0.3,0.5"],
        &dir.path().join("o"),
    );
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let sweep = &v["sweep"];
    assert_eq!(sweep["parameter"], "snap_threshold");
    assert_eq!(sweep["default_value"], "0.3");
    let rows = sweep["rows"].as_array().unwrap();
    assert_eq!(rows.iter().map(|r| r["value"].as_str().unwrap()).collect::<Vec<_>>(), ["0.05", "0.3", "0.5"]);
    assert_eq!(rows.iter().map(|r| r["is_default"].as_bool().unwrap()).collect::<Vec<_>>(), [false, true, false]);
    // At the default value the what-if is the baseline: no difference at all.
    for mode in ["ray-casting", "manual"] {
        assert_eq!(rows[1]["modes"][mode]["difference_s"], 0.0);
        assert_eq!(rows[1]["modes"][mode]["what_if_mean_s"], rows[1]["modes"][mode]["baseline_mean_s"]);
    }
    let csv = std::fs::read_to_string(dir.path().join("o/sweep.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 3);
    assert!(csv.lines().nth(2).unwrap().starts_with("replayed hands,snap_threshold,0.3,0.3,true,"));
    let png = image::open(dir.path().join("o/sweep.png")).unwrap().to_rgb8();
    let count = |c: [u8; 3]| png.pixels().filter(|p| p.0 == c).count();
    assert!(count([46, 134, 193]) > 200 && count([230, 126, 34]) > 200, "both lines are drawn");
    // The terminal table of a single what-if names the kind, the default and the new value, and
    // gives the baseline, the what-if and the difference per trial.
    let o = grove(&[
        "study",
        "--replays",
        rec.to_str().unwrap(),
        "--out",
        dir.path().join("t").to_str().unwrap(),
        "--set",
        "snap_threshold=0.2",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.starts_with("what-if (replayed hands): snap_threshold 0.3 (default) → 0.2\n"), "{text}");
    for needle in [
        "baseline_s",
        "what_if_s",
        "diff_s",
        "what-if kind: replayed hands",
        "paired (manual − ray-casting, n = 2)",
        "note: synthetic data",
    ] {
        assert!(text.contains(needle), "{needle} missing in:\n{text}");
    }
    // Two swept parameters at once are refused.
    let o = grove(&[
        "study",
        "--replays",
        rec.to_str().unwrap(),
        "--out",
        dir.path().join("p").to_str().unwrap(),
        "--set",
        "snap_threshold=0.1,0.2",
        "--set",
        "spawn_distance=1,2",
    ]);
    assert_one_line_error(&o, 2, "only one parameter can be swept");
}

#[test]
fn re_simulated_participants_are_compared_with_their_baseline() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("base");
    std::fs::create_dir(&base).unwrap();
    for f in ["P01-ray-casting-7.jsonl", "P01-manual-7.jsonl"] {
        std::fs::copy(root().join("replays/study").join(f), base.join(f)).unwrap();
    }
    let what = dir.path().join("what");
    let out =
        grove(&["synth", "--participants", "1", "--set", "touchpad_move_rate=3", "--out", what.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let header = std::fs::read_to_string(what.join("P01-manual-7.jsonl")).unwrap();
    assert!(header.lines().next().unwrap().contains("\"config\":{\"touchpad_move_rate\":\"3\"}"));
    let (out, v) =
        study_json(&["--replays", what.to_str().unwrap(), "--baseline", base.to_str().unwrap()], &dir.path().join("o"));
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let w = &v["what_if"];
    assert_eq!(w["kind"], "re-simulated participants");
    assert_eq!(w["parameters"][0]["name"], "touchpad_move_rate");
    assert_eq!(w["parameters"][0]["default_value"], "1.5");
    assert_eq!(w["parameters"][0]["new_value"], "3");
    let c = w["per_trial"].as_array().unwrap().iter().find(|c| c["mode"] == "manual").unwrap();
    assert_eq!(c["what_if_status"], "verified");
    // A participant who pushes the tree twice as fast finishes the manual task sooner.
    assert!(c["difference_s"].as_f64().unwrap() < 0.0, "{c}");
    // Without --out, synth --set refuses to write over the study.
    let o = grove(&["synth", "--participants", "1", "--set", "snap_threshold=0.2"]);
    assert_one_line_error(&o, 2, "--out");
}

#[test]
fn bad_study_input_gives_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out =
        grove(&["study", "--replays", dir.path().to_str().unwrap(), "--out", dir.path().join("o").to_str().unwrap()]);
    assert_one_line_error(&out, 2, "no recordings");
    let out = grove(&["study", "--set", "snap_treshold=0.1", "--out", dir.path().join("o").to_str().unwrap()]);
    assert_one_line_error(&out, 2, "unknown parameter 'snap_treshold'");
    // A value outside the parameter's range, in a sweep too, is refused with the range.
    let out = grove(&["study", "--set", "snap_threshold=0.1,12", "--out", dir.path().join("o").to_str().unwrap()]);
    assert_one_line_error(&out, 2, "snap_threshold: '12' must be a number from 0 to 10 m");
    assert!(!dir.path().join("o").exists());
    // The one --set parser serves grove synth and grove test too: the same range, and a list
    // (a sweep) refused where nothing is swept; min_scale above max_scale refused everywhere.
    let out = grove(&[
        "synth",
        "--participants",
        "1",
        "--set",
        "spawn_distance=101",
        "--out",
        dir.path().join("s").to_str().unwrap(),
    ]);
    assert_one_line_error(&out, 2, "spawn_distance: '101' must be a number from 0 to 100 m");
    for cmd in ["synth", "test"] {
        let out = grove(&[cmd, "--set", "snap_threshold=0.1,0.2"]);
        assert_one_line_error(&out, 2, "snap_threshold=0.1,0.2: one value only here");
        let out = grove(&[cmd, "--set", "min_scale=5", "--set", "max_scale=2"]);
        assert_one_line_error(&out, 2, "min_scale 5 is above max_scale 2");
    }
    let out = grove(&[
        "study",
        "--set",
        "max_scale=2",
        "--set",
        "min_scale=1,3",
        "--out",
        dir.path().join("o").to_str().unwrap(),
    ]);
    assert_one_line_error(&out, 2, "min_scale 3 is above max_scale 2");
    assert!(!dir.path().join("s").exists() && !dir.path().join("o").exists());
    // --help lists every parameter with its default and range.
    let help = String::from_utf8(grove(&["study", "--help"]).stdout).unwrap();
    assert!(
        help.contains("touchpad_dead_zone") && help.contains("0.15, 0 to 1:") && help.contains("0.3 m, 0 to 10 m:"),
        "{help}"
    );
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
        // The committed study is in format version 2, as the recorder writes it.
        let committed = std::fs::read(root().join("replays/study").join(f)).unwrap();
        assert!(fresh == committed, "{f}: regenerate the study with `cargo run --release -- synth --force`");
        let text = String::from_utf8(fresh).unwrap();
        assert!(text.lines().next().unwrap().contains("\"synthetic\":true"));
    }
    // It never overwrites existing recordings without --force.
    let again = grove(&["synth", "--participants", "1", "--out", dir.path().to_str().unwrap()]);
    assert_one_line_error(&again, 2, "already exists");
}
