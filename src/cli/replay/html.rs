//! `grove replay FILE --html OUT.html`: one recording's page (the study report's per-trial
//! section), with the first divergence and frames just before and at it.

use std::path::Path;

use anyhow::bail;
use grove_systems::replay::ReplayOutcome;

use grove::html::{self, trace::Moment};

/// Refuses a page path that is a folder, lies in a missing folder, or exists (without --force).
pub fn check_out(page: &Path, force: bool) -> anyhow::Result<()> {
    if page.is_dir() {
        bail!("{}: is a folder; --html needs a file name", page.display());
    }
    if page.exists() && !force {
        bail!("{}: already exists; use --force to replace it", page.display());
    }
    if let Some(parent) = page.parent()
        && !parent.as_os_str().is_empty()
        && !parent.is_dir()
    {
        bail!("{}: folder does not exist", parent.display());
    }
    Ok(())
}

/// Re-simulates `file` once more for its page and writes it to `page`.
pub fn write(file: &Path, outcome: &ReplayOutcome, page: &Path) -> anyhow::Result<()> {
    let name = file.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
    let stem = file.file_stem().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
    let mut trials = vec![grove::study::trial_from_outcome(name, stem, outcome)];
    grove::study::assign_order(&mut trials);
    let trial = trials.remove(0);
    // Frames a second before the first diverging checkpoint and at it.
    let extra: Vec<Moment> = outcome
        .first_divergence
        .iter()
        .flat_map(|d| {
            [
                Moment { tick: d.tick.saturating_sub(60), label: "1 s before the divergence".into() },
                Moment { tick: d.tick, label: "the first diverging checkpoint".into() },
            ]
        })
        .collect();
    let mut pictures = None;
    let mut shots = html::shots::Shots::new().map_err(|e| pictures = Some(e.to_string())).ok();
    let mut view = html::view_trial(trial, file.to_path_buf(), &[], true, &extra, shots.as_mut(), &mut pictures);
    view.divergence = outcome.first_divergence.clone();
    html::write_page(page, &html::page::replay(&view, pictures.as_deref()))?;
    eprintln!("replay: {} written ({} frames)", page.display(), view.frames.len());
    Ok(())
}
