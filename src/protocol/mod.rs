//! Study protocols (`docs/protocol.md`): a whole session as a RON file — instructions,
//! practice, the conditions' tasks in a counterbalanced order, questionnaires — and what
//! `grove serve --protocol` and `grove study` need of it.
//!
//! - [`format`]: the file's types; [`check`]: its rules, each failure naming its place;
//! - [`shipped`]: the System Usability Scale and raw NASA-TLX; [`score`]: their scoring;
//! - [`answer`]: what an item takes and whether an answer fits it; [`form`]: an instrument as the
//!   pages show it, what each item takes worked out;
//! - [`Loaded`]: a checked protocol, and the steps a participant goes through ([`Loaded::steps`]).

pub mod answer;
pub mod check;
pub mod form;
pub mod format;
pub mod latin;
pub mod score;
pub mod shipped;

use std::path::{Path, PathBuf};

pub use format::{Block, Compare, Condition, Instrument, Item, ItemKind, Protocol, Scoring};

/// Why a protocol file was refused: one line naming the file and the place.
#[derive(Debug, thiserror::Error)]
pub enum ProtocolError {
    /// The file could not be read.
    #[error(transparent)]
    File(#[from] grove_systems::files::FileError),
    /// The file is not a protocol (RON syntax, an unknown block or item type, a missing field).
    #[error("{path}:{line}:{column}: {message}")]
    Parse {
        /// The file.
        path: String,
        /// The line of the problem (1-based).
        line: usize,
        /// Its column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A rule broken.
    #[error("{path}: {place}: {message}")]
    Invalid {
        /// The file.
        path: String,
        /// Where.
        place: String,
        /// What.
        message: String,
    },
}

/// A checked protocol, with its text (kept beside the answers) and folder.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The protocol.
    pub protocol: Protocol,
    /// The file's text as read.
    pub text: String,
    /// The file's folder (instruction files lie inside it).
    pub folder: PathBuf,
}

/// What a participant does at one step of the session.
#[derive(Clone, Debug, PartialEq)]
pub enum StepKind {
    /// Read, look at or watch the instructions of block `block`.
    Instructions,
    /// Practise in a free scene.
    Practice,
    /// The task of condition `condition` (an index of the protocol's conditions).
    Task {
        /// The condition.
        condition: usize,
    },
    /// Answer a questionnaire, about a condition when it follows a task.
    Questionnaire {
        /// The instrument's id.
        instrument: String,
        /// The condition it is about, if any.
        condition: Option<usize>,
    },
}

/// One step of a participant's session: a protocol block, or a part of its Tasks block.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// The protocol block it comes from (0-based).
    pub block: usize,
    /// The block's name.
    pub name: String,
    /// What the participant does.
    pub kind: StepKind,
}

/// Reads and checks a protocol file.
pub fn load(path: &Path) -> Result<Loaded, ProtocolError> {
    let text = grove_systems::files::read_text(path, grove_systems::files::Kind::Index)?;
    let folder = path.parent().map(|p| if p.as_os_str().is_empty() { Path::new(".") } else { p }).unwrap_or(Path::new(".")).to_path_buf();
    parse(&text, &path.display().to_string(), &folder)
}

/// Parses and checks a protocol's text; `path` names it in errors.
pub fn parse(text: &str, path: &str, folder: &Path) -> Result<Loaded, ProtocolError> {
    let protocol: Protocol = ron::from_str(text).map_err(|e| ProtocolError::Parse {
        path: path.to_string(),
        line: e.span.start.line,
        column: e.span.start.col,
        message: e.code.to_string().replace(['\n', '\r'], " "),
    })?;
    check::check(&protocol, folder).map_err(|b| ProtocolError::Invalid { path: path.to_string(), place: b.place, message: b.message })?;
    Ok(Loaded { protocol, text: text.to_string(), folder: folder.to_path_buf() })
}

impl Loaded {
    /// An instrument the protocol gives: its own or a shipped one.
    pub fn instrument(&self, id: &str) -> Option<Instrument> {
        self.protocol.instruments.iter().find(|i| i.id == id).cloned().or_else(|| shipped::get(id))
    }

    /// The rows of the balanced Latin square over the conditions.
    pub fn rows(&self) -> usize {
        latin::williams(self.protocol.conditions.len()).len()
    }

    /// The order (condition indices) of the participant with 0-based index `p`.
    pub fn order(&self, p: usize) -> Vec<usize> {
        latin::order(p, self.protocol.conditions.len())
    }

    /// The steps of a participant whose conditions come in `order`: each block in turn, the
    /// Tasks block as one task per condition, each followed by its `after` questionnaires.
    pub fn steps(&self, order: &[usize]) -> Vec<Step> {
        let mut steps = Vec::new();
        for (b, block) in self.protocol.blocks.iter().enumerate() {
            let name = block.name().to_string();
            match block {
                Block::Instructions { .. } => steps.push(Step { block: b, name, kind: StepKind::Instructions }),
                Block::Practice { .. } => steps.push(Step { block: b, name, kind: StepKind::Practice }),
                Block::Questionnaire { instrument, .. } => steps.push(Step { block: b, name, kind: StepKind::Questionnaire { instrument: instrument.clone(), condition: None } }),
                Block::Tasks { after, .. } => {
                    for &c in order {
                        steps.push(Step { block: b, name: name.clone(), kind: StepKind::Task { condition: c } });
                        for a in after {
                            steps.push(Step { block: b, name: name.clone(), kind: StepKind::Questionnaire { instrument: a.clone(), condition: Some(c) } });
                        }
                    }
                }
            }
        }
        steps
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_protocol_loads_and_gives_both_orders() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/protocols/tree-planting.ron");
        let p = load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(p.rows(), 2);
        assert_eq!(p.order(0), vec![0, 1]);
        assert_eq!(p.order(1), vec![1, 0]);
        let steps = p.steps(&p.order(1));
        let tasks: Vec<usize> = steps.iter().filter_map(|s| match s.kind { StepKind::Task { condition } => Some(condition), _ => None }).collect();
        assert_eq!(tasks, vec![1, 0]);
        let q = p.instrument("tree-planting").expect("the paper's questionnaire");
        assert_eq!(q.items.len(), 7);
    }
}
