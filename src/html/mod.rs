//! The self-contained HTML reports: `grove study … --html` (`report.html`: the overview, the
//! task area from above, every trial) and `grove replay FILE --html OUT.html` (one trial, with
//! its divergence). One file each, no network: the charts are SVG, the pictures JPEG data URIs,
//! the script inline (`report.js`), the style inline (`report.css`). `docs/reports.md` describes
//! what the page shows and where each figure's data come from.
//!
//! The study's numbers are the ones `summary.json` holds; what they do not keep (where the ray
//! hit, the paths of moved trees, the log, the presses) comes from one more re-simulation of
//! each recording ([`trace`]), and the pictures from the renderer ([`shots`]).

pub mod area;
pub mod figures;
pub mod page;
pub mod questionnaire;
pub mod scenario_trace;
pub mod sections;
pub mod shots;
pub mod trace;

use std::path::{Path, PathBuf};

use grove_systems::replay::Divergence;
use grove_systems::resources::Override;
use rayon::prelude::*;

use crate::study::report::{Summary, incomplete_reason};
use crate::study::whatif::{Sweep, WhatIf};
use crate::study::{Trial, TrialStatus};
use trace::{Moment, Trace};

/// Why a report could not be made.
#[derive(Debug, thiserror::Error)]
pub enum HtmlError {
    /// `--html-trials` names a participant the study does not have.
    #[error("--html-trials: no participant {0} among the recordings")]
    UnknownParticipant(String),
    /// `--html-trials` is empty.
    #[error("--html-trials: give participant ids separated by commas (e.g. P03,P07), or all")]
    EmptySelection,
    /// The page could not be written.
    #[error("{path}: cannot write the report ({reason})")]
    Write {
        /// The file.
        path: String,
        /// Why.
        reason: String,
    },
    /// A picture could not be encoded as JPEG.
    #[error("JPEG encoding: {0}")]
    Jpeg(image::ImageError),
    /// The GPU or the renderer failed.
    #[error(transparent)]
    Render(#[from] crate::render::RenderError),
    /// A picture was asked for before its renderer was made.
    #[error("no renderer")]
    NoRenderer,
    /// The session's model banks could not be opened or loaded.
    #[error(transparent)]
    Bank(#[from] crate::bank::BankError),
    /// The recording could not be replayed.
    #[error(transparent)]
    Replay(#[from] grove_systems::replay::ReplayError),
}

/// Which trials get a section of their own (timeline, filmstrip, numbers).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Selection {
    /// Every trial up to [`AUTO_ALL`] recordings; beyond, the three slowest completed trials per
    /// condition and every trial left out of the comparisons.
    Auto,
    /// Every trial.
    All,
    /// The trials of these participants.
    Participants(Vec<String>),
}

/// Up to this many recordings, every trial gets its section by default.
pub const AUTO_ALL: usize = 50;

impl std::str::FromStr for Selection {
    type Err = HtmlError;
    fn from_str(s: &str) -> Result<Selection, HtmlError> {
        if s.trim() == "all" {
            return Ok(Selection::All);
        }
        let ids: Vec<String> = s.split(',').map(|x| x.trim().to_string()).filter(|x| !x.is_empty()).collect();
        if ids.is_empty() {
            return Err(HtmlError::EmptySelection);
        }
        Ok(Selection::Participants(ids))
    }
}

/// Which of `trials` get a section.
pub fn selected(trials: &[Trial], selection: &Selection) -> Result<Vec<bool>, HtmlError> {
    match selection {
        Selection::All => Ok(vec![true; trials.len()]),
        Selection::Auto if trials.len() <= AUTO_ALL => Ok(vec![true; trials.len()]),
        Selection::Participants(ids) => {
            if let Some(missing) = ids.iter().find(|id| !trials.iter().any(|t| &t.participant == *id)) {
                return Err(HtmlError::UnknownParticipant(missing.clone()));
            }
            Ok(trials.iter().map(|t| ids.contains(&t.participant)).collect())
        }
        Selection::Auto => {
            let mut pick: Vec<bool> = trials.iter().map(|t| incomplete_reason(t).is_some()).collect();
            let mut conditions: Vec<&str> =
                trials.iter().filter_map(|t| t.task.as_ref().map(|k| k.mode.as_str())).collect();
            conditions.sort_unstable();
            conditions.dedup();
            for c in conditions {
                let mut done: Vec<(usize, f64)> = trials
                    .iter()
                    .enumerate()
                    .filter(|(_, t)| t.task.as_ref().is_some_and(|k| k.mode == c))
                    .filter_map(|(i, t)| crate::study::report::usable_time(t).map(|s| (i, s)))
                    .collect();
                done.sort_by(|a, b| b.1.total_cmp(&a.1));
                for (i, _) in done.into_iter().take(3) {
                    pick[i] = true;
                }
            }
            Ok(pick)
        }
    }
}

/// One trial as the page shows it.
pub struct TrialView {
    /// The study's trial (its numbers are summary.json's).
    pub trial: Trial,
    /// The recording, as the commands on the page name it.
    pub path: PathBuf,
    /// The re-simulation's trace (none for a failed trial).
    pub trace: Option<Trace>,
    /// Why there is no trace, when there is none.
    pub trace_error: Option<String>,
    /// The filmstrip: each moment with its picture (a data URI).
    pub frames: Vec<(Moment, String)>,
    /// Whether the trial has a section of its own.
    pub detailed: bool,
    /// The first divergence, with the entities and components that differ (`grove replay`).
    pub divergence: Option<Divergence>,
}

impl TrialView {
    /// The section's anchor: the file name without `.jsonl`, in safe characters.
    pub fn anchor(&self) -> String {
        let stem = self.trial.file.trim_end_matches(".jsonl");
        format!(
            "t-{}",
            stem.chars()
                .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' })
                .collect::<String>()
        )
    }

    /// The condition: the task's mode or technique, or `no task`.
    pub fn condition(&self) -> String {
        self.trial.task.as_ref().map_or_else(|| "no task".to_string(), |k| k.mode.clone())
    }
}

/// At most this many filmstrip frames per trial.
pub const MAX_FRAMES: usize = 24;

/// Re-simulates one trial for the page; with `shots`, renders its filmstrip (and the moments
/// in `extra`).
pub fn view_trial(
    trial: Trial,
    path: PathBuf,
    overrides: &[Override],
    detailed: bool,
    extra: &[Moment],
    shots: Option<&mut shots::Shots>,
    pictures: &mut Option<String>,
) -> TrialView {
    let mut view =
        TrialView { trial, path, trace: None, trace_error: None, frames: Vec::new(), detailed, divergence: None };
    if view.trial.status == TrialStatus::Failed {
        view.trace_error = view.trial.error.clone();
        return view;
    }
    let banks = match crate::bank::open_session(&[]) {
        Ok(b) => b,
        Err(e) => {
            view.trace_error = Some(e.to_string());
            return view;
        }
    };
    let mut frames = Vec::new();
    let mut shots = if detailed { shots } else { None };
    let mut shoot = |sim: &grove_systems::Sim, m: &Moment| -> Result<(), HtmlError> {
        if let Some(s) = shots.as_deref_mut()
            && pictures.is_none()
            && (frames.len() < MAX_FRAMES || extra.iter().any(|e| e.tick == m.tick))
        {
            match s.frame(sim) {
                Ok(uri) => frames.push((m.clone(), uri)),
                // The first failure turns the pictures off, and the page says why.
                Err(e) => *pictures = Some(e.to_string()),
            }
        }
        Ok(())
    };
    match trace::trace(&view.path, overrides, &banks, view.trial.ticks, extra, &mut shoot) {
        Ok(t) => view.trace = Some(t),
        Err(e) => view.trace_error = Some(e.to_string()),
    }
    view.frames = frames;
    view
}

/// Everything the study's page shows.
pub struct StudyPage<'a> {
    /// The summary (`summary` of summary.json).
    pub summary: &'a Summary,
    /// The what-if, if the run was one.
    pub what_if: Option<&'a WhatIf>,
    /// The sweep, if the run was one.
    pub sweep: Option<&'a Sweep>,
    /// The charts as SVG text, each with its title.
    pub charts: Vec<(String, String)>,
    /// The `--replays` folder.
    pub replays: String,
    /// The overrides the trials ran under.
    pub overrides: &'a [Override],
    /// The questionnaires of a protocol's folder, if any.
    pub questionnaires: Option<&'a crate::study::questionnaire::Questionnaires>,
}

/// Writes `html` to `path` through a temporary file and a rename.
pub fn write_page(path: &Path, html: &str) -> Result<(), HtmlError> {
    crate::atomic_write::write_atomic(path, html.as_bytes())
        .map_err(|e| HtmlError::Write { path: path.display().to_string(), reason: e.to_string() })
}

/// The study's report: traces every trial (rendering the filmstrips of the selected ones and
/// the task area from above), writes `report.html` into `out`. Returns the file.
pub fn write_study(
    out: &Path,
    page: &StudyPage<'_>,
    trials: &[Trial],
    selection: &Selection,
) -> Result<PathBuf, HtmlError> {
    let pick = selected(trials, selection)?;
    let mut pictures: Option<String> = None;
    let mut shots = match shots::Shots::new() {
        Ok(s) => Some(s),
        Err(e) => {
            pictures = Some(e.to_string());
            None
        }
    };
    let bar = indicatif::ProgressBar::new(trials.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} trials traced and filmed {elapsed}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.set_prefix("report.html");
    let dir = PathBuf::from(&page.replays);
    // The trials without a section need no picture: re-simulated in parallel, one per thread;
    // then those with a section, one at a time on the one renderer.
    let mut views: Vec<Option<TrialView>> = trials
        .par_iter()
        .zip(&pick)
        .map(|(t, &detailed)| {
            (!detailed).then(|| {
                let v = view_trial(t.clone(), dir.join(&t.file), page.overrides, false, &[], None, &mut None);
                bar.inc(1);
                v
            })
        })
        .collect();
    for ((slot, t), &detailed) in views.iter_mut().zip(trials).zip(&pick) {
        if detailed {
            *slot = Some(view_trial(
                t.clone(),
                dir.join(&t.file),
                page.overrides,
                true,
                &[],
                shots.as_mut(),
                &mut pictures,
            ));
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let views: Vec<TrialView> = views.into_iter().flatten().collect();
    let areas = sections::areas(&views, page.overrides, shots.as_mut(), &mut pictures);
    let html = page::study(page, &views, &areas, pictures.as_deref());
    let file = out.join("report.html");
    write_page(&file, &html)?;
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn trial(participant: &str, mode: &str, time_s: f64, completed: bool) -> Trial {
        let task = serde_json::json!({"id": format!("{mode}-7"), "mode": mode, "completed": completed, "start_tick": 0, "end_tick": 60, "time_s": time_s,
            "errors": 0, "error_kinds": {"removals": 0, "off_target": 0, "released_green": 0}, "trees": [], "model_types": 0, "menu_opens": 0,
            "ray_path_m": 0.0, "aiming_s": 0.0, "menu_s": 0.0, "manipulating_s": 0.0});
        serde_json::from_value(serde_json::json!({"file": format!("{participant}-{mode}-7.jsonl"), "participant": participant, "synthetic": true, "session_start": null,
            "header_block": null, "config": {}, "trial_num": 1, "block_num": 1, "trial_num_in_block": 1, "start_time_s": null, "end_time_s": null, "task_start_s": null,
            "status": "verified", "error": null, "complete": true, "ticks": 60, "task": task}))
        .unwrap()
    }

    #[test]
    fn a_big_study_gets_sections_for_its_three_slowest_per_condition_and_its_incomplete_trials() {
        let mut trials: Vec<Trial> = (0..60)
            .flat_map(|i| {
                [
                    trial(&format!("P{i:02}"), "ray-casting", 10.0 + i as f64, true),
                    trial(&format!("P{i:02}"), "manual", 100.0 - i as f64, true),
                ]
            })
            .collect();
        trials[7] = trial("P03", "manual", 500.0, false);
        let pick = selected(&trials, &Selection::Auto).unwrap();
        let chosen: Vec<&str> = trials.iter().zip(&pick).filter(|(_, p)| **p).map(|(t, _)| t.file.as_str()).collect();
        // Ray-casting: P59, P58, P57 were slowest; manual: P00, P01, P02; P03's manual did not complete.
        let want = [
            "P00-manual-7.jsonl",
            "P01-manual-7.jsonl",
            "P02-manual-7.jsonl",
            "P03-manual-7.jsonl",
            "P57-ray-casting-7.jsonl",
            "P58-ray-casting-7.jsonl",
            "P59-ray-casting-7.jsonl",
        ];
        assert_eq!(chosen, want);
        // A small study: every trial; a named participant: theirs; an unknown one: an error.
        assert!(selected(&trials[..50], &Selection::Auto).unwrap().iter().all(|p| *p));
        let p = selected(&trials, &"P05".parse().unwrap()).unwrap();
        assert_eq!(p.iter().filter(|x| **x).count(), 2);
        assert!(
            matches!(selected(&trials, &"P05,X".parse().unwrap()), Err(HtmlError::UnknownParticipant(x)) if x == "X")
        );
        assert_eq!("all".parse::<Selection>().unwrap(), Selection::All);
        assert!(matches!(" , ".parse::<Selection>(), Err(HtmlError::EmptySelection)));
    }
}
