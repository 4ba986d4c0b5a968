//! The HTML reports (`grove study --html`, `grove replay --html`) opened in headless Chromium
//! (Debian's `chromium`, network off): the DOM after the page's script ran holds every
//! participant and trial, the numbers of summary.json, no script error; a screenshot of the
//! overview goes to target/html-report/; the heatmap of a scripted ray that dwells at a known
//! point peaks there; a diverged recording's page names the tick and the components, and the
//! field when the resources differ.

use crate::common;

use std::path::Path;

use common::{assert_one_line_error, chromium, grove, root};
use glam::Vec3;
use grove_systems::Sim;
use grove_systems::replay::{Header, record_events};
use grove_systems::scene::Scene;
use grove_systems::script::Script;

/// The page's script ran to its end and nothing was reported as an error, by the page or in
/// Chromium's console log.
fn assert_no_page_errors(dom: &str, log: &str) {
    assert!(dom.contains("data-ready=\"1\""), "the page's script did not finish");
    assert!(
        !dom.contains("data-errors="),
        "the page caught errors: {}",
        attr_after(dom, "data-errors=\"").unwrap_or_default()
    );
    // Chromium logs every console message (console.error, uncaught exceptions) as ":CONSOLE";
    // the page logs nothing when all is well.
    for line in log.lines() {
        assert!(!line.contains(":CONSOLE") && !line.to_lowercase().contains("uncaught"), "the page logged: {line}");
    }
}

/// The text after `key` up to the next double quote.
fn attr_after(text: &str, key: &str) -> Option<String> {
    let i = text.find(key)? + key.len();
    Some(text[i..].split('"').next()?.to_string())
}

/// The exact value and the shown text of `data-field="FIELD"` within `scope`.
fn field(scope: &str, name: &str) -> Option<(f64, String)> {
    let key = format!("data-field=\"{name}\" data-value=\"");
    let i = scope.find(&key)? + key.len();
    let v: f64 = scope[i..].split('"').next()?.parse().ok()?;
    let shown = scope[i..].split('>').nth(1)?.split('<').next()?.to_string();
    Some((v, shown))
}

/// The element that starts at the first `start` and ends at the next `end`.
fn slice<'a>(text: &'a str, start: &str, end: &str) -> &'a str {
    let i = text.find(start).unwrap_or_else(|| panic!("no {start}"));
    let j = text[i..].find(end).map_or(text.len(), |j| i + j);
    &text[i..j]
}

/// Checks a number on the page against summary.json: the exact value, and the shown text rounded.
fn assert_number(scope: &str, name: &str, want: &serde_json::Value) {
    match want.as_f64() {
        None => assert!(field(scope, name).is_none(), "{name}: the page shows a number where summary.json has {want}"),
        Some(w) => {
            let (v, shown) = field(scope, name).unwrap_or_else(|| panic!("{name} missing on the page"));
            // The page's value is the exact one; serde_json (without float_roundtrip) may read
            // summary.json's text one unit in the last place off.
            assert!((v - w).abs() <= 4.0 * f64::EPSILON * w.abs().max(1.0), "{name}: page {v}, summary.json {w}");
            let s: f64 = shown.trim().parse().unwrap_or_else(|_| panic!("{name}: shown as {shown:?}"));
            assert!((s - w).abs() <= 0.5e-2 * w.abs().max(1.0), "{name}: shown {shown}, summary.json {w}");
        }
    }
}

#[test]
fn the_study_report_shows_every_trial_and_the_numbers_of_summary_json() {
    let dir = tempfile::tempdir().unwrap();
    let out = grove(&["study", "--out", dir.path().to_str().unwrap(), "--html"]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let page = dir.path().join("report.html");
    let bytes = std::fs::metadata(&page).unwrap().len();
    assert!(bytes <= 15 * 1024 * 1024, "report.html is {bytes} bytes");
    let html = std::fs::read_to_string(&page).unwrap();
    // Self-contained: nothing fetched from anywhere.
    for needle in ["src=\"http", "href=\"http", "<link ", "src=\"//", "@import"] {
        assert!(!html.contains(needle), "the page refers to something outside it: {needle}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap()).unwrap();
    let (dom, log) = chromium(&["--dump-dom"], &page);
    assert_no_page_errors(&dom, &log);

    // Every trial: a row of the table and a section with a filmstrip and a timeline.
    let trials = summary["trials"].as_array().unwrap();
    assert_eq!(trials.len(), 24);
    for t in trials {
        let file = t["file"].as_str().unwrap();
        let row = slice(&dom, &format!("<tr class=\"trial-row\" data-file=\"{file}\""), "</tr>");
        assert!(row.contains(&format!("data-participant=\"{}\"", t["participant"].as_str().unwrap())), "{row}");
        assert_number(row, "time_s", &t["task"]["time_s"]);
        let section = slice(
            &dom,
            &format!("<section class=\"trial\" id=\"t-{}\" data-file=\"{file}\"", file.trim_end_matches(".jsonl")),
            "</section>",
        );
        assert!(section.contains("class=\"timeline\""), "{file}: no timeline");
        assert!(section.contains("data:image/jpeg;base64,"), "{file}: no filmstrip");
        assert!(
            section.contains(&format!("grove view replays/study/{file} --at {}", t["task"]["start_tick"])),
            "{file}: no command at the task start"
        );
        // One frame per planting at least (ray-casting plants 7; manual spawns and snaps them).
        assert!(section.matches("<figure data-tick=").count() >= 7, "{file}");
    }
    // Every participant, with their two times.
    let s = &summary["summary"];
    for p in s["per_participant"].as_array().unwrap() {
        let row = slice(&dom, &format!("<tr data-participant=\"{}\"", p["participant"].as_str().unwrap()), "</tr>");
        for f in ["ray_casting_s", "manual_s", "difference_s"] {
            assert_number(row, f, &p[f]);
        }
    }
    // The paired statistics and the per-condition means.
    let overview = slice(&dom, "<section id=\"overview\"", "<section id=\"trials\"");
    for f in [
        "n",
        "mean_difference",
        "sd_difference",
        "ci95_low",
        "ci95_high",
        "t",
        "wilcoxon_w_plus",
        "wilcoxon_w_minus",
        "cohens_dz",
    ] {
        assert_number(overview, &format!("paired.{f}"), &s["paired"][f]);
    }
    for f in ["t_test_p", "wilcoxon_p"] {
        let (v, _) = field(overview, &format!("paired.{f}")).unwrap();
        let w = s["paired"][f].as_f64().unwrap();
        assert!((v - w).abs() <= 4.0 * f64::EPSILON * w, "{f}: page {v}, summary.json {w}");
    }
    for m in ["ray-casting", "manual"] {
        for f in ["mean_time_s", "sd_time_s", "mean_errors"] {
            assert_number(overview, &format!("modes.{m}.{f}"), &s["modes"][m][f]);
        }
    }
    let claim = attr_after(overview, "data-field=\"ray_casting_faster_for_all\">").unwrap_or_default();
    assert!(claim.starts_with(if s["ray_casting_faster_for_all"] == true { "yes" } else { "no" }), "{claim}");
    assert!(overview.contains("<svg"), "no ablation chart");
    assert!(overview.contains("synthetic"), "the overview must say the data are synthetic");
    // The task area of both conditions, with the scene from above and every participant's switch.
    for m in ["ray-casting", "manual"] {
        let area = slice(&dom, &format!("<section class=\"area-section\" data-condition=\"{m}\""), "</section>");
        assert!(area.contains("<image href=\"data:image/jpeg;base64,"), "{m}: no picture from above");
        assert_eq!(area.matches("class=\"pswitch\"").count(), 12, "{m}");
        assert_eq!(
            area.matches("<tr data-target=").count() + area.matches("class=\"hardest\" data-target=").count(),
            7,
            "{m}"
        );
        // The errors placed near the targets are the errors the task system counted.
        let table = slice(area, "<table class=\"targets-table\"", "</table>");
        let placed: u64 = table
            .split("<tr")
            .skip(2)
            .map(|row| {
                row.rsplit("<td class=\"num\">").next().unwrap().split('<').next().unwrap().parse::<u64>().unwrap()
            })
            .sum();
        let counted: u64 =
            trials.iter().filter(|t| t["task"]["mode"] == m).map(|t| t["task"]["errors"].as_u64().unwrap()).sum();
        assert_eq!(placed, counted, "{m}: errors on the map");
        // Targets are numbered from 1 where a person reads them (the rows, the map's labels),
        // while data-target keeps the file's index as trees.csv does (docs/reports.md).
        let numbers: Vec<String> = table
            .split("<tr")
            .skip(2)
            .map(|row| row.split("<td>").nth(1).unwrap().split('<').next().unwrap().to_string())
            .collect();
        assert_eq!(numbers, (1..=7).map(|n| n.to_string()).collect::<Vec<_>>(), "{m}: the table's target numbers");
        assert!(
            area.contains("<title>target 1: ")
                && area.contains("<title>target 7: ")
                && !area.contains("<title>target 0: "),
            "{m}: the map's targets"
        );
        assert!(table.contains("data-target=\"0\""), "{m}: data-target is the file's index");
    }
    // Who was slowest in each condition, from summary.json's trials.
    for m in ["ray-casting", "manual"] {
        let slowest = trials
            .iter()
            .filter(|t| t["task"]["mode"] == m)
            .max_by(|a, b| a["task"]["time_s"].as_f64().unwrap().total_cmp(&b["task"]["time_s"].as_f64().unwrap()))
            .unwrap();
        assert!(
            overview.contains(&format!(
                "<li data-condition=\"{m}\" data-participant=\"{}\"",
                slowest["participant"].as_str().unwrap()
            )),
            "{m}: slowest"
        );
    }

    // A screenshot of the overview, to be looked at.
    let shots = root().join("target/html-report");
    std::fs::create_dir_all(&shots).unwrap();
    let png = shots.join("overview.png");
    let _ = std::fs::remove_file(&png);
    chromium(&[&format!("--screenshot={}", png.display()), "--window-size=1280,2200"], &page);
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (1280, 2200));
    let distinct: std::collections::BTreeSet<[u8; 3]> = img.pixels().step_by(97).map(|p| p.0).collect();
    assert!(distinct.len() > 50, "the screenshot looks empty ({} colours)", distinct.len());
}

#[test]
fn a_what_if_report_shows_the_baseline_the_changed_setting_and_the_differences() {
    let dir = tempfile::tempdir().unwrap();
    let replays = dir.path().join("replays");
    std::fs::create_dir(&replays).unwrap();
    // P07's manual trial no longer completes with snap_threshold 0.2 (docs/reports.md).
    for f in ["P07-manual-7.jsonl", "P07-ray-casting-7.jsonl", "P04-manual-7.jsonl", "P04-ray-casting-7.jsonl"] {
        std::fs::copy(root().join("replays/study").join(f), replays.join(f)).unwrap();
    }
    let out_dir = dir.path().join("out");
    let out = grove(&[
        "study",
        "--replays",
        replays.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--html",
        "--set",
        "snap_threshold=0.2",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap()).unwrap();
    let (dom, log) = chromium(&["--dump-dom"], &out_dir.join("report.html"));
    assert_no_page_errors(&dom, &log);
    let w = &summary["what_if"];
    let section = slice(&dom, "<section id=\"what-if\"", "</section>");
    assert!(section.contains(w["kind"].as_str().unwrap()));
    let p = &w["parameters"][0];
    assert!(
        section.contains(&format!(
            "<td>{}</td><td>{}</td><td><strong>{}</strong></td>",
            p["name"].as_str().unwrap(),
            p["default_value"].as_str().unwrap(),
            p["new_value"].as_str().unwrap()
        )),
        "{section}"
    );
    for m in ["ray-casting", "manual"] {
        for f in ["baseline_mean_s", "what_if_mean_s", "difference_s"] {
            assert_number(section, &format!("what_if.{m}.{f}"), &w["modes"][m][f]);
        }
    }
    // The claim under the baseline and under the what-if, as summary.json has them.
    let claim = |v: &serde_json::Value| match v.as_bool() {
        Some(true) => "yes",
        Some(false) => "no",
        None => "cannot say",
    };
    let said = format!(
        "baseline: <strong>{}</strong>; under the what-if: <strong>{}</strong>",
        claim(&w["baseline"]["ray_casting_faster_for_all"]),
        claim(&summary["summary"]["ray_casting_faster_for_all"])
    );
    assert!(section.contains(&said), "{said} not in {section}");
    assert_eq!(claim(&summary["summary"]["ray_casting_faster_for_all"]), "cannot say");
    // The trial that no longer completes is named with its reason.
    for i in summary["summary"]["incomplete"].as_array().unwrap() {
        assert!(dom.contains(&format!("<li data-file=\"{}\"", i["file"].as_str().unwrap())), "{i}");
    }
}

fn study_script(seed: u64) -> Script {
    Script::new(Sim::from_scene(&Scene::builtin("study").unwrap(), seed).unwrap())
}

fn write_recording(path: &Path, participant: &str, script: Script) {
    let (sim, events) = script.into_parts();
    let end = sim.tick() + 60;
    let mut header = Header::new("study", sim.seed(), sim.dt());
    header.participant = Some(participant.to_string());
    header.synthetic = true;
    let bytes = record_events(Vec::new(), &header, &events, end, serde_json::json!({})).unwrap();
    std::fs::write(path, bytes).unwrap();
}

/// The rectangles of the first heatmap in `dom`: (x, z of the cell's corner, ticks).
fn heat_cells(dom: &str) -> Vec<(f64, f64, u64)> {
    let g = slice(dom, "<g class=\"heat\"", "</g>");
    g.split("<rect")
        .skip(1)
        .map(|r| {
            (
                attr_after(r, " x=\"").unwrap().parse().unwrap(),
                attr_after(r, " y=\"").unwrap().parse().unwrap(),
                attr_after(r, "data-n=\"").unwrap().parse().unwrap(),
            )
        })
        .collect()
}

#[test]
fn the_heatmap_of_a_ray_that_dwells_at_a_point_peaks_there() {
    let dir = tempfile::tempdir().unwrap();
    let replays = dir.path().join("replays");
    std::fs::create_dir(&replays).unwrap();
    // The ray passes over two points for a second each and dwells at a third for ten.
    let dwell = Vec3::new(2.3, 0.0, -7.4);
    let mut s = study_script(7);
    s.start_task("ray-casting-7");
    s.point_at(Vec3::new(-4.0, 0.0, -3.0)).wait(60);
    s.point_at(dwell).wait(600);
    s.point_at(Vec3::new(6.0, 0.0, -2.0)).wait(60);
    s.end_task().wait(5);
    write_recording(&replays.join("P01-dwell.jsonl"), "P01", s);
    let out_dir = dir.path().join("out");
    let out = grove(&["study", "--replays", replays.to_str().unwrap(), "--out", out_dir.to_str().unwrap(), "--html"]);
    assert!(out.status.code() == Some(0) || out.status.code() == Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    let (dom, log) = chromium(&["--dump-dom"], &out_dir.join("report.html"));
    assert_no_page_errors(&dom, &log);
    let cells = heat_cells(&dom);
    let &(x, z, n) = cells.iter().max_by_key(|c| c.2).expect("a heatmap with cells");
    // The busiest cell holds the dwell point, and about ten seconds of ticks.
    let cell = attr_after(&dom, "<g class=\"heat\" data-cell=\"").unwrap().parse::<f64>().unwrap();
    assert!(
        (x..x + cell).contains(&(dwell.x as f64)) && (z..z + cell).contains(&(dwell.z as f64)),
        "peak at ({x}, {z}), dwell point {dwell}"
    );
    assert!((590..=610).contains(&n), "{n} ticks in the peak cell");
    // The others saw the ray for about a second each.
    assert!(cells.iter().filter(|c| (c.0, c.1) != (x, z)).all(|c| c.2 <= 70), "{cells:?}");
}

#[test]
fn a_replay_page_shows_the_trial_and_where_it_diverged() {
    let dir = tempfile::tempdir().unwrap();
    let good = root().join("replays/study/P02-ray-casting-7.jsonl");
    let page = dir.path().join("P02.html");
    let out = grove(&["replay", good.to_str().unwrap(), "--html", page.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let (dom, log) = chromium(&["--dump-dom"], &page);
    assert_no_page_errors(&dom, &log);
    let json = grove(&["replay", good.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_number(&dom, "time_s", &v["task"]["time_s"]);
    assert_number(&dom, "errors", &v["task"]["errors"]);
    assert!(!dom.contains("class=\"divergence\""));

    // A copy with one controller pose moved by a millimetre, its checksums signed again.
    let text = std::fs::read_to_string(&good).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let i = (lines.len() / 2..lines.len()).find(|&k| lines[k].contains("controller_pose")).unwrap();
    let (body, _) = grove_systems::replay::split_sum(&lines[i]).unwrap();
    let grove_systems::replay::Line::Event(mut ev) =
        grove_systems::replay::decode_line(&grove_systems::replay::sign_body(&body, 0).0).unwrap()
    else {
        panic!("not an event")
    };
    if let grove_systems::input::InputEvent::ControllerPose { pose } = &mut ev.event {
        pose.position.x += 0.001;
    }
    lines[i] = grove_systems::replay::encode_line(&grove_systems::replay::Line::Event(ev));
    let lines = grove_systems::replay::rechain(&lines).unwrap();
    let bad = dir.path().join("P02-changed.jsonl");
    std::fs::write(&bad, lines.join("\n") + "\n").unwrap();
    let bad_page = dir.path().join("bad.html");
    let out = grove(&["replay", bad.to_str().unwrap(), "--html", bad_page.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    let json = grove(&["replay", bad.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let d = &v["first_divergence"];
    let (dom, log) = chromium(&["--dump-dom"], &bad_page);
    assert_no_page_errors(&dom, &log);
    let block = slice(&dom, "<div class=\"divergence\"", "</table>");
    assert_eq!(
        attr_after(block, "<strong class=\"div-tick\">").map(|s| s.split('<').next().unwrap_or_default().to_string()),
        Some(d["tick"].to_string())
    );
    for x in d["differing"].as_array().unwrap() {
        let row =
            format!("<tr><td>{}</td><td>{}</td></tr>", x["entity"].as_str().unwrap(), x["component"].as_str().unwrap());
        assert!(block.contains(&row), "{row} missing");
    }
    // Frames just before and at the divergence.
    let tick = d["tick"].as_u64().unwrap();
    assert!(dom.contains(&format!("<figure data-tick=\"{tick}\"")), "no frame at the divergence");
    assert!(dom.contains(&format!("<figure data-tick=\"{}\"", tick - 60)), "no frame before the divergence");
}

#[test]
fn bad_html_arguments_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let replays = dir.path().join("replays");
    std::fs::create_dir(&replays).unwrap();
    for f in ["P01-manual-7.jsonl", "P01-ray-casting-7.jsonl"] {
        std::fs::copy(root().join("replays/study").join(f), replays.join(f)).unwrap();
    }
    let out = grove(&[
        "study",
        "--replays",
        replays.to_str().unwrap(),
        "--out",
        dir.path().to_str().unwrap(),
        "--html",
        "--html-trials",
        "P99",
    ]);
    assert_one_line_error(&out, 2, "P99");
    assert!(!dir.path().join("report.html").exists());
    let page = dir.path().join("p.html");
    std::fs::write(&page, "mine").unwrap();
    let out = grove(&["replay", "replays/study/P01-manual-7.jsonl", "--html", page.to_str().unwrap()]);
    assert_one_line_error(&out, 2, "already exists");
    assert_eq!(std::fs::read_to_string(&page).unwrap(), "mine");
}

/// A copy of a recording with one controller pose (the first in its second half) moved `by`
/// metres along X, its checksums signed again.
fn with_pose_moved(from: &Path, to: &Path, by: f32) {
    use grove_systems::replay::{Line, decode_line, encode_line, rechain, sign_body, split_sum};
    let text = std::fs::read_to_string(from).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let i = (lines.len() / 2..lines.len()).find(|&k| lines[k].contains("controller_pose")).unwrap();
    let (body, _) = split_sum(&lines[i]).unwrap();
    let Line::Event(mut ev) = decode_line(&sign_body(&body, 0).0).unwrap() else { panic!("not an event") };
    let grove_systems::input::InputEvent::ControllerPose { pose } = &mut ev.event else { panic!("not a pose") };
    pose.position.x += by;
    lines[i] = encode_line(&Line::Event(ev));
    std::fs::write(to, rechain(&lines).unwrap().join("\n") + "\n").unwrap();
}

#[test]
fn a_divergence_in_the_resources_names_the_field() {
    // The ray moved by 0.1 m for a moment: the controller itself is posed again before the next
    // checkpoint, but the task has measured a longer path of the ray. The report names the
    // resources' field, `task`, in --json and in --html, not the resources as a whole.
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("P02-moved.jsonl");
    with_pose_moved(&root().join("replays/study/P02-ray-casting-7.jsonl"), &bad, 0.1);
    let json = grove(&["replay", bad.to_str().unwrap(), "--json"]);
    assert_eq!(json.status.code(), Some(1), "{}", String::from_utf8_lossy(&json.stderr));
    let v: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let differing = v["first_divergence"]["differing"].as_array().unwrap().clone();
    let fields: Vec<&str> =
        differing.iter().filter(|x| x["entity"] == "resources").map(|x| x["component"].as_str().unwrap()).collect();
    assert!(fields.contains(&"task"), "{differing:?}");
    assert!(
        fields.iter().all(|f| grove_systems::resource_hash::FIELDS.contains(f)),
        "only fields are named: {differing:?}"
    );

    let page = dir.path().join("moved.html");
    let out = grove(&["replay", bad.to_str().unwrap(), "--html", page.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    let html = std::fs::read_to_string(&page).unwrap();
    let block = slice(&html, "<div class=\"divergence\"", "</table>");
    for f in &fields {
        assert!(
            block.contains(&format!("<tr><td>resources</td><td>{f}</td></tr>")),
            "resources {f} missing from the page"
        );
    }
    assert!(!block.contains("<td>resources</td><td>resources</td>"), "the resources named as a whole");
}
