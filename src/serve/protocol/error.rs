//! Why a protocol request or a participant's file was refused: one enum for the room, each
//! variant one line. `serve/refusals.rs` gives each its HTTP status.

use crate::serve::http::refusal::Refusal;

/// Why a protocol request, or the protocol's folder, was refused.
#[derive(Debug, thiserror::Error)]
pub enum ParticipantError {
    /// The server runs no protocol.
    #[error("this server runs no protocol (start it with grove serve --protocol FILE)")]
    NoProtocol,
    /// A participant id unfit for a file name.
    #[error("a participant id is 1 to 32 letters, digits, '_' or '-', starting with a letter or digit")]
    BadId,
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
    #[error("participant {id} is at step {at}, not {step}")]
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
    #[error("{0}")]
    BadAnswer(String),
    /// The participant has finished.
    #[error("participant {0} has finished the protocol")]
    Finished(String),
    /// A task step whose session has not ended.
    #[error("step {step} is task {task}: its session has not ended yet")]
    TaskNotEnded {
        /// The step.
        step: usize,
        /// The task.
        task: String,
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
    /// A next request of another shape.
    #[error("send {{\"from\": N}}, the step the participant leaves")]
    FromShape,
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
