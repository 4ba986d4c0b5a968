//! The HTML documents (maud templates): the study's page (overview, trials table, task areas,
//! trial sections) and one recording's page.

use maud::{html, Markup, PreEscaped, DOCTYPE};

use super::area::Area;
use super::sections::{area_section, num, trial_section};
use super::{StudyPage, TrialView};
use crate::study::report::Summary;
use crate::study::stats::PairedStats;

const CSS: &str = include_str!("report.css");
const JS: &str = include_str!("report.js");

/// The p-value as the terminal prints it: scientific below 0.001.
fn p_text(p: f64) -> String {
    if p < 1e-3 { format!("{p:.2e}") } else { format!("{p:.4}") }
}

/// A p-value with its exact value in `data-value`.
fn pnum(field: &str, p: Option<f64>) -> Markup {
    html! {
        @match p {
            Some(p) => span class="num" data-field=(field) data-value=(p) { (p_text(p)) },
            None => span class="num" data-field=(field) { "–" },
        }
    }
}

fn document(title: &str, body: Markup) -> String {
    self_contained(title, CSS, JS, body)
}

/// A self-contained page: its title, its style sheet and script inlined, nothing fetched. The
/// study's and a recording's report and a scenario's trace are written through it.
pub(crate) fn self_contained(title: &str, css: &str, js: &str, body: Markup) -> String {
    html! {
        (DOCTYPE)
        html lang="en" {
            head {
                meta charset="utf-8";
                meta name="viewport" content="width=device-width, initial-scale=1";
                title { (title) }
                style { (PreEscaped(css)) }
            }
            body {
                (body)
                script { (PreEscaped(js)) }
            }
        }
    }
    .into_string()
}

/// Where a figure's data come from, in one line.
pub fn source(summary: &Summary, what: &str) -> Markup {
    let verified = summary.status.get("verified").copied().unwrap_or(0);
    html! {
        p class="source" data-source=(if summary.synthetic { "re-simulated synthetic" } else { "re-simulated recorded" }) {
            "Source: " (what) ", re-simulated from the input events of " (summary.trials) " recordings (" (verified) " verified against their checkpoints)"
            @if summary.synthetic { "; the recordings are " strong { "synthetic" } " (simulated participants, grove synth), not people." } @else { "; recorded from people." }
        }
    }
}

fn paired_table(p: &PairedStats, prefix: &str) -> Markup {
    let f = |name: &str| format!("{prefix}{name}");
    html! {
        table class="stats" {
            tr { th { "pairs (n)" } td { (num(&f("n"), Some(p.n as f64), 0)) } th { "mean difference (" (p.unit) ")" } td { (num(&f("mean_difference"), Some(p.mean_difference), 2)) } }
            tr { th { "95 % CI" } td { (num(&f("ci95_low"), p.ci95_low, 2)) " to " (num(&f("ci95_high"), p.ci95_high, 2)) } th { "sd" } td { (num(&f("sd_difference"), Some(p.sd_difference), 2)) } }
            tr { th { "paired t (df " (p.df) ")" } td { (num(&f("t"), p.t, 2)) } th { "p (t-test)" } td { (pnum(&f("t_test_p"), p.t_test_p)) } }
            tr { th { "Wilcoxon W+ / W−" } td { (num(&f("wilcoxon_w_plus"), Some(p.wilcoxon_w_plus), 1)) " / " (num(&f("wilcoxon_w_minus"), Some(p.wilcoxon_w_minus), 1)) } th { "p (" (p.wilcoxon_method) ")" } td { (pnum(&f("wilcoxon_p"), p.wilcoxon_p)) } }
            tr { th { "Cohen's d_z" } td { (num(&f("cohens_dz"), p.cohens_dz, 2)) } th { "difference" } td { (p.difference) } }
        }
    }
}

fn claim(v: Option<bool>) -> &'static str {
    match v {
        Some(true) => "yes",
        Some(false) => "no",
        None => "cannot say",
    }
}

fn overview(page: &StudyPage<'_>, views: &[TrialView]) -> Markup {
    let s = page.summary;
    html! {
        section id="overview" {
            h2 { "Overview" }
            @if let Some(n) = &s.note { p class="note" { (n) } }
            p class="claim" { "Ray-casting faster than manual for every participant: " strong data-field="ray_casting_faster_for_all" { (claim(s.ray_casting_faster_for_all)) }
              " (" (s.comparisons) " of " (s.participants) " participants compared" @if !s.missing_comparisons.is_empty() { "; no comparison for " (s.missing_comparisons.join(", ")) } ")." }
            @if let Some(p) = &s.paired { h3 { "Paired statistics: " (p.difference) } (paired_table(p, "paired.")) (source(s, "the paired statistics")) }
            h3 { "Per condition" }
            table class="stats" {
                thead { tr { th { "condition" } th { "trials" } th { "completed" } th { "mean time (s)" } th { "sd (s)" } th { "mean errors" } } }
                tbody { @for (m, st) in &s.modes { tr data-mode=(m) { td { (m) } td { (st.trials) } td { (st.completed) } td { (num(&format!("modes.{m}.mean_time_s"), st.mean_time_s, 2)) } td { (num(&format!("modes.{m}.sd_time_s"), st.sd_time_s, 2)) } td { (num(&format!("modes.{m}.mean_errors"), st.mean_errors, 2)) } } } }
            }
            @if s.by_device.iter().any(|d| d.device != "controller") {
                h3 { "Per device" }
                table class="stats" id="per-device" {
                    thead { tr { th { "device" } th { "condition" } th { "trials" } th { "completed" } th { "mean time (s)" } th { "sd (s)" } th { "mean errors" } } }
                    tbody { @for d in &s.by_device { tr data-device=(d.device) data-mode=(d.mode) { td { (d.device) } td { (d.mode) } td { (d.stats.trials) } td { (d.stats.completed) } td { (num("by_device.mean_time_s", d.stats.mean_time_s, 2)) } td { (num("by_device.sd_time_s", d.stats.sd_time_s, 2)) } td { (num("by_device.mean_errors", d.stats.mean_errors, 2)) } } } }
                }
            }
            h3 { "Per participant" }
            table class="stats" id="per-participant" {
                thead { tr { th { "participant" } th { "ray-casting (s)" } th { "manual (s)" } th { "manual − ray-casting (s)" } th { "missing" } } }
                tbody { @for p in &s.per_participant { tr data-participant=(p.participant) { td { (p.participant) } td { (num("ray_casting_s", p.ray_casting_s, 2)) } td { (num("manual_s", p.manual_s, 2)) } td { (num("difference_s", p.difference_s, 2)) } td { (p.missing.clone().unwrap_or_default()) } } } }
            }
            (slowest(views))
            @for (title, svg) in &page.charts { figure class="chart" { (PreEscaped(svg)) figcaption { (title) } (source(s, "task times")) } }
            h3 { "Incomplete and diverged trials" }
            @if s.incomplete.is_empty() { p id="incomplete" { "None: every trial completed and was verified or re-run." } }
            @else { ul id="incomplete" { @for i in &s.incomplete { li data-file=(i.file) { (i.participant) " · " (i.task) " · " (i.file) ": " strong { (i.reason) } } } } }
            @if let Some(w) = page.what_if { (what_if(w, s)) }
            @if let Some(sw) = page.sweep { (sweep(sw)) }
        }
    }
}

fn what_if(w: &crate::study::whatif::WhatIf, s: &Summary) -> Markup {
    html! {
        section id="what-if" {
            h3 { "What-if: " (w.kind) }
            p { (w.kind_meaning) "." }
            table class="stats" { thead { tr { th { "parameter" } th { "baseline (default)" } th { "changed to" } } }
                tbody { @for p in &w.parameters { tr { td { (p.name) } td { (p.default_value) } td { strong { (p.new_value) } } } } } }
            p { "Ray-casting faster for every participant — baseline: " strong { (claim(w.baseline.ray_casting_faster_for_all)) } "; under the what-if: " strong { (claim(s.ray_casting_faster_for_all)) } "." }
            table class="stats" { thead { tr { th { "condition" } th { "baseline mean (s)" } th { "what-if mean (s)" } th { "difference (s)" } th { "pairs" } th { "without a difference" } } }
                tbody { @for (m, c) in &w.modes { tr data-mode=(m) { td { (m) } td { (num(&format!("what_if.{m}.baseline_mean_s"), c.baseline_mean_s, 2)) } td { (num(&format!("what_if.{m}.what_if_mean_s"), c.what_if_mean_s, 2)) } td { (num(&format!("what_if.{m}.difference_s"), c.difference_s, 2)) } td { (c.pairs) } td { (c.unpaired) } } } } }
            table class="stats" { thead { tr { th { "participant" } th { "task" } th { "baseline (s)" } th { "what-if (s)" } th { "difference (s)" } th { "baseline status" } th { "what-if status" } } }
                tbody { @for t in &w.per_trial { tr { td { (t.participant) } td { (t.task) } td { (num("baseline_time_s", t.baseline_time_s, 2)) } td { (num("what_if_time_s", t.what_if_time_s, 2)) } td { (num("difference_s", t.difference_s, 2)) } td { (t.baseline_status) } td { (t.what_if_status) } } } } }
            p class="source" data-source="re-simulated" { "Source: the baseline and the what-if are both re-simulated (" (w.kind) ")." }
        }
    }
}

fn sweep(sw: &crate::study::whatif::Sweep) -> Markup {
    html! {
        section id="sweep" {
            h3 { "Sweep of " (sw.parameter) " (" (sw.kind) ", default " (sw.default_value) ")" }
            table class="stats" { thead { tr { th { "value" } th { "ray-casting completed" } th { "ray-casting mean (s)" } th { "manual completed" } th { "manual mean (s)" } th { "ray-casting faster for all" } } }
                tbody { @for r in &sw.rows { tr { td { (r.value) @if r.is_default { " (default)" } } td { (r.completed.get("ray-casting").copied().unwrap_or(0)) } td { (num("ray-casting", r.modes.get("ray-casting").and_then(|c| c.what_if_mean_s), 2)) } td { (r.completed.get("manual").copied().unwrap_or(0)) } td { (num("manual", r.modes.get("manual").and_then(|c| c.what_if_mean_s), 2)) } td { (claim(r.ray_casting_faster_for_all)) } } } } }
        }
    }
}

/// Per condition, the slowest completed trial and where its time went.
fn slowest(views: &[TrialView]) -> Markup {
    let mut conditions: Vec<String> = views.iter().filter(|v| v.trial.task.is_some()).map(TrialView::condition).collect();
    conditions.sort();
    conditions.dedup();
    html! {
        h3 { "Slowest per condition" }
        ul id="slowest" {
            @for c in &conditions {
                @if let Some((v, k)) = views.iter().filter(|v| v.condition() == *c).filter_map(|v| v.trial.task.as_ref().filter(|_| crate::study::report::usable_time(&v.trial).is_some()).map(|k| (v, k))).max_by(|a, b| a.1.time_s.total_cmp(&b.1.time_s)) {
                    li data-condition=(c) data-participant=(v.trial.participant) {
                        (c) ": " strong { (v.trial.participant) } " (" (format!("{:.2}", k.time_s)) " s): aiming " (format!("{:.2}", k.aiming_s)) " s, menu " (format!("{:.2}", k.menu_s)) " s, manipulating " (format!("{:.2}", k.manipulating_s)) " s, " (k.errors) " errors, ray path " (format!("{:.1}", k.ray_path_m)) " m"
                        @if v.detailed { " — " a href=(format!("#{}", v.anchor())) { "its timeline and filmstrip" } }
                    }
                }
            }
        }
    }
}

fn trials_table(views: &[TrialView]) -> Markup {
    let mut participants: Vec<&str> = views.iter().map(|v| v.trial.participant.as_str()).collect();
    participants.sort_unstable();
    participants.dedup();
    let mut conditions: Vec<String> = views.iter().map(TrialView::condition).collect();
    conditions.sort();
    conditions.dedup();
    let mut statuses: Vec<&str> = views.iter().map(|v| v.trial.status.word()).collect();
    statuses.sort_unstable();
    statuses.dedup();
    html! {
        section id="trials" {
            h2 { "Trials" }
            div class="filters" {
                label { "participant " select id="f-participant" { option value="" { "all" } @for p in &participants { option value=(p) { (p) } } } }
                label { " condition " select id="f-condition" { option value="" { "all" } @for c in &conditions { option value=(c) { (c) } } } }
                label { " status " select id="f-status" { option value="" { "all" } @for s in &statuses { option value=(s) { (s) } } } }
                span id="f-count" {}
            }
            table id="trial-table" class="stats sortable" {
                thead { tr { th data-sort="text" { "participant" } th data-sort="num" { "trial" } th data-sort="text" { "condition" } th data-sort="text" { "status" } th data-sort="num" { "time (s)" } th data-sort="num" { "errors" } th data-sort="num" { "trees" } th data-sort="text" { "recording" } } }
                tbody {
                    @for v in views {
                        @let k = v.trial.task.as_ref();
                        tr class="trial-row" data-file=(v.trial.file) data-participant=(v.trial.participant) data-condition=(v.condition()) data-status=(v.trial.status.word()) {
                            td { (v.trial.participant) } td { (v.trial.trial_num) } td { (v.condition()) } td { span class=(format!("status {}", v.trial.status.word())) { (v.trial.status.word()) } }
                            td { (num("time_s", k.filter(|k| k.completed).map(|k| k.time_s), 2)) } td { (num("errors", k.map(|k| k.errors as f64), 0)) } td { (num("trees", k.map(|k| k.trees.len() as f64), 0)) }
                            td { @if v.detailed { a href=(format!("#{}", v.anchor())) { (v.trial.file) } } @else { (v.trial.file) } }
                        }
                    }
                }
            }
        }
    }
}

fn pictures_note(note: Option<&str>) -> Markup {
    html! { @if let Some(n) = note { p class="problem" id="no-pictures" { "No pictures in this report: " (n) } } }
}

/// The study's page.
pub fn study(page: &StudyPage<'_>, views: &[TrialView], areas: &[(Area, Option<String>)], pictures: Option<&str>) -> String {
    let detailed = views.iter().filter(|v| v.detailed).count();
    let body = html! {
        header { h1 { "grove study report" } p { "Recordings: " code { (page.replays) } " · " (views.len()) " trials · " (page.summary.participants) " participants" @if !page.overrides.is_empty() { " · under " (page.overrides.iter().map(|o| format!("{}={}", o.name, o.text)).collect::<Vec<_>>().join(", ")) } }
            nav { a href="#overview" { "Overview" } " · " a href="#trials" { "Trials" } " · " a href="#area" { "Task area" } @if page.questionnaires.is_some() { " · " a href="#questionnaires" { "Questionnaires" } } " · " a href="#trial-sections" { "Each trial" } } }
        (pictures_note(pictures))
        (overview(page, views))
        (trials_table(views))
        section id="area" {
            h2 { "The task area from above" }
            (source(page.summary, "ray hits, moved trees, planted trees and errors"))
            @for (i, (a, img)) in areas.iter().enumerate() { (area_section(a, img.as_deref(), i)) }
        }
        @if let Some(q) = page.questionnaires { (super::questionnaire::section(q, views)) }
        section id="trial-sections" {
            h2 { "Each trial" }
            @if detailed < views.len() { p { (detailed) " of " (views.len()) " trials have a section (choose with --html-trials)." } }
            @for v in views.iter().filter(|v| v.detailed) { (trial_section(v)) }
        }
    };
    document("grove study report", body)
}

/// One recording's page (`grove replay FILE --html OUT.html`).
pub fn replay(view: &TrialView, pictures: Option<&str>) -> String {
    let body = html! {
        header { h1 { "grove replay: " (view.trial.file) } }
        (pictures_note(pictures))
        (trial_section(view))
    };
    document(&format!("grove replay {}", view.trial.file), body)
}
