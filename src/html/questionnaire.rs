//! The questionnaires in the study's HTML report (`docs/protocol.md`): the scores, the paired
//! comparisons, a distribution chart per item (inline SVG: how many participants gave each
//! answer), and each participant's answers beside their trials.

use maud::{Markup, html};
use serde_json::Value;

use crate::protocol::{Instrument, ItemKind};
use crate::study::questionnaire::{Answer, Questionnaires, cell, columns};

use super::TrialView;

/// The answers an item may take, in order, as the chart's categories (none for free text).
fn categories(kind: &ItemKind) -> Option<Vec<String>> {
    let range = |lo: i64, hi: i64, step: i64| (0..=((hi - lo) / step)).map(|i| (lo + i * step).to_string()).collect();
    match kind {
        ItemKind::Rating { .. } => Some(range(0, 10, 1)),
        ItemKind::Scale { min, max, step, .. } => Some(range(*min, *max, *step)),
        ItemKind::Likert { points, .. } => Some(range(1, *points, 1)),
        ItemKind::Single { choices } | ItemKind::Multiple { choices } => Some(choices.clone()),
        ItemKind::YesNo => Some(vec!["yes".into(), "no".into()]),
        ItemKind::Text { .. } => None,
    }
}

/// How often each category was given (a multiple-choice answer counts each choice).
fn counts(cats: &[String], given: &[&Answer]) -> Vec<usize> {
    cats.iter()
        .map(|c| {
            given
                .iter()
                .filter(|a| match &a.answer {
                    Value::Array(list) => list.iter().any(|v| cell(v) == *c),
                    v => cell(v) == *c,
                })
                .count()
        })
        .collect()
}

/// A column chart of counts over a numeric item's answers, low to high.
fn columns_chart(cats: &[String], n: &[usize], id: &str) -> Markup {
    let most = n.iter().copied().max().unwrap_or(0).max(1);
    let step = (460.0 / cats.len() as f64).min(36.0);
    let (w, h, top) = (step * cats.len() as f64 + 20.0, 96.0, 70.0);
    let every = cats.len().div_ceil(11);
    html! {
        svg class="distribution" data-item=(id) width=(w) height=(h) viewBox=(format!("0 0 {w} {h}")) role="img" {
            line x1="10" y1=(top) x2=(w - 10.0) y2=(top) stroke="#999" {}
            @for (i, (c, k)) in cats.iter().zip(n).enumerate() {
                @let x = 10.0 + step * i as f64;
                @let bh = 56.0 * *k as f64 / most as f64;
                rect x=(x + 1.0) y=(top - bh) width=(step - 2.0) height=(bh) fill="#4a8f5a" data-count=(k) {}
                @if *k > 0 { text x=(x + step / 2.0) y=(top - bh - 3.0) text-anchor="middle" font-size="10" { (k) } }
                @if i % every == 0 { text x=(x + step / 2.0) y=(top + 13.0) text-anchor="middle" font-size="10" { (c) } }
            }
        }
    }
}

/// A bar chart of counts, one bar per category.
fn bars(cats: &[String], n: &[usize], id: &str) -> Markup {
    let most = n.iter().copied().max().unwrap_or(0).max(1);
    let (w, h, bar_h) = (520.0, 18.0 * cats.len() as f64 + 8.0, 14.0);
    html! {
        svg class="distribution" data-item=(id) width=(w) height=(h) viewBox=(format!("0 0 {w} {h}")) role="img" {
            @for (i, (c, k)) in cats.iter().zip(n).enumerate() {
                @let y = 4.0 + 18.0 * i as f64;
                text x="196" y=(y + 11.0) text-anchor="end" font-size="11" { (c.chars().take(30).collect::<String>()) }
                rect x="200" y=(y) width=(280.0 * *k as f64 / most as f64) height=(bar_h) fill="#4a8f5a" data-count=(k) {}
                text x=(204.0 + 280.0 * *k as f64 / most as f64) y=(y + 11.0) font-size="11" { (k) }
            }
        }
    }
}

fn item_charts(ins: &Instrument, cond: Option<&str>, answers: &[Answer]) -> Markup {
    html! {
        @for item in &ins.items {
            @let given: Vec<&Answer> = answers.iter().filter(|a| a.instrument == ins.id && a.condition.as_deref() == cond && a.item == item.id).collect();
            @let id = match cond { Some(c) => format!("{}.{c}.{}", ins.id, item.id), None => format!("{}.{}", ins.id, item.id) };
            div class="item" {
                h4 { code { (id) } " — " (item.text) " (" (given.len()) " answers)" }
                @match categories(&item.kind) {
                    Some(cats) if matches!(item.kind, ItemKind::Rating { .. } | ItemKind::Scale { .. } | ItemKind::Likert { .. }) => { (columns_chart(&cats, &counts(&cats, &given), &id)) }
                    Some(cats) => { (bars(&cats, &counts(&cats, &given), &id)) }
                    None => { ul class="texts" data-item=(id) { @for a in &given { li { strong { (a.participant) } ": " (cell(&a.answer)) } } } }
                }
            }
        }
    }
}

/// The questionnaire section of the study's report.
pub fn section(q: &Questionnaires, views: &[TrialView]) -> Markup {
    let cols = columns(&q.loaded);
    let mut groups: Vec<(String, Option<String>)> = cols.iter().map(|(i, c, _)| (i.clone(), c.clone())).collect();
    groups.dedup();
    let mut people: Vec<&str> = q.answers.iter().map(|a| a.participant.as_str()).collect();
    people.dedup();
    html! {
        section id="questionnaires" {
            h2 { "Questionnaires" }
            p class="source" { "Source: the answers " code { "grove serve --protocol" } " wrote as they were given (protocol " code { (q.loaded.protocol.name) } "), " (q.answers.len()) " answers of " (people.len()) " participants; a later answer to the same item replaces an earlier one." }
            @if !q.scores.is_empty() {
                h3 { "Scores" }
                table class="scores" {
                    thead { tr { th { "participant" } th { "instrument" } th { "condition" } th { "score (0–100)" } } }
                    tbody { @for s in &q.scores { tr data-participant=(s.participant) data-instrument=(s.instrument) { td { (s.participant) } td { (s.instrument) } td { (s.condition.as_deref().unwrap_or("")) } td class="score" { (format!("{:.1}", s.score)) } } } }
                }
            }
            @for c in &q.comparisons {
                h3 { "Paired: " code { (c.b) } " against " code { (c.a) } }
                p class="comparison" { (c.b_higher) " of " (c.n) " participants rated " code { (c.b) } " higher, " (c.same) " the same, " (c.a_higher) " lower."
                    @if let Some(s) = &c.stats { " Mean difference " (format!("{:.2}", s.mean_difference)) " points; Wilcoxon signed-rank p = " (s.wilcoxon_p.map_or("–".into(), |p| format!("{p:.3}"))) " (" (s.wilcoxon_method) "); paired t p = " (s.t_test_p.map_or("–".into(), |p| format!("{p:.3}"))) "." } }
            }
            h3 { "Each item" }
            @for (ins, cond) in &groups {
                @if let Some(i) = q.loaded.instrument(ins) {
                    h3 { (i.title) @if let Some(c) = cond { " — after " (c) } }
                    div class="items" { (item_charts(&i, cond.as_deref(), &q.answers)) }
                }
            }
            h3 { "Each participant: answers beside trials" }
            @for p in &people {
                div class="participant-answers" data-participant=(p) {
                    h4 { (p) }
                    div class="side-by-side" {
                        table class="their-trials" {
                            thead { tr { th { "trial" } th { "task" } th { "time (s)" } th { "errors" } th { "status" } } }
                            tbody { @for v in views.iter().filter(|v| v.trial.participant == *p) {
                                @let k = v.trial.task.as_ref();
                                tr { td { (v.trial.trial_num) } td { (k.map_or("-", |k| k.id.as_str())) } td { (k.map_or("-".into(), |k| format!("{:.2}", k.time_s))) } td { (k.map_or("-".into(), |k| k.errors.to_string())) } td { (v.trial.status.word()) } }
                            } }
                        }
                        table class="their-answers" {
                            thead { tr { th { "item" } th { "answer" } } }
                            tbody { @for a in q.answers.iter().filter(|a| a.participant == *p) {
                                tr data-item=(a.item) { td { code { (a.instrument) @if let Some(c) = &a.condition { "." (c) } "." (a.item) } } td class="answer" { (cell(&a.answer)) } }
                            } }
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn each_item_has_its_distribution_and_each_participant_their_answers() {
        let dir = tempfile::tempdir().unwrap();
        crate::study::questionnaire::fixture(dir.path());
        let q = crate::study::questionnaire::load(dir.path()).unwrap().unwrap();
        let html = super::section(&q, &[]).into_string();
        // Both rated guidance 8: the column for 8 counts 2, the one for 3 (replaced) none.
        let chart = html.split("data-item=\"tree-planting.guidance\"").nth(1).unwrap().split("</svg>").next().unwrap();
        let counts: Vec<&str> = chart.split("data-count=\"").skip(1).map(|s| s.split('"').next().unwrap()).collect();
        assert_eq!(counts, vec!["0", "0", "0", "0", "0", "0", "0", "0", "2", "0", "0"]);
        let choices =
            html.split("data-item=\"tree-planting.more_instructions\"").nth(1).unwrap().split("</svg>").next().unwrap();
        assert_eq!(choices.matches("data-count=\"2\"").count(), 2, "two choices, each given by both");
        assert!(html.contains("data-participant=\"P01\"") && html.contains("data-participant=\"P02\""));
        assert!(html.contains("1 of 2 participants rated"), "the comparison: P01 7 vs 4, P02 5 vs 5");
    }
}
