//! The verifying reader: re-simulates a recording file from its header and compares every
//! checkpoint, by handing each line to [`super::verifier::Verifier`]. The lines themselves are
//! checked by [`super::lines`] before any simulation.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;

use super::lines::{checkpoint_of, Checked, LineError, Lines};
use super::verifier::{Divergence, Verifier};
use super::{sim_for_header_in, Header, Line};
use crate::input::StampedEvent;
use crate::resources::Override;
use crate::sim::Sim;

/// A replay input problem: which line, and what. Its `Display` is one line: control characters
/// the recording may have put into the message are shown as spaces.
#[derive(Debug, thiserror::Error)]
#[error("{file}{}: {}", line.map(|l| format!(":{l}")).unwrap_or_default(), message.replace(|c: char| c.is_control(), " "))]
pub struct ReplayError {
    /// The file.
    pub file: String,
    /// The 1-based line number, where one applies.
    pub line: Option<u64>,
    /// What is wrong.
    pub message: String,
}

/// The outcome of a replay.
pub struct ReplayOutcome {
    /// The header.
    pub header: Header,
    /// The simulation at the end of the replay.
    pub sim: Sim,
    /// Whether the file had a footer (and `--until` did not stop early).
    pub complete: bool,
    /// Checkpoints compared (including the footer's final hash).
    pub checkpoints_checked: u64,
    /// The first divergence, if any. The replay goes on to the end of the file, but compares no
    /// further checkpoints.
    pub first_divergence: Option<Divergence>,
    /// Event counts by kind.
    pub events: BTreeMap<String, u64>,
    /// Whether checkpoints were compared at all (false for what-if runs).
    pub verifying: bool,
}

/// Options of a replay.
#[derive(Clone, Debug, Default)]
pub struct ReplayOptions {
    /// Stop at this tick.
    pub until: Option<u64>,
    /// Config overrides (what-if): checkpoints are then not compared.
    pub overrides: Vec<Override>,
    /// The model-bank folders in which the header's models are looked up.
    pub banks: Vec<std::path::PathBuf>,
    /// The scene, already read, in place of the one the header names (which is then not looked
    /// up): for a reader without a file system.
    pub scene: Option<crate::scene::Scene>,
}

/// Replays a recording from a reader. `file` names it in errors; `base_dir` is the recording's
/// folder, where a scene file it names may lie. Checkpoints are verified unless
/// `options.overrides` is non-empty (a what-if run).
pub fn replay_reader<R: Read>(reader: R, file: &str, base_dir: Option<&Path>, options: &ReplayOptions) -> Result<ReplayOutcome, ReplayError> {
    let err = |(line, message): LineError| ReplayError { file: file.to_string(), line, message };
    let mut lines = Lines::open(reader).map_err(err)?;
    // A checkpoint's per-component and per-entity hashes are read only at a divergence.
    lines.checkpoint_maps_when_needed();
    // And only a checkpoint's body is read again (at a divergence).
    lines.keep_checkpoint_bodies_only();
    let header = lines.header.clone();
    let verifying = options.overrides.is_empty();
    let banks = crate::bank::Banks::open(&options.banks).map_err(|m| err((None, m.0)))?;
    let built = match &options.scene {
        Some(scene) => super::sim_for_header_with_scene(&header, scene.clone(), &options.overrides, &banks),
        None => sim_for_header_in(&header, base_dir, &options.overrides, &banks),
    };
    let sim = built.map_err(|m| err((Some(1), m.to_string())))?;
    let mut verifier = Verifier::new(sim, verifying);
    // Counted by the kind's static name, and named as `String`s once at the end.
    let mut counts: BTreeMap<&'static str, u64> = BTreeMap::new();
    let mut stopped_early = false;
    let until = options.until.unwrap_or(u64::MAX);

    // Steps are bounded: `Lines` refuses a tick more than a checkpoint interval past the last
    // checkpoint, and any tick past the limit.
    while let Some(Checked { number: n, line, tick, body }) = lines.next().map_err(err)? {
        if tick > until {
            stopped_early = true;
            break;
        }
        if let Line::Event(e) = &line {
            *counts.entry(e.event.kind()).or_default() += 1;
        }
        verifier.take(line, tick, || checkpoint_of(&body), |_| {}).map_err(|m| err((Some(n), m.to_string())))?;
    }
    if stopped_early {
        // `until` is below a tick that `Lines` accepted, so this is bounded too.
        verifier.advance(until, |_| {});
    }
    let complete = verifier.complete();
    let (sim, checkpoints_checked, first_divergence) = verifier.finish();
    let events = counts.into_iter().map(|(k, n)| (k.to_string(), n)).collect();
    Ok(ReplayOutcome { header, sim, complete: complete && !stopped_early, checkpoints_checked, first_divergence, events, verifying })
}

/// Replays a recording file. Directories, missing files and unreadable files give an error.
pub fn replay_file(path: &Path, options: &ReplayOptions) -> Result<ReplayOutcome, ReplayError> {
    let file = path.display().to_string();
    let (f, _) = crate::files::open(path, crate::files::Kind::Recording).map_err(|e| ReplayError { file: file.clone(), line: None, message: e.reason() })?;
    replay_reader(f, &file, path.parent(), options)
}

/// Reads just the stamped events of a recording (no simulation), e.g. to re-record or edit it.
/// Every line is checked as [`replay_file`] checks it.
pub fn read_events(path: &Path) -> Result<(Header, Vec<StampedEvent>), ReplayError> {
    let file = path.display().to_string();
    let err = |(line, message): LineError| ReplayError { file: file.clone(), line, message };
    let (f, _) = crate::files::open(path, crate::files::Kind::Recording).map_err(|e| err((None, e.reason())))?;
    let mut lines = Lines::open(f).map_err(err)?;
    let mut events = Vec::new();
    while let Some(checked) = lines.next().map_err(err)? {
        if let Line::Event(e) = checked.line {
            events.push(StampedEvent { tick: e.tick, event: e.event });
        }
    }
    Ok((lines.header.clone(), events))
}
