//! The terminal output of a study: the table of trials (with a what-if's baseline and
//! differences) and the summary lines under it.

use super::report::{usable_time, Summary};
use super::stats::PairedStats;
use super::whatif::WhatIf;
use super::{Trial, TrialStatus};

fn opt(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.digits$}"))
}

/// The terminal table. Plain runs show the task time; what-if runs show the baseline, the
/// what-if and the difference per trial.
pub fn table(trials: &[Trial], what_if: Option<&WhatIf>) -> String {
    let mut out = String::new();
    if let Some(w) = what_if {
        out.push_str(&format!("what-if ({}): {}\n", w.kind, w.parameters_text()));
        out.push_str(&format!(
            "{:<12} {:>5} {:<15} {:<12} {:>10} {:>10} {:>8} {:>6} {:>7}  {}\n",
            "participant", "trial", "task", "mode", "baseline_s", "what_if_s", "diff_s", "trees", "errors", "status"
        ));
    } else {
        out.push_str(&format!("{:<12} {:>5} {:<15} {:<12} {:>8} {:>6} {:>7}  {}\n", "participant", "trial", "task", "mode", "time_s", "trees", "errors", "verified"));
    }
    for t in trials {
        let (task, mode, trees, errors) = match &t.task {
            Some(k) => (k.id.clone(), k.mode.clone(), k.trees.len().to_string(), k.errors.to_string()),
            None => ("-".into(), "-".into(), "-".into(), "-".into()),
        };
        let status = match (&t.status, &t.error) {
            (TrialStatus::Failed, Some(e)) => format!("failed: {e}"),
            (s, _) => s.word().to_string(),
        };
        let time = usable_time(t);
        if let Some(w) = what_if {
            let c = w.comparison_for(t);
            out.push_str(&format!(
                "{:<12} {:>5} {:<15} {:<12} {:>10} {:>10} {:>8} {:>6} {:>7}  {}\n",
                t.participant,
                t.trial_num,
                task,
                mode,
                opt(c.and_then(|c| c.baseline_time_s), 2),
                opt(time, 2),
                opt(c.and_then(|c| c.difference_s), 2),
                trees,
                errors,
                status
            ));
        } else {
            out.push_str(&format!("{:<12} {:>5} {:<15} {:<12} {:>8} {:>6} {:>7}  {}\n", t.participant, t.trial_num, task, mode, opt(time, 2), trees, errors, status));
        }
    }
    out
}

/// The lines under the table: per-mode statistics, the comparison, incomplete trials, the
/// paired statistics and the synthetic-data note.
pub fn summary_lines(s: &Summary) -> String {
    let mut out = String::new();
    for (mode, m) in &s.modes {
        out.push_str(&format!(
            "{mode:<12} mean {} s (sd {}) over {} completed of {} trials, {} errors per trial\n",
            opt(m.mean_time_s, 2),
            opt(m.sd_time_s, 2),
            m.completed,
            m.trials,
            opt(m.mean_errors, 2)
        ));
    }
    // By device, once a device other than a controller made trials (docs/headset.md).
    if s.by_device.iter().any(|d| d.device != "controller") {
        for d in &s.by_device {
            let m = &d.stats;
            out.push_str(&format!("device {:<17} {:<12} mean {} s (sd {}) over {} completed of {} trials\n", d.device, d.mode, opt(m.mean_time_s, 2), opt(m.sd_time_s, 2), m.completed, m.trials));
        }
    }
    for i in &s.incomplete {
        out.push_str(&format!("left out of comparisons: {} {} ({}): {}\n", i.participant, i.task, i.file, i.reason));
    }
    let faster = match s.ray_casting_faster_for_all {
        Some(true) => "yes".to_string(),
        Some(false) => "no".to_string(),
        None if s.missing_comparisons.is_empty() => "cannot say (no participant has both tasks)".to_string(),
        None => format!("cannot say (no comparison for {})", s.missing_comparisons.join(", ")),
    };
    out.push_str(&format!("ray-casting faster for every participant: {faster} ({} of {} participants compared)\n", s.comparisons, s.participants));
    match &s.paired {
        Some(p) => out.push_str(&paired_line(p)),
        None => out.push_str("paired statistics: fewer than two participants with both tasks\n"),
    }
    if let Some(k) = &s.conditions {
        out.push_str(&super::conditions::lines(k));
    }
    if let Some(note) = &s.note {
        out.push_str(&format!("note: {note}\n"));
    }
    out
}

/// One paragraph of paired statistics for the terminal.
pub fn paired_line(p: &PairedStats) -> String {
    if p.t.is_none() {
        return format!("paired ({}, n = {}): every difference is {:.2} {}; no spread, so no test\n", p.difference, p.n, p.mean_difference, p.unit);
    }
    format!(
        "paired ({}, n = {}): mean {:.2} {u} (95 % CI {} to {} {u}), sd {:.2} {u}; t({}) = {}, p = {}; Wilcoxon W+ = {}, W- = {}, p = {} ({}); Cohen's d_z = {}\n",
        p.difference,
        p.n,
        p.mean_difference,
        opt(p.ci95_low, 2),
        opt(p.ci95_high, 2),
        p.sd_difference,
        p.df,
        opt(p.t, 3),
        p.t_test_p.map_or_else(|| "-".into(), |v| format!("{v:.3e}")),
        p.wilcoxon_w_plus,
        p.wilcoxon_w_minus,
        p.wilcoxon_p.map_or_else(|| "-".into(), |v| format!("{v:.3e}")),
        p.wilcoxon_method,
        opt(p.cohens_dz, 2),
        u = p.unit
    )
}
