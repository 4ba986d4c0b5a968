//! `grove test --trace DIR`, and the trace of a failed scenario under `--keep DIR`
//! (docs/scenarios.md): one self-contained HTML page per scenario, loaded here in headless
//! Chromium (Debian's `chromium`, network off). The DOM after the page's script ran has a before
//! and an after frame, from the head and from above, for every step; the failing step, and only
//! it, is highlighted with its message; a step that changed the world has two different frames,
//! a step that ran no tick the same one; the page loads nothing from the network.

use crate::common;

use common::{chromium, grove};

/// The value of `attr="…"` in `tag`.
fn attr<'a>(tag: &'a str, attr: &str) -> Option<&'a str> {
    let key = format!(" {attr}=\"");
    let i = tag.find(&key)? + key.len();
    Some(&tag[i..i + tag[i..].find('"')?])
}

/// The opening tags of `name` elements in `html` whose class list holds `class`.
fn tags<'a>(html: &'a str, name: &str, class: &str) -> Vec<&'a str> {
    let open = format!("<{name} ");
    let mut out = Vec::new();
    let mut rest = html;
    while let Some(i) = rest.find(&open) {
        let tag = &rest[i..i + rest[i..].find('>').unwrap_or(rest.len() - i)];
        if attr(tag, "class").is_some_and(|c| c.split_whitespace().any(|x| x == class)) {
            out.push(tag);
        }
        rest = &rest[i + open.len()..];
    }
    out
}

/// Each `<section class="step …">` of the page, with its text up to the next section.
fn sections(dom: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let starts: Vec<usize> = dom.match_indices("<section class=\"").map(|(i, _)| i).collect();
    for (k, &i) in starts.iter().enumerate() {
        let end = starts.get(k + 1).copied().unwrap_or(dom.len());
        if dom[i..].starts_with("<section class=\"step") {
            out.push(&dom[i..end]);
        }
    }
    out
}

/// The frame (data URI) of each side and view in a step's section.
fn frames(section: &str) -> [(String, String); 2] {
    let side = |name: &str| {
        let i =
            section.find(&format!("<figure class=\"{name}\"")).unwrap_or_else(|| panic!("a {name} figure: {section}"));
        let fig = &section[i..i + section[i..].find("</figure>").unwrap()];
        let head = tags(fig, "img", "head").first().and_then(|t| attr(t, "src")).unwrap_or_default().to_string();
        let top = tags(fig, "image", "top-frame").first().and_then(|t| attr(t, "href")).unwrap_or_default().to_string();
        (head, top)
    };
    [side("before"), side("after")]
}

const FAILING: &str = r#"// Plants a birch, names it, then plants a conifer behind a broadleaf on the way to it.
Scenario(
    scene: "study",
    seed: 1,
    steps: [
        Plant(model: "birch-mesh", at: Point(2.0, 0.0, -3.0)),
        Name(name: "birch", tree: Last),
        Plant(model: "broadleaf-mesh", at: Point(0.1, 0.0, 0.6)),
        Plant(model: "conifer-billboard", at: Point(0.25, 0.0, -5.3)),
        Wait(10),
    ],
    expect: [TreeCount(5)],
)
"#;

#[test]
fn the_trace_of_a_failed_scenario_shows_each_step_before_and_after_and_highlights_the_failure() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("blocked.ron");
    std::fs::write(&file, FAILING).unwrap();
    let keep = dir.path().join("kept");
    let out = grove(&["test", "--keep", &keep.display().to_string(), &file.display().to_string()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    let page = keep.join("blocked.html");
    assert!(stdout.contains(&format!("; trace: {}", page.display())), "names the trace: {stdout}");
    assert!(stdout.contains("step 4 Plant(model: \"conifer-billboard\", at: Point(0.25, 0.0, -5.3)): the ray meets broadleaf-mesh (planted 2nd)"), "{stdout}");
    // The trace and the recording, nothing half-written.
    let mut names: Vec<String> =
        std::fs::read_dir(&keep).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, ["blocked.html", "blocked.jsonl"]);
    let html = std::fs::read_to_string(&page).unwrap();
    for bad in ["src=\"http", "href=\"http", "url(http", "<link", "@import"] {
        assert!(!html.contains(bad), "the page loads nothing from outside ({bad})");
    }

    let (dom, log) = chromium(&["--dump-dom"], &page);
    assert!(dom.contains("data-ready=\"1\""), "the page's script ran to its end");
    assert!(!dom.contains("data-errors="), "the page caught no error");
    assert!(!log.lines().any(|l| l.contains(":CONSOLE")), "the page logged nothing");
    let steps = sections(&dom);
    assert_eq!(steps.len(), 4, "the four steps that ran, each with a section");
    for (i, s) in steps.iter().enumerate() {
        assert!(s.contains(&format!("data-step=\"{}\"", i + 1)), "{s}");
        for (side, (head, top)) in ["before", "after"].iter().zip(frames(s)) {
            assert!(
                head.starts_with("data:image/jpeg;base64,") && head.len() > 1000,
                "step {}: a {side} frame from the head",
                i + 1
            );
            assert!(
                top.starts_with("data:image/jpeg;base64,") && top.len() > 1000,
                "step {}: a {side} frame from above",
                i + 1
            );
        }
        assert!(s.contains("grove view ") && s.contains(" --at "), "step {}: the command that opens it", i + 1);
    }
    // Only the failing step is highlighted, with its message, in the list too.
    let failed: Vec<usize> = steps
        .iter()
        .enumerate()
        .filter(|(_, s)| s.starts_with("<section class=\"step failed\""))
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(failed, [4]);
    assert!(
        steps[3].contains("class=\"message\"") && steps[3].contains("the ray meets broadleaf-mesh (planted 2nd)"),
        "{}",
        steps[3]
    );
    assert_eq!(tags(&dom, "li", "failed").len(), 1);
    // What each step did.
    assert!(steps[0].contains("planted birch-mesh (planted 1st)"), "{}", steps[0]);
    assert!(steps[1].contains("did: nothing"), "{}", steps[1]);
    assert!(steps[3].contains("selected broadleaf-mesh (planted 2nd)"), "{}", steps[3]);
    // Planting changed the world: its frames differ, from the head and from above. Naming a
    // tree ran no tick: before and after are the same frame.
    let [(h0, t0), (h1, t1)] = frames(steps[0]);
    assert!(h0 != h1 && t0 != t1, "the planting step's frames differ");
    let [(h0, t0), (h1, t1)] = frames(steps[1]);
    assert!(h0 == h1 && t0 == t1, "the naming step's frames are the same");
    // The ray, the point it meets and the selection are drawn on the view from above.
    let after = &steps[3][steps[3].find("<figure class=\"after\"").unwrap()..];
    assert!(
        after.contains("class=\"ray\"") && after.contains("class=\"hit\"") && after.contains("class=\"selection\""),
        "{after}"
    );
}

#[test]
fn trace_writes_every_scenario_with_its_recording() {
    let dir = tempfile::tempdir().unwrap();
    let traces = dir.path().join("traces");
    let out = grove(&["test", "--trace", &traces.display().to_string(), "tests/scenarios/plant-two.ron"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    let page = traces.join("plant-two.html");
    assert!(stdout.contains(&format!("trace: {}", page.display())), "{stdout}");
    let (dom, _) = chromium(&["--dump-dom"], &page);
    assert!(dom.contains("class=\"verdict pass\""), "a passing scenario's trace says so");
    assert!(
        tags(&dom, "li", "failed").is_empty() && !dom.contains("section class=\"step failed\""),
        "nothing is highlighted"
    );
    let recording = traces.join("plant-two.jsonl");
    assert!(dom.contains(&format!("grove view {} --at 0", recording.display())), "the commands open its recording");
    let replayed = grove(&["replay", &recording.display().to_string()]);
    assert_eq!(replayed.status.code(), Some(0), "the recording replays: {}", String::from_utf8_lossy(&replayed.stderr));
}
