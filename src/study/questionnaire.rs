//! The questionnaires of a folder that `grove serve --protocol` wrote (`docs/protocol.md`):
//! the protocol it kept (`protocol.ron`) and each participant's answers
//! (`<id>.answers.jsonl`), as reports: the long table (one answer a row), the wide one (one
//! participant a row), the scores of the scored instruments (SUS, raw TLX) and the paired
//! comparisons the protocol names. A later answer to the same item of the same step replaces
//! the earlier one.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;
use serde_json::Value;

use crate::protocol::{self, Block, Instrument, Loaded, Scoring};

use super::StudyError;
use super::stats::{PairedStats, paired};

/// The suffix of a participant's answers file.
pub const ANSWERS_SUFFIX: &str = ".answers.jsonl";

/// One answer.
#[derive(Clone, Debug, Serialize)]
pub struct Answer {
    /// The participant.
    pub participant: String,
    /// The instrument's id.
    pub instrument: String,
    /// The condition it was about (a questionnaire after a task), if any.
    pub condition: Option<String>,
    /// The item's id.
    pub item: String,
    /// The answer as given.
    pub answer: Value,
    /// When it was given (UTC, RFC 3339).
    pub time: String,
    /// The step of the session (1-based).
    pub step: u64,
}

/// One score.
#[derive(Clone, Debug, Serialize)]
pub struct Score {
    /// The participant.
    pub participant: String,
    /// The instrument's id.
    pub instrument: String,
    /// The condition, if the instrument followed a task.
    pub condition: Option<String>,
    /// `sus` (0–100) or `raw-tlx` (0–100).
    pub scoring: String,
    /// The score.
    pub score: f64,
}

/// A paired comparison of two items over the participants who answered both.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// The first item, `instrument/item`.
    pub a: String,
    /// The second item.
    pub b: String,
    /// Participants with both answers.
    pub n: usize,
    /// Participants whose b is above their a.
    pub b_higher: usize,
    /// Participants who gave both the same.
    pub same: usize,
    /// Participants whose a is above their b.
    pub a_higher: usize,
    /// The statistics of b − a (none for fewer than two pairs).
    pub stats: Option<PairedStats>,
}

/// A folder's questionnaires.
pub struct Questionnaires {
    /// The protocol the server kept.
    pub loaded: Loaded,
    /// Every answer, by participant, then step, then the item's place in its instrument.
    pub answers: Vec<Answer>,
    /// The scores.
    pub scores: Vec<Score>,
    /// The comparisons.
    pub comparisons: Vec<Comparison>,
}

/// An answer as a CSV cell: numbers as written, yes/no, choices joined by `;`, text as given.
pub fn cell(v: &Value) -> String {
    match v {
        Value::Bool(b) => if *b { "yes" } else { "no" }.into(),
        Value::String(s) => s.clone(),
        Value::Array(a) => a.iter().map(cell).collect::<Vec<_>>().join(";"),
        Value::Null => String::new(),
        other => other.to_string(),
    }
}

/// The questionnaire columns of the wide table, in the protocol's order: `instrument.item`, or
/// `instrument.condition.item` for one answered after each task; then each score.
pub fn columns(loaded: &Loaded) -> Vec<(String, Option<String>, String)> {
    let mut cols = Vec::new();
    let mut add = |ins: &Instrument, cond: Option<&str>| {
        for i in &ins.items {
            cols.push((ins.id.clone(), cond.map(str::to_string), i.id.clone()));
        }
    };
    for b in &loaded.protocol.blocks {
        match b {
            Block::Questionnaire { instrument, .. } => {
                if let Some(ins) = loaded.instrument(instrument) {
                    add(&ins, None);
                }
            }
            Block::Tasks { after, .. } => {
                for c in &loaded.protocol.conditions {
                    for a in after {
                        if let Some(ins) = loaded.instrument(a) {
                            add(&ins, Some(&c.name));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    cols
}

fn column_name(ins: &str, cond: Option<&str>, item: &str) -> String {
    match cond {
        Some(c) => format!("{ins}.{c}.{item}"),
        None => format!("{ins}.{item}"),
    }
}

/// Reads a folder's questionnaires: `None` when it holds no `protocol.ron`.
pub fn load(dir: &Path) -> Result<Option<Questionnaires>, StudyError> {
    let kept = dir.join("protocol.ron");
    if !kept.exists() {
        return Ok(None);
    }
    let bad = |path: &Path, reason: String| StudyError::Answers { path: path.display().to_string(), reason };
    let loaded = protocol::load(&kept).map_err(|e| bad(&kept, e.to_string()))?;
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .map_err(|source| StudyError::Folder { path: dir.to_path_buf(), source })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.ends_with(ANSWERS_SUFFIX)))
        .collect();
    files.sort();
    let mut answers = Vec::new();
    for f in &files {
        let text = grove_systems::files::read_text(f, grove_systems::files::Kind::Recording)
            .map_err(|e| bad(f, e.reason()))?;
        let mut latest: BTreeMap<(u64, String), Answer> = BTreeMap::new();
        let mut participant = None;
        for (n, line) in text.lines().enumerate() {
            let v: Value = serde_json::from_str(line).map_err(|e| bad(f, format!("line {}: {e}", n + 1)))?;
            match v["line"].as_str() {
                Some("participant") => participant = v["participant"].as_str().map(str::to_string),
                Some("answer") => {
                    let p = participant
                        .clone()
                        .ok_or_else(|| bad(f, format!("line {}: an answer before the participant line", n + 1)))?;
                    let a = Answer {
                        participant: p,
                        instrument: v["instrument"].as_str().unwrap_or_default().into(),
                        condition: v["condition"].as_str().map(str::to_string),
                        item: v["item"].as_str().unwrap_or_default().into(),
                        answer: v["answer"].clone(),
                        time: v["time"].as_str().unwrap_or_default().into(),
                        step: v["step"].as_u64().unwrap_or(0),
                    };
                    latest.insert((a.step, a.item.clone()), a);
                }
                _ => {}
            }
        }
        let mut mine: Vec<Answer> = latest.into_values().collect();
        let place = |a: &Answer| {
            loaded
                .instrument(&a.instrument)
                .and_then(|i| i.items.iter().position(|x| x.id == a.item))
                .unwrap_or(usize::MAX)
        };
        mine.sort_by_key(|a| (a.step, place(a)));
        answers.extend(mine);
    }
    answers.sort_by(|a, b| a.participant.cmp(&b.participant).then(a.step.cmp(&b.step)));
    let scores = scores(&loaded, &answers);
    let comparisons = compare(&loaded, &answers);
    Ok(Some(Questionnaires { loaded, answers, scores, comparisons }))
}

fn scores(loaded: &Loaded, answers: &[Answer]) -> Vec<Score> {
    let mut groups: BTreeMap<(String, String, Option<String>), Vec<&Answer>> = BTreeMap::new();
    for a in answers {
        groups.entry((a.participant.clone(), a.instrument.clone(), a.condition.clone())).or_default().push(a);
    }
    let mut out = Vec::new();
    for ((participant, instrument, condition), given) in groups {
        let Some(ins) = loaded.instrument(&instrument) else { continue };
        let values: Vec<Option<i64>> =
            ins.items.iter().map(|i| given.iter().find(|a| a.item == i.id).and_then(|a| a.answer.as_i64())).collect();
        if let Some(score) = protocol::score::score(&ins, &values) {
            let scoring = match ins.scoring {
                Scoring::Sus => "sus",
                Scoring::RawTlx => "raw-tlx",
                Scoring::None => continue,
            };
            out.push(Score { participant, instrument, condition, scoring: scoring.into(), score });
        }
    }
    out
}

fn compare(loaded: &Loaded, answers: &[Answer]) -> Vec<Comparison> {
    let value = |p: &str, path: &str| -> Option<f64> {
        let (ins, item) = path.split_once('/')?;
        answers
            .iter()
            .find(|a| a.participant == p && a.instrument == ins && a.item == item && a.condition.is_none())
            .and_then(|a| a.answer.as_f64())
    };
    let mut people: Vec<&str> = answers.iter().map(|a| a.participant.as_str()).collect();
    people.dedup();
    loaded
        .protocol
        .compare
        .iter()
        .map(|c| {
            let diffs: Vec<f64> = people.iter().filter_map(|p| Some(value(p, &c.b)? - value(p, &c.a)?)).collect();
            Comparison {
                a: c.a.clone(),
                b: c.b.clone(),
                n: diffs.len(),
                b_higher: diffs.iter().filter(|d| **d > 0.0).count(),
                same: diffs.iter().filter(|d| **d == 0.0).count(),
                a_higher: diffs.iter().filter(|d| **d < 0.0).count(),
                stats: paired(&diffs, &format!("{} − {}", c.b, c.a), "points"),
            }
        })
        .collect()
}

/// The long table's columns.
pub const LONG_COLUMNS: &[&str] = &["participant", "instrument", "condition", "item", "answer", "time", "step"];
/// The scores table's columns.
pub const SCORE_COLUMNS: &[&str] = &["participant", "instrument", "condition", "scoring", "score"];

/// Writes `questionnaire_long.csv`, `questionnaire_wide.csv` and `questionnaire_scores.csv`.
pub fn write(out: &Path, q: &Questionnaires) -> Result<(), StudyError> {
    use super::csv_out::with_writer;
    use crate::atomic_write::via_temp;
    via_temp(&out.join("questionnaire_long.csv"), |tmp| {
        with_writer(tmp, |w| {
            w.write_record(LONG_COLUMNS)?;
            for a in &q.answers {
                w.write_record([
                    a.participant.clone(),
                    a.instrument.clone(),
                    a.condition.clone().unwrap_or_default(),
                    a.item.clone(),
                    cell(&a.answer),
                    a.time.clone(),
                    a.step.to_string(),
                ])?;
            }
            Ok(())
        })
    })?;
    let cols = columns(&q.loaded);
    let mut score_cols: Vec<(String, Option<String>)> =
        q.scores.iter().map(|s| (s.instrument.clone(), s.condition.clone())).collect();
    score_cols.sort();
    score_cols.dedup();
    via_temp(&out.join("questionnaire_wide.csv"), |tmp| {
        with_writer(tmp, |w| {
            let mut head = vec!["participant".to_string()];
            head.extend(cols.iter().map(|(i, c, it)| column_name(i, c.as_deref(), it)));
            head.extend(score_cols.iter().map(|(i, c)| column_name(i, c.as_deref(), "score")));
            w.write_record(&head)?;
            let mut people: Vec<&str> = q.answers.iter().map(|a| a.participant.as_str()).collect();
            people.dedup();
            for p in people {
                let mut row = vec![p.to_string()];
                for (i, c, it) in &cols {
                    row.push(
                        q.answers
                            .iter()
                            .find(|a| a.participant == p && &a.instrument == i && &a.condition == c && &a.item == it)
                            .map(|a| cell(&a.answer))
                            .unwrap_or_default(),
                    );
                }
                for (i, c) in &score_cols {
                    row.push(
                        q.scores
                            .iter()
                            .find(|s| s.participant == p && &s.instrument == i && &s.condition == c)
                            .map(|s| s.score.to_string())
                            .unwrap_or_default(),
                    );
                }
                w.write_record(&row)?;
            }
            Ok(())
        })
    })?;
    via_temp(&out.join("questionnaire_scores.csv"), |tmp| {
        with_writer(tmp, |w| {
            w.write_record(SCORE_COLUMNS)?;
            for s in &q.scores {
                w.write_record([
                    s.participant.clone(),
                    s.instrument.clone(),
                    s.condition.clone().unwrap_or_default(),
                    s.scoring.clone(),
                    s.score.to_string(),
                ])?;
            }
            Ok(())
        })
    })?;
    Ok(())
}

/// The questionnaires in summary.json.
pub fn json(q: &Questionnaires) -> Value {
    serde_json::json!({
        "protocol": q.loaded.protocol.name,
        "participants": q.answers.iter().map(|a| a.participant.as_str()).collect::<std::collections::BTreeSet<_>>(),
        "answers": q.answers.len(),
        "scores": q.scores,
        "comparisons": q.comparisons,
    })
}

/// Lines for the terminal: the answers read, the mean scores, the comparisons.
pub fn lines(q: &Questionnaires) -> String {
    use std::fmt::Write as _;
    let mut t = String::new();
    let people = q.answers.iter().map(|a| a.participant.as_str()).collect::<std::collections::BTreeSet<_>>().len();
    let _ = writeln!(
        t,
        "questionnaires ({}): {} answers of {people} participants",
        q.loaded.protocol.name,
        q.answers.len()
    );
    let mut means: BTreeMap<(String, Option<String>), Vec<f64>> = BTreeMap::new();
    for s in &q.scores {
        means.entry((s.instrument.clone(), s.condition.clone())).or_default().push(s.score);
    }
    for ((ins, cond), v) in means {
        let _ = writeln!(
            t,
            "  {ins}{}: mean score {:.1} (n = {})",
            cond.map(|c| format!(" after {c}")).unwrap_or_default(),
            v.iter().sum::<f64>() / v.len() as f64,
            v.len()
        );
    }
    for c in &q.comparisons {
        let _ = writeln!(
            t,
            "  {} vs {}: {} of {} participants rated {} higher, {} the same, {} lower",
            c.b, c.a, c.b_higher, c.n, c.b, c.same, c.a_higher
        );
    }
    t
}

/// A protocol folder for tests: the shipped protocol and two participants' answers (P01 gives
/// `guidance` twice: 3, then 8).
#[cfg(test)]
pub fn fixture(dir: &Path) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    std::fs::copy(root.join("assets/protocols/tree-planting.ron"), dir.join("protocol.ron")).unwrap();
    let line = |_p: &str, step: u64, ins: &str, cond: Option<&str>, item: &str, v: Value| {
        serde_json::json!({"line": "answer", "step": step, "block": "x", "instrument": ins, "condition": cond, "item": item, "answer": v, "time": "2026-12-01T09:00:00.000Z"}).to_string() + "\n"
    };
    for (p, index, sus, billboard, lowpoly, tlx) in
        [("P01", 0, [4, 2, 4, 1, 4, 2, 5, 2, 4, 1], 7, 4, 30), ("P02", 1, [3, 3, 3, 3, 3, 3, 3, 3, 3, 3], 5, 5, 60)]
    {
        let mut text = serde_json::json!({"line": "participant", "participant": p, "protocol": "tree-planting", "index": index, "order": [], "time": "t"}).to_string() + "\n";
        for (i, item) in ["mental", "physical", "temporal", "performance", "effort", "frustration"].iter().enumerate() {
            text += &line(p, 4, "nasa-tlx", Some("manual"), item, serde_json::json!(tlx + 5 * i as i64));
        }
        if p == "P01" {
            text += &line(p, 7, "tree-planting", None, "guidance", serde_json::json!(3));
        }
        text += &line(p, 7, "tree-planting", None, "guidance", serde_json::json!(8));
        text +=
            &line(p, 7, "tree-planting", None, "more_instructions", serde_json::json!(["Bounding box", "Ray-casting"]));
        text += &line(p, 7, "tree-planting", None, "realism_billboard", serde_json::json!(billboard));
        text += &line(p, 7, "tree-planting", None, "realism_lowpoly", serde_json::json!(lowpoly));
        text += &line(p, 7, "tree-planting", None, "would_use", serde_json::json!(p == "P01"));
        for (i, s) in sus.iter().enumerate() {
            text += &line(p, 8, "sus", None, &format!("sus{}", i + 1), serde_json::json!(s));
        }
        std::fs::write(dir.join(format!("{p}{ANSWERS_SUFFIX}")), text).unwrap();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn answers_scores_and_comparisons_of_a_protocol_folder() {
        let dir = tempfile::tempdir().unwrap();
        fixture(dir.path());
        let q = load(dir.path()).unwrap().expect("a protocol folder");
        // 6 TLX + 5 questions + 10 SUS each; P01's first guidance is replaced by their second.
        assert_eq!(q.answers.len(), 42);
        let guidance: Vec<&Value> = q.answers.iter().filter(|a| a.item == "guidance").map(|a| &a.answer).collect();
        assert_eq!(guidance, vec![&serde_json::json!(8), &serde_json::json!(8)]);
        let score =
            |p: &str, ins: &str| q.scores.iter().find(|s| s.participant == p && s.instrument == ins).map(|s| s.score);
        // P01's SUS: (3+3+3+4+3+3+4+3+3+4) × 2.5; P02 all 3s: 50; TLX the mean of 30..55 and 60..85.
        assert_eq!(score("P01", "sus"), Some(82.5));
        assert_eq!(score("P02", "sus"), Some(50.0));
        assert_eq!(score("P01", "nasa-tlx"), Some(42.5));
        assert_eq!(score("P02", "nasa-tlx"), Some(72.5));
        let c = &q.comparisons[0];
        assert_eq!((c.n, c.b_higher, c.same, c.a_higher), (2, 1, 1, 0));
        assert_eq!(cell(&serde_json::json!(["a", "b"])), "a;b");
        assert_eq!(cell(&serde_json::json!(false)), "no");
        let cols = columns(&q.loaded);
        assert_eq!(cols.len(), 6 * 2 + 7 + 10);
        assert_eq!(cols[6], ("nasa-tlx".to_string(), Some("manual".to_string()), "mental".to_string()));
    }

    #[test]
    fn a_folder_without_a_protocol_has_no_questionnaires_and_a_damaged_answers_file_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        assert!(load(dir.path()).unwrap().is_none());
        fixture(dir.path());
        std::fs::write(dir.path().join("P03.answers.jsonl"), "{\"line\": \"answer\"}\nnot json\n").unwrap();
        let e = load(dir.path()).err().expect("refused").to_string();
        assert!(e.contains("P03.answers.jsonl") && e.contains("line 1"), "{e}");
    }
}
