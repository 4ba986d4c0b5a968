//! The participants of a protocol run by `grove serve --protocol` (`docs/protocol.md`): each
//! one's id, condition order (the balanced Latin square's row of their index) and the step of
//! the session they are at, and their answers. Everything is kept in `DIR/<id>.answers.jsonl`,
//! one JSON line per event (the participant, each step entered, each answer, the end), handed to
//! the operating system before the request is answered, as recordings are; a server started
//! again on the folder reads the files back and each participant resumes at their step.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde_json::{json, Value};

use crate::protocol::form::FormInstrument;
use crate::protocol::{Loaded, Step, StepKind};

use crate::serve::protocol::error::ParticipantError;

/// The suffix of a participant's file.
pub const ANSWERS_SUFFIX: &str = ".answers.jsonl";
/// The copy of the protocol kept in the folder (what `grove study` reads).
pub const PROTOCOL_FILE: &str = "protocol.ron";
/// The most answer lines one participant's file takes (answers given again included), so that
/// a client repeating answers cannot fill the disk.
pub const MAX_ANSWER_LINES: usize = 10_000;

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
    /// The step they are at (0-based; `steps.len()` once done).
    pub at: usize,
    /// Answers by (step, item), the last given.
    pub answers: BTreeMap<(usize, String), Value>,
    /// Answer lines in their file.
    pub answer_lines: usize,
}

/// A request's view of whether a step is finished: the task sessions the server has ended.
pub trait TaskSessions {
    /// Whether a session of `participant` for `task` has ended (or was abandoned).
    fn ended(&self, participant: &str, task: &str) -> bool;
}

/// Every participant of a folder.
pub struct Participants {
    /// The protocol.
    pub loaded: Loaded,
    dir: PathBuf,
    list: Mutex<Vec<Participant>>,
}

fn now() -> String {
    chrono::DateTime::<chrono::Utc>::from(std::time::SystemTime::now()).format("%Y-%m-%dT%H:%M:%S%.3fZ").to_string()
}

fn io(path: &Path, e: impl std::fmt::Display) -> ParticipantError {
    ParticipantError::Io { path: path.display().to_string(), message: e.to_string() }
}

impl Participants {
    /// Opens a folder for a protocol: keeps a copy of the protocol in it (refusing a folder that
    /// holds another one) and reads back every participant's file.
    pub fn open(loaded: Loaded, dir: &Path) -> Result<(Participants, Vec<String>), ParticipantError> {
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
        let copy = dir.join(PROTOCOL_FILE);
        if copy.exists() {
            let held = grove_systems::files::read_text(&copy, grove_systems::files::Kind::Index).map_err(|e| ParticipantError::File(e.reason()))?;
            if held != loaded.text {
                return Err(ParticipantError::OtherProtocol { copy: copy.display().to_string() });
            }
        } else {
            crate::atomic_write::write_bytes(&copy, loaded.text.as_bytes()).map_err(|e| ParticipantError::File(e.to_string()))?;
        }
        let mut list = Vec::new();
        let mut notes = Vec::new();
        let mut names: Vec<PathBuf> = std::fs::read_dir(dir)
            .map_err(|e| io(dir, e))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.ends_with(ANSWERS_SUFFIX)))
            .collect();
        names.sort();
        for path in names {
            let p = read_back(&loaded, &path)?;
            notes.push(format!("participant {} resumes at step {} of {}", p.id, (p.at + 1).min(p.steps.len()), p.steps.len()));
            list.push(p);
        }
        list.sort_by_key(|p| p.index);
        Ok((Participants { loaded, dir: dir.to_path_buf(), list: Mutex::new(list) }, notes))
    }

    fn path_of(&self, id: &str) -> PathBuf {
        self.dir.join(format!("{id}{ANSWERS_SUFFIX}"))
    }

    /// Appends lines to a participant's file in one write.
    fn append(&self, id: &str, lines: &[Value]) -> Result<(), ParticipantError> {
        let path = self.path_of(id);
        let mut bytes = Vec::new();
        for l in lines {
            bytes.extend_from_slice(serde_json::to_string(l).unwrap_or_default().as_bytes());
            bytes.push(b'\n');
        }
        let mut f = std::fs::OpenOptions::new().create(true).append(true).open(&path).map_err(|e| io(&path, e))?;
        f.write_all(&bytes).map_err(|e| io(&path, e))
    }

    /// A new participant (the next id and the next row of the square), or the one named `id`
    /// if it exists; `true` when new.
    pub fn join(&self, id: Option<&str>) -> Result<(Value, bool), ParticipantError> {
        let mut list = self.list.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(id) = id {
            if crate::serve::ids::participant(id).is_err() {
                return Err(ParticipantError::BadId);
            }
            if let Some(p) = list.iter().find(|p| p.id == id) {
                return Ok((self.state(p), false));
            }
        }
        let index = list.len();
        let total = self.loaded.protocol.participants;
        if index >= total {
            return Err(ParticipantError::AllJoined { total });
        }
        let id = id.map(str::to_string).unwrap_or_else(|| format!("P{:02}", index + 1));
        let order = self.loaded.order(index);
        let steps = self.loaded.steps(&order);
        let names: Vec<&str> = order.iter().map(|c| self.loaded.protocol.conditions[*c].name.as_str()).collect();
        let first = json!({"line": "participant", "participant": id, "protocol": self.loaded.protocol.name, "index": index, "order": names, "time": now()});
        let step = step_line(&steps, 0);
        self.append(&id, &[first, step])?;
        let p = Participant { id, index, order, steps, at: 0, answers: BTreeMap::new(), answer_lines: 0 };
        let v = self.state(&p);
        list.push(p);
        Ok((v, true))
    }

    /// A participant's state.
    pub fn get(&self, id: &str) -> Result<Value, ParticipantError> {
        let list = self.list.lock().unwrap_or_else(|p| p.into_inner());
        list.iter().find(|p| p.id == id).map(|p| self.state(p)).ok_or_else(|| ParticipantError::Unknown(id.to_string()))
    }

    /// Every participant's state.
    pub fn all(&self) -> Vec<Value> {
        let list = self.list.lock().unwrap_or_else(|p| p.into_inner());
        list.iter().map(|p| self.state(p)).collect()
    }

    /// Records answers to the questionnaire of step `step` (1-based): every one is checked
    /// against its item before any is written.
    pub fn answer(&self, id: &str, step: usize, answers: &serde_json::Map<String, Value>) -> Result<Value, ParticipantError> {
        let mut list = self.list.lock().unwrap_or_else(|p| p.into_inner());
        let p = list.iter_mut().find(|p| p.id == id).ok_or_else(|| ParticipantError::Unknown(id.to_string()))?;
        if step != p.at + 1 {
            return Err(ParticipantError::WrongStep { id: id.to_string(), at: p.at + 1, step });
        }
        let Some(StepKind::Questionnaire { instrument, condition }) = p.steps.get(p.at).map(|s| s.kind.clone()) else {
            return Err(ParticipantError::NotAQuestionnaire { id: id.to_string(), step });
        };
        let ins = self.loaded.instrument(&instrument).ok_or(ParticipantError::InstrumentGone)?;
        if answers.is_empty() {
            return Err(ParticipantError::NoAnswers);
        }
        if p.answer_lines + answers.len() > MAX_ANSWER_LINES {
            return Err(ParticipantError::TooManyAnswers { id: id.to_string(), given: p.answer_lines, most: MAX_ANSWER_LINES });
        }
        let time = now();
        let cond = condition.map(|c| self.loaded.protocol.conditions[c].name.clone());
        let mut lines = Vec::new();
        for (item_id, value) in answers {
            let item = ins.items.iter().find(|i| &i.id == item_id).ok_or_else(|| ParticipantError::NoSuchItem { instrument: ins.id.clone(), item: item_id.clone() })?;
            crate::protocol::answer::check(item, value).map_err(ParticipantError::BadAnswer)?;
            lines.push(json!({"line": "answer", "step": step, "block": p.steps[p.at].name, "instrument": ins.id, "condition": cond, "item": item_id, "answer": value, "time": time}));
        }
        self.append(id, &lines)?;
        p.answer_lines += lines.len();
        for (item_id, value) in answers {
            p.answers.insert((p.at, item_id.clone()), value.clone());
        }
        Ok(self.state(p))
    }

    /// Moves participant `id` from step `from` (1-based) to the next, if the step is finished:
    /// a task whose session has ended, a questionnaire with every required item answered.
    pub fn next(&self, id: &str, from: usize, tasks: &dyn TaskSessions) -> Result<Value, ParticipantError> {
        let mut list = self.list.lock().unwrap_or_else(|p| p.into_inner());
        let p = list.iter_mut().find(|p| p.id == id).ok_or_else(|| ParticipantError::Unknown(id.to_string()))?;
        if p.at >= p.steps.len() {
            return Err(ParticipantError::Finished(id.to_string()));
        }
        if from != p.at + 1 {
            return Err(ParticipantError::WrongStep { id: id.to_string(), at: p.at + 1, step: from });
        }
        match &p.steps[p.at].kind {
            StepKind::Task { condition } => {
                let task = &self.loaded.protocol.conditions[*condition].task;
                if !tasks.ended(id, task) {
                    return Err(ParticipantError::TaskNotEnded { step: from, task: task.clone() });
                }
            }
            StepKind::Questionnaire { instrument, .. } => {
                let ins = self.loaded.instrument(instrument).ok_or(ParticipantError::InstrumentGone)?;
                let missing: Vec<&str> = ins.items.iter().filter(|i| i.required && !p.answers.contains_key(&(p.at, i.id.clone()))).map(|i| i.id.as_str()).collect();
                if !missing.is_empty() {
                    return Err(ParticipantError::NotAnswered { step: from, missing: missing.join(", ") });
                }
            }
            StepKind::Instructions | StepKind::Practice => {}
        }
        let line = if p.at + 1 < p.steps.len() { step_line(&p.steps, p.at + 1) } else { json!({"line": "done", "time": now()}) };
        self.append(id, &[line])?;
        p.at += 1;
        Ok(self.state(p))
    }

    /// What a participant's page and the dashboard are told.
    fn state(&self, p: &Participant) -> Value {
        let cond = |c: usize| &self.loaded.protocol.conditions[c];
        let steps: Vec<Value> = p.steps.iter().enumerate().map(|(i, s)| self.describe(i, s)).collect();
        let answers: serde_json::Map<String, Value> = p.answers.iter().filter(|((s, _), _)| *s == p.at).map(|((_, k), v)| (k.clone(), v.clone())).collect();
        json!({
            "participant": p.id,
            "protocol": self.loaded.protocol.name,
            "order": p.order.iter().map(|c| cond(*c).name.clone()).collect::<Vec<_>>(),
            "step": p.at + 1,
            "steps": steps,
            "done": p.at >= p.steps.len(),
            "answers": answers,
        })
    }

    fn describe(&self, i: usize, s: &Step) -> Value {
        let block = &self.loaded.protocol.blocks[s.block];
        let mut v = json!({"step": i + 1, "block": s.name});
        let o = v.as_object_mut().expect("an object");
        match (&s.kind, block) {
            (StepKind::Instructions, crate::protocol::Block::Instructions { text, image, video, .. }) => {
                o.insert("kind".into(), json!("instructions"));
                o.insert("text".into(), json!(text));
                o.insert("image".into(), json!(image.as_ref().map(|_| format!("/protocol/media/{}/image", s.name))));
                o.insert("video".into(), json!(video.as_ref().map(|_| format!("/protocol/media/{}/video", s.name))));
            }
            (StepKind::Practice, crate::protocol::Block::Practice { text, seconds, .. }) => {
                o.insert("kind".into(), json!("practice"));
                o.insert("text".into(), json!(text));
                o.insert("seconds".into(), json!(seconds));
                o.insert("scene".into(), json!(self.loaded.protocol.scene));
            }
            (StepKind::Task { condition }, _) => {
                let c = &self.loaded.protocol.conditions[*condition];
                o.insert("kind".into(), json!("task"));
                o.insert("condition".into(), json!(c.name));
                o.insert("task".into(), json!(c.task));
                o.insert("scene".into(), json!(self.loaded.protocol.scene));
            }
            (StepKind::Questionnaire { instrument, condition }, _) => {
                o.insert("kind".into(), json!("questionnaire"));
                o.insert("instrument".into(), serde_json::to_value(self.loaded.instrument(instrument).map(|i| FormInstrument::new(&i))).unwrap_or(Value::Null));
                o.insert("condition".into(), json!(condition.map(|c| self.loaded.protocol.conditions[c].name.clone())));
            }
            _ => {}
        }
        v
    }

    /// The file of an instruction block's image or video, inside the protocol's folder.
    pub fn media(&self, block: &str, what: &str) -> Option<PathBuf> {
        self.loaded.protocol.blocks.iter().find_map(|b| match b {
            crate::protocol::Block::Instructions { name, image, video, .. } if name == block => match what {
                "image" => image.as_ref().map(|f| self.loaded.folder.join(f)),
                "video" => video.as_ref().map(|f| self.loaded.folder.join(f)),
                _ => None,
            },
            _ => None,
        })
    }
}

fn step_line(steps: &[Step], at: usize) -> Value {
    json!({"line": "step", "step": at + 1, "block": steps[at].name, "time": now()})
}

/// Reads a participant's file back: the participant, the last step entered, the answers. A last
/// line cut short by a crash (no newline) was never acknowledged and is cut off.
fn read_back(loaded: &Loaded, path: &Path) -> Result<Participant, ParticipantError> {
    let text = grove_systems::files::read_text(path, grove_systems::files::Kind::Recording).map_err(|e| ParticipantError::File(e.reason()))?;
    let whole = match text.rfind('\n') {
        Some(end) => end + 1,
        None => 0,
    };
    if whole < text.len() {
        let f = std::fs::OpenOptions::new().write(true).open(path).map_err(|e| io(path, e))?;
        f.set_len(whole as u64).map_err(|e| io(path, e))?;
    }
    let bad = |n: usize, why: &str| io(path, format!("line {n}: {why}"));
    let mut p: Option<Participant> = None;
    for (n, line) in text[..whole].lines().enumerate() {
        let v: Value = serde_json::from_str(line).map_err(|e| bad(n + 1, &e.to_string()))?;
        match (v["line"].as_str(), p.as_mut()) {
            (Some("participant"), None) => {
                let id = v["participant"].as_str().ok_or_else(|| bad(n + 1, "no participant"))?.to_string();
                let index = v["index"].as_u64().ok_or_else(|| bad(n + 1, "no index"))? as usize;
                let order = loaded.order(index);
                let steps = loaded.steps(&order);
                p = Some(Participant { id, index, order, steps, at: 0, answers: BTreeMap::new(), answer_lines: 0 });
            }
            (Some("step"), Some(p)) => p.at = (v["step"].as_u64().unwrap_or(1) as usize).saturating_sub(1).min(p.steps.len()),
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

#[cfg(test)]
mod tests {
    use super::*;

    struct NoneEnded;
    impl TaskSessions for NoneEnded {
        fn ended(&self, _: &str, _: &str) -> bool {
            false
        }
    }

    fn shipped() -> Loaded {
        crate::protocol::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/protocols/tree-planting.ron")).expect("the shipped protocol")
    }

    #[test]
    fn a_participant_resumes_at_their_step_and_a_line_cut_short_by_a_crash_is_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let (ps, _) = Participants::open(shipped(), dir.path()).unwrap();
        let (first, new) = ps.join(None).unwrap();
        assert!(new);
        assert_eq!(first["participant"], "P01");
        ps.next("P01", 1, &NoneEnded).unwrap();
        ps.next("P01", 2, &NoneEnded).unwrap();
        let refused = crate::serve::http::refusal::Refusal::from(ps.next("P01", 3, &NoneEnded).unwrap_err());
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
        let (second, new) = again.join(None).unwrap();
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
}
