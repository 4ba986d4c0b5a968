//! `docs/reports.md` is the codebook: every CSV column and every JSON field that `grove study`
//! and `grove replay --json` write must be documented there (as `name` in backticks).

use crate::common;

use std::collections::BTreeSet;
use std::path::Path;

use common::{grove, root};

/// JSON fields whose keys are data (statuses, modes, parameter names, event kinds), not field
/// names: their keys are skipped, their values still checked.
const DATA_MAPS: &[&str] = &["status", "overrides", "modes", "events", "config", "completed"];

fn collect_keys(v: &serde_json::Value, out: &mut BTreeSet<String>) {
    match v {
        serde_json::Value::Object(map) => {
            for (k, x) in map {
                out.insert(k.clone());
                if DATA_MAPS.contains(&k.as_str()) && x.is_object() {
                    for inner in x.as_object().unwrap().values() {
                        collect_keys(inner, out);
                    }
                } else {
                    collect_keys(x, out);
                }
            }
        }
        serde_json::Value::Array(items) => items.iter().for_each(|x| collect_keys(x, out)),
        _ => {}
    }
}

fn csv_header(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines().next().unwrap().split(',').map(str::to_string).collect()
}

fn copy_recordings(to: &Path, participants: &[&str]) {
    std::fs::create_dir_all(to).unwrap();
    for p in participants {
        for t in ["ray-casting-7", "manual-7"] {
            let f = format!("{p}-{t}.jsonl");
            std::fs::copy(root().join("replays/study").join(&f), to.join(&f)).unwrap();
        }
    }
}

fn undocumented(doc: &str, names: impl IntoIterator<Item = String>) -> Vec<String> {
    names.into_iter().filter(|n| !doc.contains(&format!("`{n}`"))).collect()
}

#[test]
fn every_column_and_field_is_documented() {
    let doc = std::fs::read_to_string(root().join("docs/reports.md")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    // P09's manual trial does not complete at snap_threshold = 0.2, so the what-if has an
    // incomplete trial, a missing comparison and paired statistics over the others.
    let rec = dir.path().join("rec");
    copy_recordings(&rec, &["P01", "P02", "P09"]);
    let mut keys = BTreeSet::new();
    let mut columns = Vec::new();

    let out_a = dir.path().join("a");
    let o = grove(&[
        "study",
        "--json",
        "--replays",
        rec.to_str().unwrap(),
        "--out",
        out_a.to_str().unwrap(),
        "--set",
        "snap_threshold=0.2",
    ]);
    assert!(o.status.code().is_some(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(!v["what_if"].is_null());
    collect_keys(&v, &mut keys);
    let file: serde_json::Value = serde_json::from_slice(&std::fs::read(out_a.join("summary.json")).unwrap()).unwrap();
    collect_keys(&file, &mut keys);
    columns.extend(csv_header(&out_a.join("trial_results.csv")));
    columns.extend(csv_header(&out_a.join("trees.csv")));

    let out_b = dir.path().join("b");
    let o = grove(&[
        "study",
        "--json",
        "--replays",
        rec.to_str().unwrap(),
        "--out",
        out_b.to_str().unwrap(),
        "--set",
        "snap_threshold=0.1,0.3",
    ]);
    let v: serde_json::Value =
        serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&o.stderr)));
    assert!(!v["sweep"].is_null());
    collect_keys(&v, &mut keys);
    columns.extend(csv_header(&out_b.join("sweep.csv")));

    let o = grove(&["replay", "--json", "replays/study/P01-ray-casting-7.jsonl"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    collect_keys(&v, &mut keys);

    // The walk found the fields it should have, so the check cannot pass vacuously.
    for k in
        ["ray_casting_faster_for_all", "wilcoxon_p", "baseline_time_s", "kind_meaning", "time_since_start_s", "speedup"]
    {
        assert!(keys.contains(k) || columns.iter().any(|c| c == k), "the outputs lack {k}");
    }
    let missing_fields = undocumented(&doc, keys);
    assert!(missing_fields.is_empty(), "fields not documented in docs/reports.md: {missing_fields:?}");
    let missing_cols = undocumented(&doc, columns);
    assert!(missing_cols.is_empty(), "columns not documented in docs/reports.md: {missing_cols:?}");
}
