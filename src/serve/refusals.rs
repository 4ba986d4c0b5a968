//! The one place where a session or protocol error becomes an HTTP refusal: its status, its
//! reason (the error's one line) and the fields a client acts on (`acked`, `code`, `state`,
//! `verification`). `docs/serve.md` and `docs/protocol.md` list the statuses.

use serde_json::json;

use crate::serve::http::refusal::Refusal;
use crate::serve::protocol::error::ParticipantError;
use crate::serve::sessions::error::SessionError;
use crate::serve::sessions::states::Code;

impl From<SessionError> for Refusal {
    fn from(e: SessionError) -> Refusal {
        use SessionError as E;
        match e {
            E::Refused(r) => r,
            E::Stopped { acked, cause } => Refusal::from(*cause).with("acked", acked),
            e => {
                let r = Refusal::new(session_status(&e), e.to_string());
                match e {
                    E::Busy | E::InProgress => r.with("code", json!(Code::Busy)),
                    E::Writer { acked, .. } => r.with("acked", acked).with("code", json!(Code::Writer)),
                    E::Gap { acked } => r.with("acked", acked).with("code", json!(Code::Gap)),
                    E::Broken { acked, .. } => r.with("acked", acked),
                    E::Gone { state, acked, verification, .. } => r.with("acked", acked).with("state", json!(state)).with("verification", json!(verification)),
                    _ => r,
                }
            }
        }
    }
}

/// The HTTP status of a session error.
fn session_status(e: &SessionError) -> u16 {
    use SessionError as E;
    match e {
        E::Refused(r) => r.status,
        E::Stopped { cause, .. } => session_status(cause),
        E::HeaderLines | E::Header(_) | E::NoParticipant | E::BadId(_) | E::SceneTwice | E::Scene(_) | E::Technique(_) => 400,
        E::HeaderAndFields | E::HeaderNotText | E::ContinueNotBool | E::ContinueWithFields | E::Fields(_) | E::NoNewline { .. } | E::NoWriter { .. } | E::BadWriter | E::NoFrom => 400,
        E::NoSuchSession | E::BuiltinScene(_) | E::NoSceneFile(_) => 404,
        E::Busy | E::InProgress | E::Writer { .. } | E::Gap { .. } => 409,
        E::Gone { .. } | E::Ended => 410,
        E::HeaderTooLong { .. } | E::LineTooLong { .. } => 413,
        E::RecordingFull { .. } | E::Line { .. } | E::NotUtf8 { .. } => 422,
        E::Full { .. } => 503,
        E::Name(_) | E::HeaderWrite { .. } | E::Write { .. } | E::Broken { .. } | E::Io { .. } | E::FileLine { .. } | E::NoHeader { .. } | E::Cut { .. } | E::Banks(_) | E::Read(_) | E::Task(_) => 500,
    }
}

impl From<ParticipantError> for Refusal {
    fn from(e: ParticipantError) -> Refusal {
        use ParticipantError as E;
        let status = match &e {
            E::Refused(r) => return r.clone(),
            E::BadId | E::IdNotText(_) | E::JoinShape(_) | E::NoAnswers | E::AnswersShape | E::FromShape | E::StepNotNumber { .. } => 400,
            E::NoProtocol | E::Unknown(_) | E::NoMedia { .. } | E::Media(_) => 404,
            E::AllJoined { .. } | E::IdInUse { .. } | E::WrongStep { .. } | E::NotAQuestionnaire { .. } | E::Finished(_) | E::TaskNotEnded { .. } | E::NotAnswered { .. } => 409,
            E::TooManyAnswers { .. } => 413,
            E::NoSuchItem { .. } | E::BadAnswer(_) => 422,
            E::InstrumentGone | E::OtherProtocol { .. } | E::FileId { .. } | E::RepeatedId { .. } | E::CaseClash { .. } | E::File(_) | E::Io { .. } => 500,
        };
        Refusal::new(status, e.to_string())
    }
}
