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
pub use crate::serve::protocol::folder::{Participant, ANSWERS_SUFFIX};

/// The copy of the protocol kept in the folder (what `grove study` reads).
pub const PROTOCOL_FILE: &str = "protocol.ron";
/// The most answer lines one participant's file takes (answers given again included), so that
/// a client repeating answers cannot fill the disk.
pub const MAX_ANSWER_LINES: usize = 10_000;


/// What the participants see of the folder's sessions: the one that finishes a task step, and
/// the participant ids the sessions use.
pub trait TaskSessions {
    /// The file of the session that finishes `participant`'s step of `task` that began at `began`
    /// (`docs/protocol.md`: theirs, of that task, opened after the step began, and complete or
    /// ended by its client); or, when none does, each session of theirs for that task that is
    /// not this step's, with why.
    fn finishing(&self, participant: &str, task: &str, began: &str) -> Result<String, Vec<(String, &'static str)>>;
    /// The participant ids the folder's sessions use, each with one of its files.
    fn ids_in_use(&self) -> Vec<(String, String)>;
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
        let list = crate::serve::protocol::folder::read_all(&loaded, dir)?;
        let notes = list.iter().map(|p| format!("participant {} resumes at step {} of {}", p.id, (p.at + 1).min(p.steps.len()), p.steps.len())).collect();
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
    /// if it exists; `true` when new. One namespace: an automatic id skips every id in use (a
    /// participant's, or one the folder's sessions use), a new id that is in use is refused, and
    /// ids are compared without regard to case.
    pub fn join(&self, id: Option<&str>, sessions: &dyn TaskSessions) -> Result<(Value, bool), ParticipantError> {
        let mut list = self.list.lock().unwrap_or_else(|p| p.into_inner());
        let used = sessions.ids_in_use();
        let holder = |candidate: &str| -> Option<String> {
            match list.iter().find(|p| p.id.eq_ignore_ascii_case(candidate)) {
                Some(p) => Some(format!("participant {}", p.id)),
                None => used.iter().find(|(i, _)| i.eq_ignore_ascii_case(candidate)).map(|(i, f)| format!("the sessions of {i} in this folder ({f})")),
            }
        };
        if let Some(id) = id {
            if crate::serve::ids::participant(id).is_err() {
                return Err(ParticipantError::BadId);
            }
            if let Some(p) = list.iter().find(|p| p.id == id) {
                return Ok((self.state(p), false));
            }
            if let Some(holder) = holder(id) {
                return Err(ParticipantError::IdInUse { id: id.to_string(), holder });
            }
        }
        let index = list.len();
        let total = self.loaded.protocol.participants;
        if index >= total {
            return Err(ParticipantError::AllJoined { total });
        }
        let id = match id {
            Some(id) => id.to_string(),
            None => (index + 1..).map(|n| format!("P{n:02}")).find(|c| holder(c).is_none()).unwrap_or_default(),
        };
        let order = self.loaded.order(index);
        let steps = self.loaded.steps(&order);
        let names: Vec<&str> = order.iter().map(|c| self.loaded.protocol.conditions[*c].name.as_str()).collect();
        let time = now();
        let first = json!({"line": "participant", "participant": id, "protocol": self.loaded.protocol.name, "index": index, "order": names, "time": time});
        let step = step_line(&steps, 0, &time);
        self.append(&id, &[first, step])?;
        let mut began = vec![None; steps.len()];
        if let Some(b) = began.first_mut() {
            *b = Some(time);
        }
        let p = Participant { id, index, order, steps, began, at: 0, answers: BTreeMap::new(), answer_lines: 0 };
        let v = self.state(&p);
        list.push(p);
        Ok((v, true))
    }

    /// A participant's state.
    pub fn get(&self, id: &str) -> Result<Value, ParticipantError> {
        let list = self.list.lock().unwrap_or_else(|p| p.into_inner());
        list.iter().find(|p| p.id == id).map(|p| self.state(p)).ok_or_else(|| ParticipantError::Unknown(id.to_string()))
    }

    /// Every participant's task steps: (participant, task, when the step began if they have
    /// reached it).
    pub fn task_steps(&self) -> Vec<(String, String, Option<String>)> {
        let list = self.list.lock().unwrap_or_else(|p| p.into_inner());
        let mut out = Vec::new();
        for p in list.iter() {
            for (i, s) in p.steps.iter().enumerate() {
                if let StepKind::Task { condition } = &s.kind {
                    out.push((p.id.clone(), self.loaded.protocol.conditions[*condition].task.clone(), p.began.get(i).cloned().flatten()));
                }
            }
        }
        out
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
            crate::protocol::answer::check(item, value)?;
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
                let began = p.began.get(p.at).cloned().flatten().unwrap_or_default();
                if let Err(others) = tasks.finishing(id, task, &began) {
                    let others = others.iter().map(|(file, why)| format!("{file} ({why})")).collect();
                    return Err(ParticipantError::TaskNotEnded { step: from, task: task.clone(), others });
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
        let time = now();
        let line = if p.at + 1 < p.steps.len() { step_line(&p.steps, p.at + 1, &time) } else { json!({"line": "done", "time": time}) };
        self.append(id, &[line])?;
        p.at += 1;
        if let Some(b) = p.began.get_mut(p.at) {
            *b = Some(time);
        }
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

fn step_line(steps: &[Step], at: usize, time: &str) -> Value {
    json!({"line": "step", "step": at + 1, "block": steps[at].name, "time": time})
}

#[cfg(test)]
#[path = "participants_tests.rs"]
mod tests;
