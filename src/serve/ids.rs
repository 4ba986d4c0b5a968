//! The names the server makes: session ids and tokens from the operating system's random
//! source, and a recording's file name from a participant and task id it has validated. No name
//! a client sends ever becomes a path: a participant id is a plain word checked here, a task id
//! must be a built-in task's, and the number is the server's own count.

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

/// The longest participant id, characters.
pub const MAX_PARTICIPANT: usize = 32;

/// Where a file name part is refused: which field and why, one line.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{field} {value:?} is not allowed: {why}")]
pub struct BadId {
    /// The field, e.g. "participant".
    pub field: &'static str,
    /// The value as sent (control characters shown escaped by `{:?}`).
    pub value: String,
    /// Why.
    pub why: &'static str,
}

/// Why a name could not be made: no random bytes, or no file for a session.
#[derive(Debug, thiserror::Error)]
pub enum IdError {
    /// The operating system gave no random bytes.
    #[error("cannot draw random bytes from the operating system: {0}")]
    Random(String),
    /// A session's file could not be made.
    #[error("{path}: {message}")]
    File {
        /// The path (or the folder, when every name is taken).
        path: String,
        /// What went wrong, one line.
        message: String,
    },
}

/// Checks a participant id: 1 to [`MAX_PARTICIPANT`] ASCII letters, digits, `_` or `-`, starting
/// with a letter or digit (so `P01`, `p-7`; never `..`, a slash or a dot).
pub fn participant(id: &str) -> Result<&str, BadId> {
    let bad = |why| BadId { field: "participant", value: id.chars().take(80).collect(), why };
    if id.is_empty() || id.len() > MAX_PARTICIPANT {
        return Err(bad("it must be 1 to 32 characters long"));
    }
    if !id.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-') || !id.as_bytes()[0].is_ascii_alphanumeric() {
        return Err(bad("only letters, digits, '_' and '-' are allowed, starting with a letter or digit"));
    }
    Ok(id)
}

/// The task part of a file name: a built-in task's id, or `free` for a session without a task.
pub fn task_part(task: Option<&str>) -> Result<String, BadId> {
    match task {
        None => Ok("free".into()),
        Some(t) if grove_systems::task::TaskDef::builtin(t).is_some() && t.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-') => Ok(t.to_string()),
        Some(t) => Err(BadId { field: "task", value: t.chars().take(80).collect(), why: "it is not a built-in task" }),
    }
}

/// Creates the session's file `DIR/<participant>-<task>-<n>.jsonl` with the first `n` (from 1)
/// whose name is free, refusing to reuse a name (a file created meanwhile by another session
/// is skipped). Returns the open file and its path.
pub fn create_session_file(dir: &Path, participant: &str, task: &str) -> Result<(File, PathBuf), IdError> {
    for n in 1..=100_000u32 {
        let path = dir.join(format!("{participant}-{task}-{n}.jsonl"));
        match OpenOptions::new().append(true).create_new(true).open(&path) {
            Ok(f) => return Ok((f, path)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(IdError::File { path: path.display().to_string(), message: e.to_string() }),
        }
    }
    Err(IdError::File { path: dir.display().to_string(), message: format!("100000 files of {participant}-{task} already; use another folder") })
}

/// `n` random bytes from the operating system as lowercase hex.
pub fn random_hex(n: usize) -> Result<String, IdError> {
    let mut bytes = vec![0u8; n];
    getrandom::fill(&mut bytes).map_err(|e| IdError::Random(e.to_string()))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// Whether two secrets are equal, in time that does not depend on where they first differ.
pub fn same_secret(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// Whether a text is a secret of the server's own form (32 lowercase hex digits: 128 bits from
/// [`random_hex`]), as session ids and tokens are.
pub fn is_secret(text: &str) -> bool {
    text.len() == 32 && text.bytes().all(|b| b.is_ascii_hexdigit() && !b.is_ascii_uppercase())
}

/// Whether a session id is of the server's own form, checked before any lookup.
pub fn is_session_id(id: &str) -> bool {
    is_secret(id)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn participant_ids_are_plain_words() {
        for ok in ["P01", "p-7", "a_b", "X"] {
            assert_eq!(participant(ok), Ok(ok));
        }
        for bad in ["", "../../etc/x", "..", ".hidden", "a/b", "a\\b", "a b", "-x", "é", "a\0", &"x".repeat(33)] {
            assert!(participant(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn task_parts_are_built_in_tasks_or_free() {
        assert_eq!(task_part(None).unwrap(), "free");
        assert_eq!(task_part(Some("ray-casting-7")).unwrap(), "ray-casting-7");
        assert!(task_part(Some("../x")).is_err());
        assert!(task_part(Some("manual-8")).is_err());
    }

    #[test]
    fn file_names_count_up_and_never_reuse_a_name() {
        let dir = tempfile::tempdir().unwrap();
        let (_, a) = create_session_file(dir.path(), "P01", "manual-7").unwrap();
        let (_, b) = create_session_file(dir.path(), "P01", "manual-7").unwrap();
        std::fs::write(dir.path().join("P02-free-1.jsonl"), b"x").unwrap();
        let (_, c) = create_session_file(dir.path(), "P02", "free").unwrap();
        let name = |p: &PathBuf| p.file_name().unwrap().to_string_lossy().into_owned();
        assert_eq!([name(&a), name(&b), name(&c)], ["P01-manual-7-1.jsonl", "P01-manual-7-2.jsonl", "P02-free-2.jsonl"]);
        assert_eq!(std::fs::read(dir.path().join("P02-free-1.jsonl")).unwrap(), b"x", "an existing file is left alone");
    }

    #[test]
    fn secrets_compare_whole_and_session_ids_have_one_form() {
        assert!(same_secret("abc", "abc") && !same_secret("abc", "abd") && !same_secret("abc", "abcd"));
        let id = random_hex(16).unwrap();
        assert!(is_session_id(&id), "{id}");
        assert_ne!(id, random_hex(16).unwrap());
        assert!(!is_session_id("../../etc/passwd") && !is_session_id(&id.to_uppercase()));
    }
}
