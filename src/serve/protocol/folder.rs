//! A protocol's folder read back at start: every participant's `DIR/<id>.answers.jsonl`, a last
//! line cut short by a crash cut off, and the ids checked as the server gives them: each a plain
//! word equal to its file's name, one participant per file, and no two that differ only in case
//! (they would be one file on a macOS or Windows disk). A folder an older `grove serve` wrote
//! with a repeated id is reported by the id, with how to mend it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::protocol::Loaded;
use crate::serve::protocol::error::ParticipantError;
use crate::protocol::Step;

/// The suffix of a participant's file.
pub const ANSWERS_SUFFIX: &str = ".answers.jsonl";
/// One participant.
#[derive(Clone, Debug)]
pub struct Participant {
    /// The id (`P01`, …).
    pub id: String,
    /// Their index (0-based) among the participants: the Latin square's row.
    pub index: usize,
    /// Their conditions in order (indices of the protocol's conditions).
    pub order: Vec<usize>,
    /// Their steps.
    pub steps: Vec<Step>,
    /// When each step began (the time of its line in their file; the first step's is when they
    /// joined), for the steps they have reached.
    pub began: Vec<Option<String>>,
    /// The step they are at (0-based; `steps.len()` once done).
    pub at: usize,
    /// Answers by (step, item), the last given.
    pub answers: BTreeMap<(usize, String), Value>,
    /// Answer lines in their file.
    pub answer_lines: usize,
}

fn io(path: &Path, e: impl std::fmt::Display) -> ParticipantError {
    ParticipantError::Io { path: path.display().to_string(), message: e.to_string() }
}

/// Every participant of the folder, in the order they joined.
pub fn read_all(loaded: &Loaded, dir: &Path) -> Result<Vec<Participant>, ParticipantError> {
    let mut names: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.ends_with(ANSWERS_SUFFIX)))
        .collect();
    names.sort();
    let mut list: Vec<Participant> = Vec::new();
    for path in names {
        let p = read_back(loaded, &path)?;
        if let Some(other) = list.iter().find(|o| o.id.eq_ignore_ascii_case(&p.id)) {
            return Err(ParticipantError::CaseClash { dir: dir.display().to_string(), a: other.id.clone(), b: p.id });
        }
        list.push(p);
    }
    list.sort_by_key(|p| p.index);
    Ok(list)
}

/// Reads a participant's file back: the participant, the step they are at and when each step
/// began, the answers. A last line cut short by a crash (no newline) was never acknowledged and
/// is cut off.
fn read_back(loaded: &Loaded, path: &Path) -> Result<Participant, ParticipantError> {
    let text = grove_systems::files::read_text(path, grove_systems::files::Kind::Recording).map_err(|e| ParticipantError::File(e.reason()))?;
    let whole = text.rfind('\n').map_or(0, |end| end + 1);
    if whole < text.len() {
        let f = std::fs::OpenOptions::new().write(true).open(path).map_err(|e| io(path, e))?;
        f.set_len(whole as u64).map_err(|e| io(path, e))?;
    }
    let file = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let named = file.strip_suffix(ANSWERS_SUFFIX).unwrap_or_default().to_string();
    let bad = |n: usize, why: &str| io(path, format!("line {n}: {why}"));
    let mut p: Option<Participant> = None;
    for (n, line) in text[..whole].lines().enumerate() {
        let v: Value = serde_json::from_str(line).map_err(|e| bad(n + 1, &e.to_string()))?;
        let time = v["time"].as_str().unwrap_or_default().to_string();
        match (v["line"].as_str(), p.as_mut()) {
            (Some("participant"), None) => {
                let id = v["participant"].as_str().ok_or_else(|| bad(n + 1, "no participant"))?.to_string();
                if id != named || crate::serve::ids::participant(&id).is_err() {
                    return Err(ParticipantError::FileId { file, id });
                }
                let index = v["index"].as_u64().ok_or_else(|| bad(n + 1, "no index"))? as usize;
                let order = loaded.order(index);
                let steps = loaded.steps(&order);
                let mut began = vec![None; steps.len()];
                if let Some(first) = began.first_mut() {
                    *first = Some(time);
                }
                p = Some(Participant { id, index, order, steps, began, at: 0, answers: BTreeMap::new(), answer_lines: 0 });
            }
            (Some("participant"), Some(first)) => {
                let second = v["index"].as_u64().map_or(0, |i| i + 1);
                return Err(ParticipantError::RepeatedId { file, id: first.id.clone(), first: first.index + 1, second, line: n + 1 });
            }
            (Some("step"), Some(p)) => {
                p.at = (v["step"].as_u64().unwrap_or(1) as usize).saturating_sub(1).min(p.steps.len());
                if let Some(b) = p.began.get_mut(p.at) {
                    *b = Some(time);
                }
            }
            (Some("done"), Some(p)) => p.at = p.steps.len(),
            (Some("answer"), Some(p)) => {
                let step = (v["step"].as_u64().unwrap_or(1) as usize).saturating_sub(1);
                p.answers.insert((step, v["item"].as_str().unwrap_or_default().to_string()), v["answer"].clone());
                p.answer_lines += 1;
            }
            _ => return Err(bad(n + 1, "not a line of a participant's file")),
        }
    }
    p.ok_or_else(|| io(path, "no participant line"))
}
