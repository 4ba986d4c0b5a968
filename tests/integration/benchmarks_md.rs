//! `scripts/benchmarks_md.py` turns the JSON that `grove bench` prints into docs/benchmarks.md.
//! These tests feed it small hand-written JSON and check the page against tables written by hand
//! from that input.

use crate::common;

use std::path::Path;
use std::process::{Command, Output};

use common::{assert_one_line_error, root};

/// The interpreter scripts/test exports, or python3.
fn python() -> String {
    std::env::var("GROVE_PYTHON").unwrap_or_else(|_| "python3".into())
}

fn script(args: &[&str], dir: &Path) -> Output {
    Command::new(python())
        .arg(root().join("scripts/benchmarks_md.py"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| {
            panic!("running {} scripts/benchmarks_md.py: {e} (set GROVE_PYTHON or install python3)", python())
        })
}

const RUN: &str = r#"{
  "machine": "Test CPU, 2 cores", "command": "grove bench sim water raycast", "date": "2026-11-24",
  "build": "release", "threads": 1,
  "sim_tick": [{"trees": 1000, "ms_per_tick_median": 0.0071}, {"trees": 10000, "ms_per_tick_median": 0.071}],
  "water": {"adapter": "llvmpipe", "water_test": {
    "with_water": {"ms_per_frame": 207.0, "fps": 4.83},
    "without_water": {"ms_per_frame": 104, "fps": 9.615}}},
  "raycast": {"trees": 10000, "ns_per_ray_median": 1470.25}
}"#;

/// A later run of one benchmark, without a machine, command or date of its own.
const LATER: &str = r#"{"build": "release", "threads": 1, "raycast": {"trees": 10000, "ns_per_ray_median": 1440.0}}"#;

/// The lines of `page` from the heading `## name` to the next heading.
fn section<'a>(page: &'a str, name: &str) -> Vec<&'a str> {
    let heading = format!("## {name}");
    let mut lines = page.lines().skip_while(|l| *l != heading);
    assert!(lines.next().is_some(), "no section {heading:?} in:\n{page}");
    lines.take_while(|l| !l.starts_with("## ")).filter(|l| !l.is_empty()).collect()
}

#[test]
fn one_table_per_benchmark_with_machine_command_and_date() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("run.json"), RUN).unwrap();
    let out = script(&["--out", "page.md", "run.json"], dir.path());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let page = std::fs::read_to_string(dir.path().join("page.md")).unwrap();

    let sim = section(&page, "sim_tick");
    for meta in [
        "- machine: Test CPU, 2 cores",
        "- command: `grove bench sim water raycast`",
        "- date: 2026-11-24",
        "- build: release",
    ] {
        assert!(sim.contains(&meta), "{meta:?} missing from {sim:#?}");
    }
    let table: Vec<&str> = sim.iter().copied().filter(|l| l.starts_with('|')).collect();
    assert_eq!(table, ["| trees | ms_per_tick_median |", "|---|---|", "| 1000 | 0.0071 |", "| 10000 | 0.071 |"]);

    let water = section(&page, "water");
    assert!(water.contains(&"- adapter: llvmpipe"), "{water:#?}");
    let table: Vec<&str> = water.iter().copied().filter(|l| l.starts_with('|')).collect();
    assert_eq!(
        table,
        [
            "| case | ms_per_frame | fps |",
            "|---|---|---|",
            "| water_test / with_water | 207 | 4.83 |",
            "| water_test / without_water | 104 | 9.615 |",
        ]
    );

    let ray: Vec<&str> = section(&page, "raycast").into_iter().filter(|l| l.starts_with('|')).collect();
    assert_eq!(ray, ["| figure | value |", "|---|---|", "| trees | 10000 |", "| ns_per_ray_median | 1470 |"]);
}

#[test]
fn flags_fill_in_the_machine_and_a_later_file_wins() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("run.json"), RUN).unwrap();
    std::fs::write(dir.path().join("later.json"), LATER).unwrap();
    let args = ["--machine", "Other CPU, 4 cores", "--command", "grove bench raycast", "--date", "2026-11-25"];
    let out = script(&[&args[..], &["--out", "page.md", "run.json", "later.json"]].concat(), dir.path());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let page = std::fs::read_to_string(dir.path().join("page.md")).unwrap();
    let ray = section(&page, "raycast");
    assert!(ray.contains(&"- machine: Other CPU, 4 cores"), "{ray:#?}");
    assert!(ray.contains(&"- date: 2026-11-25"), "{ray:#?}");
    assert!(ray.contains(&"| ns_per_ray_median | 1440 |"), "{ray:#?}");
    assert!(!page.contains("1470"), "the earlier raycast figure should be replaced:\n{page}");
    // The file's own machine stays with its other benchmarks.
    assert!(section(&page, "sim_tick").contains(&"- machine: Test CPU, 2 cores"));
    assert_eq!(page.matches("## raycast").count(), 1);
}

#[test]
fn missing_date_and_hand_written_pages_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("later.json"), LATER).unwrap();
    let out = script(&["--machine", "M", "--command", "C", "--out", "page.md", "later.json"], dir.path());
    assert_one_line_error(&out, 2, "no date");
    assert!(!dir.path().join("page.md").exists(), "no page is written on bad input");

    std::fs::write(dir.path().join("page.md"), "# notes written by hand\n").unwrap();
    let out =
        script(&["--machine", "M", "--command", "C", "--date", "D", "--out", "page.md", "later.json"], dir.path());
    assert_one_line_error(&out, 2, "not written by this script");
    assert_eq!(std::fs::read_to_string(dir.path().join("page.md")).unwrap(), "# notes written by hand\n");

    std::fs::write(dir.path().join("bad.json"), "[1, 2]").unwrap();
    let out = script(&["--machine", "M", "--command", "C", "--date", "D", "--out", "new.md", "bad.json"], dir.path());
    assert_one_line_error(&out, 2, "expected a JSON object");
    let out = script(&["--no-such-flag", "x.json"], dir.path());
    assert_one_line_error(&out, 2, "unrecognized arguments");
}

#[test]
fn the_json_grove_bench_prints_becomes_a_table() {
    let dir = tempfile::tempdir().unwrap();
    let bench = common::grove(&["bench", "sim", "--trees", "1000,2000", "--ticks", "3"]);
    assert!(bench.status.success(), "{}", String::from_utf8_lossy(&bench.stderr));
    std::fs::write(dir.path().join("sim.json"), &bench.stdout).unwrap();
    let out = script(
        &[
            "--machine",
            "this machine",
            "--command",
            "grove bench sim",
            "--date",
            "today",
            "--out",
            "page.md",
            "sim.json",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let page = std::fs::read_to_string(dir.path().join("page.md")).unwrap();
    let sim = section(&page, "sim_tick");
    assert!(sim.contains(&"- build: debug") || sim.contains(&"- build: release"), "{sim:#?}");
    let table: Vec<&str> = sim.iter().copied().filter(|l| l.starts_with('|')).collect();
    assert_eq!(table.len(), 4, "a header, a rule and one row per tree count: {table:#?}");
    assert!(table[0].starts_with("| trees | ") && table[0].contains(" ms_per_tick_median "), "{}", table[0]);
    assert!(table[2].starts_with("| 1000 | ") && table[3].starts_with("| 2000 | "), "{table:#?}");
}

#[test]
fn the_committed_page_is_what_the_script_writes_from_its_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let page = root().join("docs/benchmarks.md");
    let committed = std::fs::read_to_string(&page).unwrap();
    let command = committed
        .lines()
        .find(|l| l.starts_with("python3 scripts/benchmarks_md.py"))
        .expect("the page names the command that regenerates it");
    let inputs: Vec<&str> = command.split_whitespace().skip(4).collect();
    assert!(!inputs.is_empty() && inputs.iter().all(|p| p.starts_with("docs/benchmarks/")), "{command}");
    let out_path = dir.path().join("benchmarks.md");
    let out = Command::new(python())
        .arg(root().join("scripts/benchmarks_md.py"))
        .args(["--out", out_path.to_str().unwrap()])
        .args(&inputs)
        .current_dir(root())
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(
        std::fs::read_to_string(&out_path).unwrap(),
        committed,
        "docs/benchmarks.md is stale: regenerate it with `{command}`"
    );
}

/// `scripts/headline.py` writes the README's headline table between its markers from a folder of
/// benchmark JSON: a figure from the file that holds it, a row whose file is missing says so,
/// and the text around the markers is kept; a README without the markers is refused (exit 2).
#[test]
fn the_headline_table_is_written_between_its_markers_from_the_json() {
    let dir = tempfile::tempdir().unwrap();
    let bench = dir.path().join("benchmarks");
    std::fs::create_dir(&bench).unwrap();
    std::fs::write(
        bench.join("raycast.json"),
        r#"{"machine": "Test CPU, 2 cores", "date": "2026-11-24", "command": "grove bench raycast", "run": "a test run",
            "raycast": {"trees": 10000, "ns_per_ray_median": 1470}}"#,
    )
    .unwrap();
    let readme = dir.path().join("README.md");
    let before = "# grove\n\nintro\n\n<!-- headline table: written by scripts/headline.py from docs/benchmarks/*.json -->\nold table\n<!-- end of the headline table -->\n\nafter\n";
    std::fs::write(&readme, before).unwrap();
    let run = |readme: &Path| {
        Command::new(python())
            .arg(root().join("scripts/headline.py"))
            .args(["--readme", readme.to_str().unwrap(), bench.to_str().unwrap()])
            .output()
            .unwrap()
    };
    let out = run(&readme);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&readme).unwrap();
    assert!(
        text.starts_with("# grove\n\nintro\n\n") && text.ends_with("<!-- end of the headline table -->\n\nafter\n"),
        "{text}"
    );
    assert!(!text.contains("old table"), "{text}");
    assert!(
        text.contains(
            "| one controller ray, 10k trees and the study planes | 1.47 µs | ≤ 2 µs | Test CPU, 2026-11-24 |"
        ),
        "{text}"
    );
    assert!(text.contains("| simulation tick, 100k / 1M trees | not measured |"), "{text}");
    assert!(text.contains("From one run: a test run."), "{text}");
    let bare = dir.path().join("BARE.md");
    std::fs::write(&bare, "# no markers\n").unwrap();
    assert_one_line_error(&run(&bare), 2, "marker");
    assert_eq!(std::fs::read_to_string(&bare).unwrap(), "# no markers\n");
}
