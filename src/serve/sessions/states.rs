//! The states a session and its verification are in, as `sessions.json` and the API write them
//! (`docs/serve.md`, "The folder it writes"), and the codes of a refused session request: the
//! serde names are the words the files and answers have always had.

use serde::{Deserialize, Serialize};

/// Where a session is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SessionState {
    /// Being written; continued after a restart.
    Open,
    /// Its client ended it.
    Ended,
    /// No request for `--abandon-after`: the server ended it.
    Abandoned,
    /// After a restart its file no longer kept the rules (the entry's `note` says why).
    Unresumable,
}

impl SessionState {
    /// The word the files use.
    pub fn as_str(self) -> &'static str {
        match self {
            SessionState::Open => "open",
            SessionState::Ended => "ended",
            SessionState::Abandoned => "abandoned",
            SessionState::Unresumable => "unresumable",
        }
    }

    /// Whether the session was ended (by its client or as abandoned): it is verified, and a
    /// protocol's task step with it is finished.
    pub fn is_closed(self) -> bool {
        matches!(self, SessionState::Ended | SessionState::Abandoned)
    }
}

impl std::fmt::Display for SessionState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What the re-simulation of an ended session's file found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum VerifyStatus {
    /// Every checkpoint and the footer's final hash agree.
    Verified,
    /// No checkpoint to compare (a session with only its header, too).
    Unverified,
    /// No footer: verified to its last checkpoint.
    Incomplete,
    /// A checkpoint differs (the first is named).
    Diverged,
    /// The replay refused the file.
    Invalid,
}

impl VerifyStatus {
    /// The word the files use.
    pub fn as_str(self) -> &'static str {
        match self {
            VerifyStatus::Verified => "verified",
            VerifyStatus::Unverified => "unverified",
            VerifyStatus::Incomplete => "incomplete",
            VerifyStatus::Diverged => "diverged",
            VerifyStatus::Invalid => "invalid",
        }
    }

    /// The status of a file the replay read (every one but `invalid`), by the rule `grove replay
    /// --json` follows too.
    pub fn of(verdict: grove_systems::replay::verdict::Verdict) -> VerifyStatus {
        use grove_systems::replay::verdict::Verdict as V;
        match verdict {
            V::Verified => VerifyStatus::Verified,
            V::Unverified => VerifyStatus::Unverified,
            V::Incomplete => VerifyStatus::Incomplete,
            V::Diverged => VerifyStatus::Diverged,
        }
    }

    /// Whether the file failed (diverged or invalid), as `grove serve push` exits 1 for.
    pub fn failed(self) -> bool {
        matches!(self, VerifyStatus::Diverged | VerifyStatus::Invalid)
    }
}

impl std::fmt::Display for VerifyStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Why a request on a session was refused, for a client that acts on it: the `code` of a 409
/// answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Code {
    /// Another request on the session is in progress: ask again.
    Busy,
    /// Another client writes the session.
    Writer,
    /// The batch does not start at the file's next line: `acked` says where it does.
    Gap,
}

#[cfg(test)]
mod tests {
    use super::*;

    // The words of docs/serve.md's `sessions.json` table and its 409 codes, written out here as
    // the files have them: every state, status and code written as its word and read back.
    const STATES: [(SessionState, &str); 4] = [(SessionState::Open, "open"), (SessionState::Ended, "ended"), (SessionState::Abandoned, "abandoned"), (SessionState::Unresumable, "unresumable")];
    const STATUSES: [(VerifyStatus, &str); 5] = [
        (VerifyStatus::Verified, "verified"),
        (VerifyStatus::Unverified, "unverified"),
        (VerifyStatus::Incomplete, "incomplete"),
        (VerifyStatus::Diverged, "diverged"),
        (VerifyStatus::Invalid, "invalid"),
    ];

    #[test]
    fn every_state_and_status_is_written_and_read_as_the_word_the_files_have() {
        for (state, word) in STATES {
            assert_eq!(serde_json::to_string(&state).unwrap(), format!("\"{word}\""));
            assert_eq!(serde_json::from_str::<SessionState>(&format!("\"{word}\"")).unwrap(), state);
            assert_eq!(state.to_string(), word);
        }
        for (status, word) in STATUSES {
            assert_eq!(serde_json::to_string(&status).unwrap(), format!("\"{word}\""));
            assert_eq!(serde_json::from_str::<VerifyStatus>(&format!("\"{word}\"")).unwrap(), status);
            assert_eq!(status.to_string(), word);
        }
        for (code, word) in [(Code::Busy, "busy"), (Code::Writer, "writer"), (Code::Gap, "gap")] {
            assert_eq!(serde_json::to_value(code).unwrap(), serde_json::json!(word));
            assert_eq!(serde_json::from_value::<Code>(serde_json::json!(word)).unwrap(), code);
        }
        assert!(serde_json::from_str::<SessionState>("\"Open\"").is_err(), "only the files' words are read");
        assert!(serde_json::from_str::<VerifyStatus>("\"ok\"").is_err());
    }
}
