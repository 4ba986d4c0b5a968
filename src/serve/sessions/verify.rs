//! A session's verification: the file re-simulated natively, as `grove replay` does (or its
//! lines replayed as they came, [`crate::serve::sessions::live`]): verified,
//! unverified (no checkpoint to compare), incomplete (no footer: verified up to its last
//! checkpoint), diverged (the first checkpoint that differs) or invalid (the replay refused the
//! file, which the line checks should have made impossible).

use std::path::{Path, PathBuf};

use grove_systems::replay::verdict::Verdict;
use grove_systems::replay::{replay_file, Divergence, ReplayOptions};
use serde::{Deserialize, Serialize};

use crate::serve::sessions::states::VerifyStatus;

/// The first checkpoint at which the re-simulation and the file disagree.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FirstDivergence {
    /// Its tick.
    pub tick: u64,
    /// The hash in the file.
    pub expected_hash: String,
    /// The re-simulated hash.
    pub actual_hash: String,
}

/// What the re-simulation of a session's file found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Verification {
    /// Verified, unverified, incomplete, diverged or invalid.
    pub status: VerifyStatus,
    /// Whether the file has its footer.
    pub complete: bool,
    /// Checkpoints compared (the footer's final hash included).
    pub checkpoints_checked: u64,
    /// For a file without a divergence: the tick up to which the world was verified (its last
    /// checkpoint, or its footer's final tick).
    pub verified_to_tick: Option<u64>,
    /// The tick the replay reached.
    pub last_tick: u64,
    /// The first divergence, if any.
    pub first_divergence: Option<FirstDivergence>,
    /// Why the replay refused the file (status `invalid`).
    pub error: Option<String>,
}

impl Verification {
    /// A file the replay refused (or that could not be read back), with why.
    pub fn invalid(error: String, last_tick: u64) -> Verification {
        Verification { status: VerifyStatus::Invalid, complete: false, checkpoints_checked: 0, verified_to_tick: None, last_tick, first_divergence: None, error: Some(error) }
    }

    /// One line for the terminal.
    pub fn summary(&self) -> String {
        match self.status {
            VerifyStatus::Verified => format!("verified ({} checkpoints, final tick {})", self.checkpoints_checked, self.last_tick),
            VerifyStatus::Unverified => format!("unverified (no checkpoint to compare; tick {})", self.last_tick),
            VerifyStatus::Incomplete => format!(
                "incomplete (no footer): verified to tick {}, its last checkpoint ({} checkpoints); the file ends at tick {}",
                self.verified_to_tick.unwrap_or(0),
                self.checkpoints_checked,
                self.last_tick
            ),
            VerifyStatus::Diverged => match &self.first_divergence {
                Some(d) => format!("diverged at tick {} (the file has {}, the re-simulation {})", d.tick, d.expected_hash, d.actual_hash),
                None => "diverged".into(),
            },
            VerifyStatus::Invalid => format!("invalid: {}", self.error.as_deref().unwrap_or("?")),
        }
    }
}

/// Re-simulates a session's file with these model banks. `last_tick` and `last_checkpoint` are
/// the ticks of the file's last line and last checkpoint line (0 for none), as the server wrote
/// them.
pub fn verify(path: &Path, banks: &[PathBuf], last_tick: u64, last_checkpoint: u64) -> Verification {
    let options = ReplayOptions { banks: banks.to_vec(), ..ReplayOptions::default() };
    match replay_file(path, &options) {
        Err(e) => Verification::invalid(e.to_string(), last_tick),
        Ok(out) => Verification::found(out.complete, out.checkpoints_checked, out.first_divergence.as_ref(), last_tick, last_checkpoint),
    }
}

impl Verification {
    /// What a replay found, the file's last line and last checkpoint being at these ticks:
    /// the status by the rule `grove replay --json` follows too ([`Verdict::of`]).
    pub fn found(complete: bool, checkpoints_checked: u64, divergence: Option<&Divergence>, last_tick: u64, last_checkpoint: u64) -> Verification {
        let first_divergence = divergence.map(|d| FirstDivergence { tick: d.tick, expected_hash: d.expected_hash.clone(), actual_hash: d.actual_hash.clone() });
        let status = VerifyStatus::of(Verdict::of(first_divergence.is_some(), complete, checkpoints_checked));
        let verified_to_tick = match (&first_divergence, complete) {
            (Some(_), _) => None,
            (None, true) => Some(last_tick),
            (None, false) => Some(last_checkpoint),
        };
        Verification { status, complete, checkpoints_checked, verified_to_tick, last_tick, first_divergence, error: None }
    }
}
