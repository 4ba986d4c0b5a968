//! Which session finishes a protocol's task step (`docs/protocol.md`, "Tasks"): the
//! participant's own session of that task, opened after the step began, and complete (its
//! footer written) or ended by its client with lines past its header. Any other session of the
//! participant's task, a recording pushed into the folder before the step, one left with only its
//! header, one abandoned before its end, is not this step's: the step is not finished by it, and
//! `/api/dashboard` lists it as such, with why.

use chrono::{DateTime, SubsecRound};

use crate::serve::sessions::registry::Entry;
use crate::serve::sessions::states::SessionState;

/// Whether a session was opened at or after `began` (both RFC 3339). A session listed with whole
/// seconds (as older folders have them) is compared to the second the step began in.
fn opened_after(opened: &str, began: &str) -> bool {
    match (DateTime::parse_from_rfc3339(opened), DateTime::parse_from_rfc3339(began)) {
        (Ok(o), Ok(b)) if opened.contains('.') => o >= b,
        (Ok(o), Ok(b)) => o >= b.trunc_subsecs(0),
        _ => false,
    }
}

/// Why a session of a task step's participant and task is not that step's (the step began at
/// `began`), or `None` when it finishes the step once ended (or, still open, may finish it).
pub fn not_this_steps(e: &Entry, began: &str) -> Option<&'static str> {
    if !opened_after(&e.opened, began) {
        return Some("opened before the step began");
    }
    let complete = e.verification.as_ref().is_some_and(|v| v.complete);
    match e.state {
        SessionState::Open => None,
        SessionState::Unresumable => Some("it could not be continued after a restart"),
        _ if e.lines <= 1 => Some("it has only its header"),
        _ if complete => None,
        SessionState::Ended => None,
        SessionState::Abandoned => Some("abandoned before its end"),
    }
}

/// Whether an ended session finishes the task step that began at `began`.
pub fn finishes(e: &Entry, began: &str) -> bool {
    e.state.is_closed() && not_this_steps(e, began).is_none()
}

/// How the dashboard lists a session of a task: `None` when it is (or may be) its task step's,
/// else why it is not this step's. `steps` are every participant's task steps (participant,
/// task, when it began).
pub fn listed(e: &Entry, steps: &[(String, String, Option<String>)]) -> Option<String> {
    let task = e.task.as_deref()?;
    let theirs: Vec<&Option<String>> = steps.iter().filter(|(p, t, _)| *p == e.participant && t == task).map(|(_, _, b)| b).collect();
    if theirs.is_empty() {
        return Some(if steps.iter().any(|(p, _, _)| *p == e.participant) { format!("{task} is not a task of {}", e.participant) } else { format!("no participant {} in the protocol", e.participant) });
    }
    // The step it may be: the last one of that task that began before it opened, else the first.
    let began: Vec<&String> = theirs.iter().filter_map(|b| b.as_ref()).collect();
    let step = began.iter().rev().find(|b| opened_after(&e.opened, b)).or(began.first());
    match step {
        None => Some("opened before the step began".into()),
        Some(b) => not_this_steps(e, b).map(str::to_string),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::serve::sessions::verify::Verification;

    fn entry(opened: &str, state: SessionState, lines: u64, complete: Option<bool>) -> Entry {
        let verification = complete.map(|complete| Verification { complete, ..Verification::invalid(String::new(), 0) });
        Entry { id: "0".repeat(32), file: "P01-manual-7-1.jsonl".into(), participant: "P01".into(), task: Some("manual-7".into()), opened: opened.into(), state, lines, closed: None, verification, note: None, identity: None }
    }

    #[test]
    fn only_a_session_opened_after_the_step_began_and_ended_with_more_than_its_header_finishes_it() {
        let began = "2026-12-01T09:30:00.250Z";
        let after = "2026-12-01T09:31:00.000Z";
        use SessionState::*;
        let cases = [
            (entry(after, Ended, 700, Some(true)), None),
            (entry(after, Ended, 40, Some(false)), None),
            (entry(after, Abandoned, 700, Some(true)), None),
            (entry(after, Open, 12, None), None),
            (entry("2026-12-01T09:29:59.999Z", Ended, 700, Some(true)), Some("opened before the step began")),
            (entry("2019-06-03T09:02:36Z", Ended, 700, Some(true)), Some("opened before the step began")),
            (entry("2026-12-01T09:30:00Z", Ended, 700, Some(true)), None),
            (entry("2026-12-01T09:29:59Z", Ended, 700, Some(true)), Some("opened before the step began")),
            (entry(after, Ended, 1, Some(false)), Some("it has only its header")),
            (entry(after, Abandoned, 1, Some(false)), Some("it has only its header")),
            (entry(after, Abandoned, 300, Some(false)), Some("abandoned before its end")),
            (entry(after, Unresumable, 300, None), Some("it could not be continued after a restart")),
        ];
        for (e, why) in cases {
            assert_eq!(not_this_steps(&e, began), why, "{} {:?} {} lines", e.opened, e.state, e.lines);
            assert_eq!(finishes(&e, began), why.is_none() && e.state != Open, "{} {:?}", e.opened, e.state);
        }
    }
}
