//! Why a protocol request or a participant's file was refused: one enum for the room, each
//! variant one line. `serve/refusals.rs` gives each its HTTP status.

use crate::serve::http::refusal::Refusal;

/// The sessions that are not a step's, as the end of its refusal: `; not this step's: FILE (why), …`.
fn not_this_steps(others: &[String]) -> String {
    if others.is_empty() {
        String::new()
    } else {
        format!("; not this step's: {}", others.join(", "))
    }
}

/// Why a protocol request, or the protocol's folder, was refused.
#[derive(Debug, thiserror::Error)]
pub enum ParticipantError {
    /// The server runs no protocol.
    #[error("this server runs no protocol (start it with grove serve --protocol FILE)")]
    NoProtocol,
    /// A participant id unfit for a file name.
    #[error("a participant id is 1 to 32 letters, digits, '_' or '-', starting with a letter or digit")]
    BadId,
    /// A participant id that is not a string.
    #[error("'participant' must be a participant id, a string (1 to 32 letters, digits, '_' or '-'); the request sent {0}")]
    IdNotText(String),
    /// A join request with other fields than `participant`.
    #[error("send {{}} for a new participant or {{\"participant\": ID}}; the request has '{0}'")]
    JoinShape(String),
    /// A new participant's id already in use (ids are compared without regard to case).
    #[error("participant id {id} is in use by {holder} (ids are compared without regard to case); choose another, or send {{}} for the next free one")]
    IdInUse {
        /// The id asked for.
        id: String,
        /// What has it.
        holder: String,
    },
    /// Every participant the protocol is for has joined.
    #[error("the protocol is for {total} participants, and all {total} have joined")]
    AllJoined {
        /// The protocol's participants.
        total: usize,
    },
    /// No participant of that id.
    #[error("no participant {0}")]
    Unknown(String),
    /// The request names another step than the participant's.
    #[error("participant {id} is at step {at}; the request names step {step}")]
    WrongStep {
        /// The participant.
        id: String,
        /// Their step (1-based).
        at: usize,
        /// The step the request names.
        step: usize,
    },
    /// Answers to a step that is not a questionnaire.
    #[error("step {step} of participant {id} is not a questionnaire")]
    NotAQuestionnaire {
        /// The participant.
        id: String,
        /// The step.
        step: usize,
    },
    /// The step's instrument is not in the protocol.
    #[error("the instrument is gone")]
    InstrumentGone,
    /// An answers request without answers.
    #[error("no answers given: send {{\"step\": N, \"answers\": {{ITEM: ANSWER, …}}}}")]
    NoAnswers,
    /// A participant's file holds as many answers as it takes.
    #[error("participant {id} has given {given} answers, the most one participant's file takes is {most}")]
    TooManyAnswers {
        /// The participant.
        id: String,
        /// Answers given.
        given: usize,
        /// The most a file takes.
        most: usize,
    },
    /// An answer to an item the questionnaire does not have.
    #[error("questionnaire '{instrument}' has no item '{item}'")]
    NoSuchItem {
        /// The questionnaire.
        instrument: String,
        /// The item named.
        item: String,
    },
    /// An answer that does not fit its item.
    #[error(transparent)]
    BadAnswer(#[from] crate::protocol::answer::BadAnswer),
    /// The participant has finished.
    #[error("participant {0} has finished the protocol")]
    Finished(String),
    /// A task step whose session has not ended.
    #[error("step {step} is task {task}: its session has not ended yet{}", not_this_steps(.others))]
    TaskNotEnded {
        /// The step.
        step: usize,
        /// The task.
        task: String,
        /// The participant's other sessions of the task, each `FILE (why it is not this step's)`.
        others: Vec<String>,
    },
    /// A questionnaire step with required items unanswered.
    #[error("step {step}: items not answered yet: {missing}")]
    NotAnswered {
        /// The step.
        step: usize,
        /// The items, comma-separated.
        missing: String,
    },
    /// An instruction block without that file.
    #[error("block {block} has no {what}")]
    NoMedia {
        /// The block.
        block: String,
        /// `image` or `video`.
        what: String,
    },
    /// An instruction block's file that cannot be served.
    #[error("{0}")]
    Media(String),
    /// An answers request of another shape.
    #[error("send {{\"step\": N, \"answers\": {{ITEM: ANSWER, …}}}}")]
    AnswersShape,
    /// A step that is not a whole number from 1.
    #[error("'{field}' must be the participant's step, a whole number from 1; the request sent {sent}")]
    StepNotNumber {
        /// `step` or `from`.
        field: &'static str,
        /// What was sent, as JSON (cut short).
        sent: String,
    },
    /// A next request of another shape.
    #[error("send {{\"from\": N}}, the step the participant leaves")]
    FromShape,
    /// A participant's file whose participant line names another id than its file, or an id
    /// unfit for a file name.
    #[error("{file}: its participant line names {id:?}, which is not the id its name gives; a participant's file is ID.answers.jsonl with that ID inside")]
    FileId {
        /// The file.
        file: String,
        /// The id inside.
        id: String,
    },
    /// Two participants with one id in one file, as an older `grove serve` could write.
    #[error("{file}: two participants have the id {id}, participant {first} and participant {second} (from line {line}), as an older grove serve gave a named id again as an automatic one; their steps and answers are mixed in this file. To mend the folder, move the second participant's lines (from line {line} on, those of their steps) into a file of an id no one has, such as {id}-2.answers.jsonl with that id in its first line, and rename their recordings to it; or go on in a new --out folder")]
    RepeatedId {
        /// The file.
        file: String,
        /// The id.
        id: String,
        /// The first participant's number (1-based, in the order they joined).
        first: usize,
        /// The second's.
        second: u64,
        /// The second participant line.
        line: usize,
    },
    /// Two participants whose ids differ only in case (one file on a macOS or Windows disk).
    #[error("{dir}: participants {a} and {b} have ids that differ only in case, which are one file on a macOS or Windows disk; rename one participant's files (its answers and recordings) to an id no one has")]
    CaseClash {
        /// The folder.
        dir: String,
        /// One id.
        a: String,
        /// The other.
        b: String,
    },
    /// The folder holds another protocol.
    #[error("{copy} holds another protocol than the one given; start a new --out folder for it")]
    OtherProtocol {
        /// The protocol's copy in the folder.
        copy: String,
    },
    /// A file could not be read or written.
    #[error("{0}")]
    File(String),
    /// A file or folder could not be read or written, or a participant's file is not one.
    #[error("{path}: {message}")]
    Io {
        /// The path.
        path: String,
        /// What went wrong, one line.
        message: String,
    },
    /// Refused by the layer beneath (the body reader), as it is.
    #[error(transparent)]
    Refused(#[from] Refusal),
}
