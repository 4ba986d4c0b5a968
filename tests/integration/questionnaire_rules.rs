//! The questionnaires' rules, tested once, here: what each kind of item takes is stated once
//! (`src/protocol/answer.rs`), the options the pages offer are worked out from it
//! (`src/protocol/form.rs`), and the server alone checks an answer against it. Fed the answers
//! the pages send (`tests/fixtures/questionnaires/answers.json`, written by
//! `web/page/test/answers.test.mjs` from the headset's panel logic and the form page's, for the
//! items as the server describes them, `forms.json`) and answers just outside what each item
//! takes.

use std::collections::BTreeMap;

use grove::protocol::answer::{check, takes, Takes};
use grove::protocol::form::FormItem;
use grove::protocol::{Instrument, ItemKind, StepKind};
use serde_json::{json, Value};

use crate::common::{root, scratch};
use crate::serve_fixture::{request, Server};

/// The protocols whose instruments the fixtures hold: the shipped one and every kind of item.
const PROTOCOLS: [&str; 2] = ["assets/protocols/tree-planting.ron", "tests/fixtures/questionnaires/every-kind.ron"];

fn fixture(name: &str) -> std::path::PathBuf {
    root().join("tests/fixtures/questionnaires").join(name)
}

/// Every instrument the protocols give, by id.
fn instruments() -> BTreeMap<String, Instrument> {
    let mut out = BTreeMap::new();
    for file in PROTOCOLS {
        let loaded = grove::protocol::load(&root().join(file)).unwrap_or_else(|e| panic!("{e}"));
        for step in loaded.steps(&loaded.order(0)) {
            if let StepKind::Questionnaire { instrument, .. } = step.kind {
                out.insert(instrument.clone(), loaded.instrument(&instrument).expect("an instrument the protocol gives"));
            }
        }
    }
    out
}

#[test]
fn the_server_describes_each_instrument_as_the_fixture_the_pages_are_tested_on() {
    let mut described = serde_json::Map::new();
    for file in PROTOCOLS {
        let dir = scratch("questionnaire-forms");
        let server = Server::start(&dir, 0, &["--protocol", file]);
        let joined = request(&server.addr, "POST", "/api/protocol/participants", &[], b"{}");
        assert_eq!(joined.status, 201, "{}", joined.body);
        for step in joined.json["steps"].as_array().unwrap() {
            if step["kind"] == "questionnaire" {
                described.insert(step["instrument"]["id"].as_str().unwrap().to_string(), step["instrument"].clone());
            }
        }
    }
    let ids: Vec<&String> = described.keys().collect();
    assert_eq!(ids, ["every-kind", "nasa-tlx", "sus", "tree-planting"]);
    let text = serde_json::to_string_pretty(&Value::Object(described)).unwrap() + "\n";
    if std::env::var_os("GROVE_WRITE_FIXTURES").is_some() {
        std::fs::write(fixture("forms.json"), &text).unwrap();
    }
    assert_eq!(std::fs::read_to_string(fixture("forms.json")).unwrap(), text, "the server describes the instruments otherwise: write forms.json again (GROVE_WRITE_FIXTURES=1), then answers.json (web/page/test/answers.test.mjs)");
}

#[test]
fn every_answer_the_headset_and_the_form_page_send_fits_its_item() {
    let all = instruments();
    let sent: Vec<Value> = serde_json::from_str(&std::fs::read_to_string(fixture("answers.json")).unwrap()).unwrap();
    let mut answered: BTreeMap<(String, String, String), usize> = BTreeMap::new();
    for body in &sent {
        let (page, id) = (body["page"].as_str().unwrap(), body["instrument"].as_str().unwrap());
        let ins = &all[id];
        for (item_id, answer) in body["answers"].as_object().unwrap() {
            let item = ins.items.iter().find(|i| &i.id == item_id).unwrap_or_else(|| panic!("{page} sends {id}/{item_id}, which is no item"));
            check(item, answer).unwrap_or_else(|e| panic!("{page}, participant {}: {e}", body["participant"]));
            *answered.entry((page.replace("-typed", ""), id.to_string(), item_id.clone())).or_default() += 1;
        }
    }
    // Both pages answered every item of every instrument, and every option of it was sent.
    for page in ["headset", "form"] {
        for (id, ins) in &all {
            for item in &ins.items {
                assert!(answered.contains_key(&(page.to_string(), id.clone(), item.id.clone())), "{page} never answers {id}/{}", item.id);
                if let Takes::Whole { .. } | Takes::One(_) = takes(&item.kind) {
                    for o in FormItem::new(item).options {
                        let sent_it = sent.iter().any(|b| b["page"] == page && b["instrument"] == id.as_str() && b["answers"][&item.id] == o.value);
                        assert!(sent_it, "{page} never sends {} for {id}/{}", o.value, item.id);
                    }
                }
            }
        }
    }
}

/// Answers just outside what `kind` takes.
fn outside(kind: &ItemKind) -> Vec<Value> {
    let mut bad = vec![Value::Null, json!({})];
    match takes(kind) {
        Takes::Whole { lo, hi, step } => {
            bad.extend([json!(lo - 1), json!(hi + 1), json!(lo as f64 + 0.5), json!(lo.to_string()), json!(true), json!([lo])]);
            if step > 1 {
                bad.push(json!(lo + 1));
            }
        }
        Takes::One(choices) => bad.extend([json!("not one of them"), json!(choices[0].to_uppercase() + "!"), json!([choices[0]]), json!(0)]),
        Takes::Several(choices) => bad.extend([json!(choices[0]), json!([choices[0], choices[0]]), json!(["not one of them"]), json!([1])]),
        Takes::Text { max_chars } => bad.extend([json!("é".repeat(max_chars + 1)), json!(7), json!(["a"])]),
        Takes::YesNo => bad.extend([json!("yes"), json!(1), json!([true])]),
    }
    bad
}

#[test]
fn an_item_takes_every_option_the_pages_offer_and_nothing_outside_them() {
    for (id, ins) in instruments() {
        for item in &ins.items {
            let form = FormItem::new(item);
            // Each option the pages offer, as they send it (a multiple choice's in a list).
            let several = matches!(takes(&item.kind), Takes::Several(_));
            let mut good: Vec<Value> = form.options.iter().map(|o| if several { json!([o.value]) } else { o.value.clone() }).collect();
            match takes(&item.kind) {
                Takes::Several(choices) => good.extend([json!([]), json!(choices), json!([choices.last().unwrap()])]),
                Takes::Text { max_chars } => {
                    assert_eq!(form.max_chars, Some(max_chars), "{id}/{}: the pages are told the limit", item.id);
                    good.extend([json!(""), json!("é".repeat(max_chars))]);
                }
                _ => assert!(!good.is_empty(), "{id}/{}", item.id),
            }
            for v in &good {
                check(item, v).unwrap_or_else(|e| panic!("{id}/{}: an answer the pages offer is refused: {e}", item.id));
            }
            for v in outside(&item.kind) {
                let e = check(item, &v).expect_err(&format!("{id}/{}: {v} is taken", item.id));
                assert!(e.reason.contains(&format!("item '{}'", item.id)) && !e.reason.contains('\n'), "one line naming the item: {e}");
            }
        }
    }
}
