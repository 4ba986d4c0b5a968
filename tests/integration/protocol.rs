//! Bad protocol files (`docs/protocol.md`) are refused by `grove serve --protocol` before it
//! listens: exit 2 and one line on stderr naming the file and the place.

use std::process::Command;

use crate::common::root;

fn shipped() -> String {
    std::fs::read_to_string(root().join("assets/protocols/tree-planting.ron")).unwrap()
}

/// Runs `grove serve --protocol` on `text` (written to a file) and returns its stderr, asserting
/// exit 2 and one line.
fn refused(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("bad.ron");
    std::fs::write(&file, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_grove"))
        .args(["serve", "--port", "0", "--out"])
        .arg(dir.path().join("out"))
        .arg("--protocol")
        .arg(&file)
        .current_dir(root())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(2), "stderr: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(err.contains("bad.ron"), "names the file: {err}");
    assert!(!dir.path().join("out").exists(), "nothing written for a refused protocol");
    err
}

fn with(from: &str, to: &str) -> String {
    let text = shipped();
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

#[test]
fn an_unknown_item_type_is_refused_with_its_line_and_column() {
    let text = with("kind: YesNo", "kind: Slider(min: 0, max: 1)");
    let line = text.lines().position(|l| l.contains("Slider")).unwrap() + 1;
    let err = refused(&text);
    assert!(err.contains(&format!("bad.ron:{line}:")), "{err}");
    assert!(err.contains("Slider"), "{err}");
}

#[test]
fn a_scale_without_anchors_is_refused_naming_its_item() {
    let err = refused(&with("kind: Rating(anchors: [\"Not at all\", \"Very well\"])", "kind: Rating()"));
    assert!(
        err.contains("instrument 'tree-planting', item 1 'guidance'") && err.contains("needs its anchors"),
        "{err}"
    );
    let err = refused(&shipped().replace(
        "kind: Rating(anchors: [\"Not realistic at all\", \"Very realistic\"])",
        "kind: Scale(min: 0, max: 10, anchors: [\"low\"])",
    ));
    assert!(err.contains("item 3 'realism_billboard'") && err.contains("a scale needs its anchors"), "{err}");
}

#[test]
fn conditions_a_latin_square_cannot_balance_are_refused() {
    let err = refused(&with("participants: 12", "participants: 7"));
    assert!(
        err.contains("participants: a balanced Latin square of 2 conditions has 2 rows")
            && err.contains("the protocol has 7"),
        "{err}"
    );
    let three = with(
        "Condition(name: \"manual\", task: \"manual-7\"),",
        "Condition(name: \"manual\", task: \"manual-7\"),\n        Condition(name: \"again\", task: \"manual-7\"),",
    );
    let err = refused(&three.replacen("participants: 12", "participants: 8", 1));
    assert!(err.contains("3 conditions has 6 rows") && err.contains("multiple of 6"), "{err}");
}

#[test]
fn an_empty_block_is_refused() {
    let text = shipped();
    let start = text.find("text: \"You will plant").unwrap();
    let end = start + text[start..].find("\",\n").unwrap() + 2;
    let err = refused(&format!("{}{}", &text[..start], &text[end..]));
    assert!(err.contains("block 1 'instructions': an empty block"), "{err}");
    let err = refused(
        &with("blocks: [", "blocks: [\n        Questionnaire(name: \"nothing\", instrument: \"empty\"),").replacen(
            "instruments: [",
            "instruments: [\n        Instrument(id: \"empty\", title: \"Nothing\", items: []),",
            1,
        ),
    );
    assert!(err.contains("instrument 'empty': an empty questionnaire"), "{err}");
}

#[test]
fn a_task_that_does_not_exist_is_refused() {
    let err = refused(&with("task: \"manual-7\"", "task: \"manual-9\""));
    assert!(err.contains("condition 2 'manual': task 'manual-9' does not exist"), "{err}");
    let err = refused(&with(
        "Questionnaire(name: \"usability\", instrument: \"sus\")",
        "Questionnaire(name: \"usability\", instrument: \"umux\")",
    ));
    assert!(err.contains("block 5 'usability': questionnaire 'umux' does not exist"), "{err}");
}

#[test]
fn a_folder_that_holds_another_protocol_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("protocol.ron"), with("participants: 12", "participants: 24")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_grove"))
        .args(["serve", "--port", "0", "--protocol", "assets/protocols/tree-planting.ron", "--out"])
        .arg(dir.path())
        .current_dir(root())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("holds another protocol") && err.trim_end().lines().count() == 1, "{err}");
}

#[test]
fn the_protocol_pages_and_requests_need_the_token_and_a_server_without_a_protocol_says_so() {
    use crate::serve_fixture::{Server, request};
    let dir = tempfile::tempdir().unwrap();
    let server = Server::start(
        &dir.path().join("out"),
        0,
        &["--require-token", "--protocol", "assets/protocols/tree-planting.ron"],
    );
    let token = server.url.split("token=").nth(1).expect("a token in the URL").to_string();
    let bearer = format!("Bearer {token}");
    for path in ["/dashboard", "/protocol", "/api/dashboard", "/api/protocol/participants/P01"] {
        assert_eq!(request(&server.addr, "GET", path, &[], b"").status, 401, "{path}");
    }
    let joined = request(&server.addr, "POST", "/api/protocol/participants", &[("Authorization", &bearer)], b"{}");
    assert_eq!(joined.status, 201, "{}", joined.body);
    assert_eq!(joined.json["participant"], "P01");
    let page = request(&server.addr, "GET", "/dashboard", &[("Authorization", &bearer)], b"");
    assert_eq!(page.status, 200);
    assert!(page.body.contains("<table id=\"sessions\">"));
    let live = request(&server.addr, "GET", "/api/dashboard", &[("Authorization", &bearer)], b"");
    assert_eq!(live.json["participants"][0]["participant"], "P01");
    let plain = Server::start(&dir.path().join("plain"), 0, &[]);
    let none = request(&plain.addr, "GET", "/api/protocol", &[], b"");
    assert_eq!(none.status, 404);
    assert!(none.json["error"].as_str().unwrap().contains("runs no protocol"), "{}", none.body);
}
