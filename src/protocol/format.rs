//! The protocol file's types (RON, `docs/protocol.md`): the conditions and how many
//! participants they are counterbalanced over, the blocks in order, and the questionnaires
//! (instruments) with their items. Only the shapes live here; `check.rs` holds the rules.

use serde::{Deserialize, Serialize};

/// A whole study session, as a protocol file states it.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Protocol {
    /// The protocol's name (a word: letters, digits, `-`, `_`).
    pub name: String,
    /// How many participants the study has: a multiple of the balanced Latin square's rows.
    pub participants: usize,
    /// The scene the tasks and the practice run in (a built-in scene).
    #[serde(default = "default_scene")]
    pub scene: String,
    /// The conditions, counterbalanced over the participants by a balanced Latin square.
    pub conditions: Vec<Condition>,
    /// The blocks, in order.
    pub blocks: Vec<Block>,
    /// The protocol's own questionnaires; the shipped ones (`sus`, `nasa-tlx`) need no entry.
    #[serde(default)]
    pub instruments: Vec<Instrument>,
    /// Pairs of items compared within participants in the study's report.
    #[serde(default)]
    pub compare: Vec<Compare>,
}

fn default_scene() -> String {
    "study".into()
}

/// One condition: a task, done with a technique.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Condition {
    /// The condition's name, as reports show it.
    pub name: String,
    /// A built-in task (`assets/tasks/`).
    pub task: String,
}

/// A block of the session.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Block {
    /// Instructions to read, look at or watch; at least one of the three.
    Instructions {
        /// The block's name.
        name: String,
        /// Text shown to the participant.
        #[serde(default)]
        text: String,
        /// An image file, relative to the protocol file's folder.
        #[serde(default)]
        image: Option<String>,
        /// A video file, relative to the protocol file's folder.
        #[serde(default)]
        video: Option<String>,
    },
    /// Practice in a free scene, for a time or (without `seconds`) until the participant ends it.
    Practice {
        /// The block's name.
        name: String,
        /// What the participant is asked to try.
        #[serde(default)]
        text: String,
        /// How long the practice lasts; none: until the participant ends it.
        #[serde(default)]
        seconds: Option<f64>,
    },
    /// One task per condition, in the participant's order; after each, the questionnaires
    /// named in `after` (answered for that condition).
    Tasks {
        /// The block's name.
        name: String,
        /// Questionnaires answered after each task, about it.
        #[serde(default)]
        after: Vec<String>,
    },
    /// A questionnaire: one of the protocol's instruments or a shipped one.
    Questionnaire {
        /// The block's name.
        name: String,
        /// The instrument's id.
        instrument: String,
    },
}

impl Block {
    /// The block's name.
    pub fn name(&self) -> &str {
        match self {
            Block::Instructions { name, .. }
            | Block::Practice { name, .. }
            | Block::Tasks { name, .. }
            | Block::Questionnaire { name, .. } => name,
        }
    }
}

/// A questionnaire.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Instrument {
    /// Its id (a word), as answers and reports name it.
    pub id: String,
    /// Its title, shown above the items.
    pub title: String,
    /// A sentence shown before the items.
    #[serde(default)]
    pub intro: String,
    /// How its answers make a score.
    #[serde(default)]
    pub scoring: Scoring,
    /// The items, in order.
    pub items: Vec<Item>,
}

/// How an instrument is scored.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Scoring {
    /// No score: the answers alone.
    #[default]
    None,
    /// The System Usability Scale (Brooke 1996): ten 1–5 items; odd items score − 1, even
    /// items 5 − score, the sum × 2.5 (0–100).
    Sus,
    /// Raw NASA-TLX (Hart 2006): the mean of the six subscales (0–100), without the weights.
    RawTlx,
}

/// One question.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Item {
    /// Its id (a word), unique within the instrument.
    pub id: String,
    /// The question.
    pub text: String,
    /// The answer it takes.
    pub kind: ItemKind,
    /// Whether the questionnaire can be left without it (default: required).
    #[serde(default = "yes")]
    pub required: bool,
}

fn yes() -> bool {
    true
}

/// The answer an item takes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ItemKind {
    /// A whole number from 0 to 10; `anchors` name the two ends.
    Rating {
        /// The words at 0 and at 10.
        #[serde(default)]
        anchors: Vec<String>,
    },
    /// A whole number from `min` to `max` in steps of `step`; `anchors` name the two ends.
    Scale {
        /// The lowest answer.
        min: i64,
        /// The highest answer.
        max: i64,
        /// The step between answers (default 1).
        #[serde(default = "one")]
        step: i64,
        /// The words at the two ends.
        #[serde(default)]
        anchors: Vec<String>,
    },
    /// A Likert item: a whole number from 1 to `points`; `anchors` name the two ends or every point.
    Likert {
        /// How many points (2 to 11).
        points: i64,
        /// The words at the two ends, or one per point.
        #[serde(default)]
        anchors: Vec<String>,
    },
    /// One of the choices.
    Single {
        /// The choices.
        choices: Vec<String>,
    },
    /// Any of the choices (none included).
    Multiple {
        /// The choices.
        choices: Vec<String>,
    },
    /// Free text, at most `max_chars` characters.
    Text {
        /// The longest answer in characters.
        #[serde(default = "text_limit")]
        max_chars: usize,
    },
    /// Yes or no.
    YesNo,
}

fn one() -> i64 {
    1
}

fn text_limit() -> usize {
    2000
}

/// Two items compared within participants (each participant's b − a).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Compare {
    /// The first item, `instrument/item`.
    pub a: String,
    /// The second item, `instrument/item`.
    pub b: String,
}
