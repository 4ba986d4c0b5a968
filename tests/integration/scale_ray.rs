//! The Ray driver (`scripts/ray_study.py`) on a local Ray cluster of two CPUs: a synthetic study
//! of 1,000 recordings, run as Ray tasks in shards and merged, gives the reports of the run
//! without shards. It needs the Python package `ray` (scripts/requirements-test.txt, which
//! scripts/test installs into a virtual environment and names in GROVE_PYTHON).

use crate::common;

use std::path::Path;
use std::process::{Command, Output};

use common::{grove, root};

fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "exit {:?}; stdout: {}; stderr: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

fn python() -> String {
    let python = std::env::var("GROVE_PYTHON").unwrap_or_else(|_| "python3".into());
    let check = Command::new(&python).args(["-c", "import ray"]).output();
    match check {
        Ok(o) if o.status.success() => python,
        Ok(o) => panic!(
            "the Python package ray is missing for {python} ({}): run the tests through scripts/test, which installs scripts/requirements-test.txt into target/pyenv, or pip install ray and set GROVE_PYTHON",
            String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or("")
        ),
        Err(e) => panic!("{python} does not run ({e}): install Python 3 and ray, or set GROVE_PYTHON"),
    }
}

fn same_reports(whole: &Path, merged: &Path) {
    for n in ["trial_results.csv", "trees.csv", "ablation.png"] {
        assert!(
            std::fs::read(whole.join(n)).unwrap() == std::fs::read(merged.join(n)).unwrap(),
            "{n} differs between the run without shards and Ray's"
        );
    }
    let strip = |p: &Path| -> String {
        let text = std::fs::read_to_string(p).unwrap();
        text.lines().filter(|l| !l.trim_start().starts_with("\"wall_seconds\"")).collect::<Vec<_>>().join("\n")
    };
    assert_eq!(
        strip(&whole.join("summary.json")),
        strip(&merged.join("summary.json")),
        "summary.json apart from wall_seconds"
    );
}

#[test]
fn a_local_ray_cluster_runs_a_1000_recording_synthetic_study_through_the_driver() {
    let python = python();
    let dir = tempfile::tempdir().unwrap();
    let rec = dir.path().join("rec");
    // 1,000 recordings: 500 synthetic participants, each with both tasks. Participant i acts as
    // the shipped participant P(i mod 12 + 1) did (synthesising 500 afresh would triple the
    // test's time): their two recordings, copied under a new id in the header (its checksum
    // re-signed; the chain of the lines after it starts at 0, so they stay as they are).
    std::fs::create_dir(&rec).unwrap();
    for i in 0..500 {
        let from = format!("P{:02}", i % 12 + 1);
        let to = format!("S{:04}", i + 1);
        for task in ["manual-7", "ray-casting-7"] {
            let text = std::fs::read_to_string(root().join(format!("replays/study/{from}-{task}.jsonl"))).unwrap();
            let (header, rest) = text.split_once('\n').unwrap();
            let (body, _) = grove_systems::replay::split_sum(header).unwrap();
            let body = body.replacen(&format!("\"participant\":\"{from}\""), &format!("\"participant\":\"{to}\""), 1);
            assert!(body.contains(&to));
            let (header, _) = grove_systems::replay::sign_body(&body, 0);
            std::fs::write(rec.join(format!("{to}-{task}.jsonl")), format!("{header}\n{rest}")).unwrap();
        }
    }

    let whole = dir.path().join("whole");
    let started = std::time::Instant::now();
    ok(&grove(&["study", "--replays", rec.to_str().unwrap(), "--out", whole.to_str().unwrap()]));
    let unsharded_s = started.elapsed().as_secs_f64();

    let merged = dir.path().join("ray");
    let timings = dir.path().join("timings.json");
    let o = Command::new(&python)
        .arg(root().join("scripts/ray_study.py"))
        .args([
            "--grove",
            env!("CARGO_BIN_EXE_grove"),
            "--replays",
            rec.to_str().unwrap(),
            "--shards",
            "4",
            "--num-cpus",
            "2",
        ])
        .args(["--out", merged.to_str().unwrap(), "--timings", timings.to_str().unwrap()])
        .current_dir(root())
        .output()
        .unwrap();
    ok(&o);
    let t: serde_json::Value = serde_json::from_slice(&std::fs::read(&timings).unwrap()).unwrap();
    assert_eq!(t["per_shard_s"].as_array().unwrap().len(), 4, "{t}");
    // The figures of docs/scale.md (shown with --nocapture).
    eprintln!("1,000 recordings: without shards {unsharded_s:.2} s; through Ray {t}");
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(merged.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["trials"].as_array().unwrap().len(), 1000);
    assert_eq!(v["summary"]["participants"], 500);
    assert_eq!(v["summary"]["status"]["verified"], 1000, "{}", v["summary"]["status"]);
    same_reports(&whole, &merged);

    // Shards that synthesise their own participants (the baseline and the re-simulated ones
    // under a setting) and study them, with nothing but the binary: the reports of the same
    // synthesis and study without shards.
    let (base, what) = (dir.path().join("base"), dir.path().join("what"));
    ok(&grove(&["synth", "--participants", "3", "--out", base.to_str().unwrap()]));
    ok(&grove(&["synth", "--participants", "3", "--set", "touchpad_move_rate=3", "--out", what.to_str().unwrap()]));
    let whole = dir.path().join("synth-whole");
    ok(&grove(&[
        "study",
        "--replays",
        what.to_str().unwrap(),
        "--baseline",
        base.to_str().unwrap(),
        "--out",
        whole.to_str().unwrap(),
    ]));
    let merged = dir.path().join("synth-ray");
    let o = Command::new(&python)
        .arg(root().join("scripts/ray_study.py"))
        .args([
            "--grove",
            env!("CARGO_BIN_EXE_grove"),
            "--synth-participants",
            "3",
            "--synth-set",
            "touchpad_move_rate=3",
            "--shards",
            "2",
            "--num-cpus",
            "2",
        ])
        .args(["--out", merged.to_str().unwrap()])
        .current_dir(root())
        .output()
        .unwrap();
    ok(&o);
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(merged.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["what_if"]["kind"], "re-simulated participants");
    same_reports(&whole, &merged);

    // A driver whose shards fail (grove refuses their input) says why in one line.
    let o = Command::new(&python)
        .arg(root().join("scripts/ray_study.py"))
        .args([
            "--grove",
            env!("CARGO_BIN_EXE_grove"),
            "--replays",
            rec.to_str().unwrap(),
            "--set",
            "snap_treshold=0.1",
            "--shards",
            "2",
            "--num-cpus",
            "2",
        ])
        .args(["--out", dir.path().join("x").to_str().unwrap()])
        .current_dir(root())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.lines().any(|l| l.starts_with("ray_study: ") && l.contains("unknown parameter 'snap_treshold'")),
        "{stderr}"
    );
}
