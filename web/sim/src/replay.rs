//! A verifying replay of a recording handed over as bytes: the same reader, checks and
//! re-simulation as `grove replay`, and the same report (grove-systems' [`ReplayReport`], the
//! fields of `grove replay --json`), less the wall-clock figures, which JavaScript measures.

use grove_systems::replay::{decode_line, replay_reader, Line, ReplayOptions, ReplayReport};
use serde::{Deserialize, Serialize};

use crate::error::Error;

/// What a replay is asked.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReplayArgs {
    /// The recording's name in messages (its path, as `grove replay` names it).
    #[serde(default)]
    pub file: String,
    /// The text of the scene file the header names, when it is not a built-in scene.
    pub scene_text: Option<String>,
    /// Stop at this tick.
    pub until: Option<u64>,
}

/// The report and the task's one-line result, as `grove replay` prints it.
#[derive(Debug, Serialize)]
pub struct Replayed {
    /// The report.
    pub report: ReplayReport,
    /// `grove replay`'s line about the task, if the session ran one.
    pub task_line: Option<String>,
}

/// Replays `recording` and verifies its checkpoints.
pub fn replay(args: &ReplayArgs, recording: &[u8]) -> Result<Replayed, Error> {
    crate::install_techniques();
    let mut options = ReplayOptions { until: args.until, ..Default::default() };
    if let Some(text) = &args.scene_text {
        // Named as the header names it (a header that does not read is refused by the reader
        // below, with its line number).
        let first = recording.split(|b| *b == b'\n').next().unwrap_or_default();
        let name = match std::str::from_utf8(first).ok().map(decode_line) {
            Some(Ok(Line::Header(h))) => h.scene,
            _ => String::new(),
        };
        if !name.is_empty() {
            options.scene = Some(crate::options::scene(&name, Some(text))?);
        }
    }
    let outcome = replay_reader(recording, &args.file, None, &options)?;
    let report = ReplayReport::new(args.file.clone(), &outcome);
    Ok(Replayed { task_line: report.task.as_ref().map(|t| t.result_line()), report })
}
