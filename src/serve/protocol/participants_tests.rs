//! The participants' unit tests: a participant resuming at their step, a line cut short by a
//! crash dropped, a folder keeping its protocol.

use super::*;

/// A folder whose sessions finish no step and use these ids.
struct NoneEnded(Vec<&'static str>);
impl TaskSessions for NoneEnded {
    fn finishing(&self, _: &str, _: &str, _: &str) -> Result<String, Vec<(String, &'static str)>> {
        Err(Vec::new())
    }
    fn ids_in_use(&self) -> Vec<(String, String)> {
        self.0.iter().map(|i| (i.to_string(), format!("{i}-manual-7-1.jsonl"))).collect()
    }
}

fn shipped() -> Loaded {
    crate::protocol::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/protocols/tree-planting.ron")).expect("the shipped protocol")
}

#[test]
fn a_participant_resumes_at_their_step_and_a_line_cut_short_by_a_crash_is_dropped() {
    let dir = tempfile::tempdir().unwrap();
    let (ps, _) = Participants::open(shipped(), dir.path()).unwrap();
    let (first, new) = ps.join(None, &NoneEnded(vec![])).unwrap();
    assert!(new);
    assert_eq!(first["participant"], "P01");
    ps.next("P01", 1, &NoneEnded(vec![])).unwrap();
    ps.next("P01", 2, &NoneEnded(vec![])).unwrap();
    let refused = crate::serve::http::refusal::Refusal::from(ps.next("P01", 3, &NoneEnded(vec![])).unwrap_err());
    assert_eq!(refused.status, 409);
    drop(ps);
    // A crash in the middle of a write leaves part of a line: it was never acknowledged.
    let file = dir.path().join("P01.answers.jsonl");
    let whole = std::fs::read_to_string(&file).unwrap();
    std::fs::write(&file, format!("{whole}{{\"line\":\"step\",\"st")).unwrap();
    let (again, notes) = Participants::open(shipped(), dir.path()).unwrap();
    assert_eq!(notes, vec!["participant P01 resumes at step 3 of 8".to_string()]);
    assert_eq!(again.get("P01").unwrap()["step"], 3);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), whole);
    let (second, new) = again.join(None, &NoneEnded(vec![])).unwrap();
    assert!(new);
    assert_eq!(second["order"], serde_json::json!(["manual", "ray-casting"]));
}

#[test]
fn a_folder_keeps_its_protocol_and_refuses_another() {
    let dir = tempfile::tempdir().unwrap();
    let loaded = shipped();
    Participants::open(loaded.clone(), dir.path()).unwrap();
    assert_eq!(std::fs::read_to_string(dir.path().join(PROTOCOL_FILE)).unwrap(), loaded.text);
    let mut other = loaded;
    other.text.push_str("\n// changed\n");
    let e = Participants::open(other, dir.path()).err().expect("refused");
    assert!(e.to_string().contains("holds another protocol"), "{e}");
}
