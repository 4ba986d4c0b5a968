//! A replay's outcome in one word, the same for every tool that says it: `grove replay --json`,
//! `node web/replay.mjs --json` (the WebAssembly module) and `grove serve`'s verification of a
//! session (`docs/replay-format.md`).

/// A recording's replay in one word.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Every checkpoint compared and the footer's final hash agree.
    Verified,
    /// No checkpoint was compared (an event-only file, a session with only its header).
    Unverified,
    /// No footer: every checkpoint compared agrees, up to the file's last one.
    Incomplete,
    /// A checkpoint differs.
    Diverged,
}

impl Verdict {
    /// What a replay found: whether a checkpoint differed, whether the file has its footer, and
    /// how many checkpoints were compared (the footer's final hash included).
    pub fn of(diverged: bool, complete: bool, checkpoints_checked: u64) -> Verdict {
        if diverged {
            Verdict::Diverged
        } else if checkpoints_checked == 0 {
            Verdict::Unverified
        } else if !complete {
            Verdict::Incomplete
        } else {
            Verdict::Verified
        }
    }

    /// The word the reports use.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Verified => "verified",
            Verdict::Unverified => "unverified",
            Verdict::Incomplete => "incomplete",
            Verdict::Diverged => "diverged",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_without_a_footer_is_incomplete_once_a_checkpoint_was_compared() {
        assert_eq!(Verdict::of(false, true, 88), Verdict::Verified);
        assert_eq!(Verdict::of(false, false, 40), Verdict::Incomplete);
        assert_eq!(Verdict::of(false, false, 0), Verdict::Unverified);
        assert_eq!(Verdict::of(false, true, 0), Verdict::Unverified);
        assert_eq!(Verdict::of(true, false, 3), Verdict::Diverged);
    }
}
