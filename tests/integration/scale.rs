//! Studies in shards: `grove study --shard K/N`, `grove study merge`, `grove synth --shard K/N`
//! and the Slurm script give the same reports and recordings as a run without shards.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{assert_one_line_error, grove, root};

fn ok(o: &Output) {
    assert!(o.status.success(), "exit {:?}; stderr: {}", o.status.code(), String::from_utf8_lossy(&o.stderr));
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `summary.json` without its timing fields (`wall_seconds`, at any depth), as text.
fn without_timing(json: &str) -> String {
    fn strip(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Object(m) => {
                m.remove("wall_seconds");
                m.values_mut().for_each(strip);
            }
            serde_json::Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    let mut v: serde_json::Value = serde_json::from_str(json).unwrap();
    strip(&mut v);
    serde_json::to_string_pretty(&v).unwrap()
}

/// Asserts that two report folders hold the same files: CSV and PNG byte for byte, summary.json
/// equal apart from `wall_seconds`, which is its only line that differs.
fn assert_same_reports(whole: &Path, merged: &Path) {
    let mut names: Vec<String> =
        std::fs::read_dir(whole).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    let mut merged_names: Vec<String> =
        std::fs::read_dir(merged).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    merged_names.sort();
    assert_eq!(names, merged_names, "the same report files");
    assert!(names.iter().any(|n| n == "trial_results.csv") && names.iter().any(|n| n == "summary.json"), "{names:?}");
    for n in &names {
        let (a, b) = (std::fs::read(whole.join(n)).unwrap(), std::fs::read(merged.join(n)).unwrap());
        if n == "summary.json" {
            let (a, b) = (String::from_utf8(a).unwrap(), String::from_utf8(b).unwrap());
            assert_eq!(without_timing(&a), without_timing(&b), "summary.json apart from wall_seconds");
            let differing: Vec<(&str, &str)> = a.lines().zip(b.lines()).filter(|(x, y)| x != y).collect();
            assert!(
                differing.iter().all(|(x, _)| x.trim_start().starts_with("\"wall_seconds\"")),
                "only timing lines differ: {differing:?}"
            );
            assert_eq!(a.lines().count(), b.lines().count());
        } else {
            assert!(a == b, "{n} differs between the run without shards and the merge");
        }
    }
}

/// Runs shards 1..=n of `grove study ARGS` into `dir` and returns the partial results.
fn shards(args: &[&str], n: u32, dir: &Path) -> Vec<PathBuf> {
    shards_counted(args, n, dir).into_iter().map(|(p, _)| p).collect()
}

/// As [`shards`], with the number of recordings each shard re-simulated.
fn shards_counted(args: &[&str], n: u32, dir: &Path) -> Vec<(PathBuf, usize)> {
    (1..=n)
        .map(|k| {
            let part = dir.join(format!("part-{k}"));
            let mut all = vec!["study".to_string()];
            all.extend(args.iter().map(|a| a.to_string()));
            all.extend(["--shard".into(), format!("{k}/{n}"), "--out".into(), part.display().to_string()]);
            let o = Command::new(env!("CARGO_BIN_EXE_grove")).args(&all).current_dir(root()).output().unwrap();
            ok(&o);
            let stdout = String::from_utf8_lossy(&o.stdout);
            let count = stdout
                .strip_prefix(&format!("shard {k}/{n}: "))
                .and_then(|r| r.split(' ').next())
                .and_then(|c| c.parse().ok());
            (part, count.unwrap_or_else(|| panic!("shard {k}/{n} printed {stdout}")))
        })
        .collect()
}

fn merge(parts: &[PathBuf], out: &Path) -> Output {
    let mut all = vec!["study".to_string(), "merge".into()];
    all.extend(parts.iter().map(|p| p.display().to_string()));
    all.extend(["--out".into(), out.display().to_string()]);
    Command::new(env!("CARGO_BIN_EXE_grove")).args(&all).current_dir(root()).output().unwrap()
}

/// Whether shard k of n holds participant p (1-based), by the rule of docs/scale.md:
/// XXH3 of the id `P0p`, modulo n, plus 1.
fn grove_shard_holds(k: u64, n: u64, p: u32) -> bool {
    xxhash_rust::xxh3::xxh3_64(format!("P{p:02}").as_bytes()) % n + 1 == k
}

fn trials_of(summary: &Path) -> usize {
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(summary).unwrap()).unwrap();
    v["trials"].as_array().unwrap().len()
}

#[test]
fn four_shards_of_the_shipped_study_merge_into_the_reports_without_shards() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole");
    ok(&grove(&["study", "--out", s(&whole)]));
    let counted = shards_counted(&[], 4, dir.path());
    // The 24 recordings are spread: each in one shard, no shard with all of them.
    assert_eq!(counted.iter().map(|(_, c)| c).sum::<usize>(), 24);
    assert!(counted.iter().all(|(_, c)| *c < 24), "{counted:?}");
    let parts: Vec<PathBuf> = counted.into_iter().map(|(p, _)| p).collect();
    let merged = dir.path().join("merged");
    // Shards given in any order.
    let mut shuffled = parts.clone();
    shuffled.reverse();
    ok(&merge(&shuffled, &merged));
    assert_eq!(trials_of(&merged.join("summary.json")), 24);
    assert_same_reports(&whole, &merged);
}

#[test]
fn shards_of_a_what_if_and_of_a_sweep_merge_into_the_reports_without_shards() {
    let dir = tempfile::tempdir().unwrap();
    // A what-if on the replayed hands: the what-if and its baseline in every shard.
    let set = ["--set", "snap_threshold=0.2"];
    let whole = dir.path().join("whole");
    let mut args = set.to_vec();
    args.extend(["--out", s(&whole)]);
    let mut study = vec!["study"];
    study.extend(&args);
    ok(&grove(&study));
    let wdir = dir.path().join("w");
    std::fs::create_dir(&wdir).unwrap();
    let merged = dir.path().join("merged");
    ok(&merge(&shards(&set, 4, &wdir), &merged));
    assert_same_reports(&whole, &merged);

    // A sweep, through the Slurm script's array tasks and its merge job.
    let sweep = "snap_threshold=0.1,0.3";
    let whole = dir.path().join("sweep-whole");
    ok(&grove(&["study", "--set", sweep, "--out", s(&whole)]));
    let parts = dir.path().join("parts");
    let out = dir.path().join("sweep-merged");
    let slurm = |cmd: &str, k: u32| {
        Command::new("bash")
            .args([root().join("scripts/slurm_study.sh").to_str().unwrap(), cmd])
            .env("GROVE", env!("CARGO_BIN_EXE_grove"))
            .env("REPLAYS", root().join("replays/study"))
            .env("PARTS", &parts)
            .env("OUT", &out)
            .env("SET", sweep)
            .env("SHARDS", "3")
            .env("SLURM_ARRAY_TASK_ID", k.to_string())
            .current_dir(root())
            .output()
            .unwrap()
    };
    std::fs::create_dir(&parts).unwrap();
    for k in 1..=3 {
        ok(&slurm("shard", k));
    }
    ok(&slurm("merge", 0));
    assert!(out.join("sweep.csv").exists());
    assert_same_reports(&whole, &out);
}

#[test]
fn shards_of_re_simulated_participants_merge_and_synth_shards_are_the_same_recordings() {
    let dir = tempfile::tempdir().unwrap();
    // Three participants in three shards: every recording equals the committed one, which was
    // written without shards.
    let rec = dir.path().join("rec");
    for k in 1..=3 {
        let o = grove(&["synth", "--participants", "3", "--shard", &format!("{k}/3"), "--out", s(&rec)]);
        ok(&o);
        assert!(String::from_utf8_lossy(&o.stdout).contains(&format!("(shard {k}/3)")));
    }
    let mut names: Vec<String> =
        std::fs::read_dir(&rec).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names.len(), 6, "{names:?}");
    for n in &names {
        assert!(
            std::fs::read(rec.join(n)).unwrap() == std::fs::read(root().join("replays/study").join(n)).unwrap(),
            "{n} differs from the committed recording"
        );
    }
    // A shard's synth writes exactly the recordings the same shard of the study re-simulates.
    let one = dir.path().join("one");
    ok(&grove(&["synth", "--participants", "3", "--shard", "2/3", "--out", s(&one)]));
    let o = grove(&["study", "--replays", s(&one), "--shard", "2/3", "--out", s(&dir.path().join("p"))]);
    ok(&o);
    let n = std::fs::read_dir(&one).unwrap().count();
    assert!(
        String::from_utf8_lossy(&o.stdout).contains(&format!("{n} of {n} recordings")),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    // A shard without any participant writes no recording, and its study is an empty part.
    let k = (1..=4).find(|&k| !(1..=3).any(|p| grove_shard_holds(k, 4, p))).expect("a shard of 4 without P01–P03");
    let none = dir.path().join("none");
    ok(&grove(&["synth", "--participants", "3", "--shard", &format!("{k}/4"), "--out", s(&none)]));
    assert_eq!(std::fs::read_dir(&none).unwrap().count(), 0);
    let o = grove(&[
        "study",
        "--replays",
        s(&none),
        "--shard",
        &format!("{k}/4"),
        "--out",
        s(&dir.path().join("empty-part")),
    ]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("0 of 0 recordings"), "{}", String::from_utf8_lossy(&o.stdout));

    // Re-simulated participants under a changed setting, compared with the baseline in shards.
    let what = dir.path().join("what");
    ok(&grove(&["synth", "--participants", "3", "--set", "touchpad_move_rate=3", "--out", s(&what)]));
    let args = ["--replays", s(&what), "--baseline", s(&rec)];
    let whole = dir.path().join("whole");
    let mut study = vec!["study"];
    study.extend(args);
    study.extend(["--out", s(&whole)]);
    ok(&grove(&study));
    let pdir = dir.path().join("parts");
    std::fs::create_dir(&pdir).unwrap();
    let merged = dir.path().join("merged");
    ok(&merge(&shards(&args, 2, &pdir), &merged));
    assert_same_reports(&whole, &merged);

    // The same through the Slurm script's array tasks, each synthesising its own participants
    // (baseline and re-simulated) in a temporary folder.
    let parts = dir.path().join("slurm-parts");
    std::fs::create_dir(&parts).unwrap();
    let out = dir.path().join("slurm-merged");
    let slurm = |cmd: &str, k: u32| {
        Command::new("bash")
            .args([root().join("scripts/slurm_study.sh").to_str().unwrap(), cmd])
            .env("GROVE", env!("CARGO_BIN_EXE_grove"))
            .env("SYNTH_PARTICIPANTS", "3")
            .env("SYNTH_SET", "touchpad_move_rate=3")
            .env("TMPDIR", dir.path())
            .env("PARTS", &parts)
            .env("OUT", &out)
            .env("SHARDS", "2")
            .env("SLURM_ARRAY_TASK_ID", k.to_string())
            .current_dir(root())
            .output()
            .unwrap()
    };
    for k in 1..=2 {
        ok(&slurm("shard", k));
    }
    ok(&slurm("merge", 0));
    assert_same_reports(&whole, &out);
}

#[test]
fn a_missing_repeated_or_foreign_shard_is_one_line_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let rec = dir.path().join("rec");
    std::fs::create_dir(&rec).unwrap();
    for f in ["P01-ray-casting-7.jsonl", "P01-manual-7.jsonl", "P02-manual-7.jsonl", "P03-manual-7.jsonl"] {
        std::fs::copy(root().join("replays/study").join(f), rec.join(f)).unwrap();
    }
    let parts = shards(&["--replays", s(&rec)], 3, dir.path());
    let out = dir.path().join("out");
    assert_one_line_error(&merge(&parts[..2], &out), 2, "shard 3/3 missing");
    assert_one_line_error(
        &merge(&[parts[0].clone(), parts[1].clone(), parts[1].clone(), parts[2].clone()], &out),
        2,
        "shard 2/3 is given twice",
    );
    // A shard of the same recordings under another setting is another study.
    let other = dir.path().join("other");
    ok(&grove(&["study", "--replays", s(&rec), "--set", "snap_threshold=0.2", "--shard", "3/3", "--out", s(&other)]));
    assert_one_line_error(&merge(&[parts[0].clone(), parts[1].clone(), other], &out), 2, "another study");
    // A file that is not a partial result.
    let csv = dir.path().join("x.csv");
    std::fs::write(&csv, "a,b\n").unwrap();
    assert_one_line_error(&merge(&[parts[0].clone(), csv], &out), 2, "not a partial study result");
    let cut = dir.path().join("cut");
    let bytes = std::fs::read(&parts[0]).unwrap();
    std::fs::write(&cut, &bytes[..bytes.len() - 3]).unwrap();
    assert_one_line_error(&merge(&[cut, parts[1].clone(), parts[2].clone()], &out), 2, "damaged partial result");
    assert!(!out.exists() || std::fs::read_dir(&out).unwrap().next().is_none(), "no reports from a refused merge");

    // Bad --shard values, a missing --out and an existing partial result.
    for bad in ["0/3", "4/3", "3", "x/y"] {
        assert_one_line_error(
            &grove(&["study", "--replays", s(&rec), "--shard", bad, "--out", s(&dir.path().join("q"))]),
            2,
            "--shard",
        );
        assert_one_line_error(
            &grove(&["synth", "--participants", "2", "--shard", bad, "--out", s(&dir.path().join("q"))]),
            2,
            "--shard",
        );
    }
    assert_one_line_error(&grove(&["study", "--replays", s(&rec), "--shard", "1/3"]), 2, "--out PART");
    let before = std::fs::read(&parts[0]).unwrap();
    assert_one_line_error(
        &grove(&["study", "--replays", s(&rec), "--shard", "1/3", "--out", s(&parts[0])]),
        2,
        "already exists",
    );
    assert_eq!(std::fs::read(&parts[0]).unwrap(), before, "the partial result is left as it was");
    assert_one_line_error(
        &grove(&["study", "--replays", s(&rec), "--shard", "1/3", "--out", s(dir.path())]),
        2,
        "is a folder",
    );
    // Shards that hold no recording at all make no study.
    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let lone = dir.path().join("lone");
    ok(&grove(&["study", "--replays", s(&empty), "--shard", "1/1", "--out", s(&lone)]));
    assert_one_line_error(&merge(&[lone], &out), 2, "no recordings in any of the shards");
    // The merge refuses a folder holding reports, as grove study does.
    ok(&merge(&parts, &out));
    assert_one_line_error(&merge(&parts, &out), 2, "--force");
}
