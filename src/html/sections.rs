//! The page's task-area and per-trial sections.

use grove_systems::replay::{read_events, sim_for_header_in};
use grove_systems::resources::Override;
use maud::{html, Markup};

use super::area::{self, Area, AreaTrial};
use super::figures;
use super::shots::Shots;
use super::TrialView;

/// One condition's area and its picture from above (a data URI), in the order conditions first
/// appear among the trials.
pub fn areas(views: &[TrialView], overrides: &[Override], mut shots: Option<&mut Shots>, pictures: &mut Option<String>) -> Vec<(Area, Option<String>)> {
    let mut conditions: Vec<String> = Vec::new();
    for v in views.iter().filter(|v| v.trace.is_some()) {
        if !conditions.contains(&v.condition()) {
            conditions.push(v.condition());
        }
    }
    conditions
        .into_iter()
        .map(|c| {
            let of: Vec<&TrialView> = views.iter().filter(|v| v.condition() == c).collect();
            let trials: Vec<AreaTrial<'_>> = of.iter().filter_map(|v| v.trace.as_ref().map(|trace| AreaTrial { participant: &v.trial.participant, report: v.trial.task.as_ref(), trace })).collect();
            let a = area::gather(&c, &trials);
            let mut image = None;
            if let (Some(s), None, Some(first)) = (shots.as_deref_mut(), pictures.as_ref(), of.iter().find(|v| v.trace.is_some())) {
                // The scene as the first trial of the condition starts: its own trees, no planted one.
                let world = read_events(&first.path).map_err(|e| e.to_string()).and_then(|(h, _)| {
                    let banks = crate::bank::open_session(&[]).map_err(|e| e.to_string())?;
                    sim_for_header_in(&h, first.path.parent(), overrides, &banks).map_err(|e| e.to_string())
                });
                match world.and_then(|sim| s.top(&sim, a.view).map_err(|e| e.to_string())) {
                    Ok(uri) => image = Some(uri),
                    Err(e) => *pictures = Some(e),
                }
            }
            (a, image)
        })
        .collect()
}

fn opt(x: Option<f64>, d: usize) -> String {
    x.map_or_else(|| "–".into(), |v| format!("{v:.d$}"))
}

/// A condition's task area: the map with the participants' switches, and the per-target table.
pub fn area_section(a: &Area, image: Option<&str>, n: usize) -> Markup {
    let id = format!("c{n}");
    let hardest = a.per_target.iter().filter(|t| t.mean_took_s.is_some()).max_by(|x, y| x.mean_took_s.unwrap_or(0.0).total_cmp(&y.mean_took_s.unwrap_or(0.0))).map(|t| t.index);
    html! {
        section class="area-section" data-condition=(a.condition) {
            h3 { "Condition: " (a.condition) }
            div class="switches" data-area=(id) {
                "Participants: "
                @for p in a.heat.keys() {
                    label { input type="checkbox" class="pswitch" data-p=(p) checked; (p) } " "
                }
                button type="button" class="all-on" { "all" } " " button type="button" class="all-off" { "none" }
            }
            div class="map" { (area::area_svg(a, image, &id)) }
            p class="legend" {
                span class="sw heat" {} " ray hit points (ticks per " (super::trace::CELL_M) " m cell, all shown participants) "
                span class="sw path" {} " tree moved, grab to release "
                span class="sw planted" {} " planted tree, with its error vector from the target (white ring, numbered) "
                span class="sw error" {} " interaction error (removal, off target, released green)"
            }
            table class="targets-table" {
                thead { tr { th { "target" } th { "model" } th { "x, z (m)" } th { "satisfied" } th { "mean time the tree took (s)" } th { "slowest" } th { "mean distance from target (m)" } th { "errors nearest it" } } }
                tbody {
                    @for t in &a.per_target {
                        tr class=[(Some(t.index) == hardest).then_some("hardest")] data-target=(t.index) {
                            td { (t.index + 1) } td { (t.model) } td { (format!("{:.1}, {:.1}", t.position.x, t.position.z)) }
                            td { (t.satisfied) " of " (t.trials) }
                            td class="num" { (opt(t.mean_took_s, 2)) }
                            td { @if let Some((p, s)) = &t.slowest { (p) " (" (format!("{s:.2}")) " s)" } }
                            td class="num" { (opt(t.mean_error_m, 3)) }
                            td class="num" { (t.errors) }
                        }
                    }
                }
            }
            @if let Some(h) = hardest { p { "Hardest target (longest mean time): " strong { (h + 1) } "." } }
        }
    }
}

/// A number with its exact value in `data-value` (what the tests compare with summary.json).
pub fn num(field: &str, v: Option<f64>, d: usize) -> Markup {
    html! {
        @match v {
            Some(v) => span class="num" data-field=(field) data-value=(v) { (format!("{v:.d$}")) },
            None => span class="num" data-field=(field) { "–" },
        }
    }
}

/// The shell command that opens the recording at `tick` in the viewer.
pub fn view_command(v: &TrialView, tick: u64) -> String {
    format!("grove view {} --at {tick}", v.path.display())
}

/// One trial's section: numbers, timeline, tree durations, filmstrip, divergence.
pub fn trial_section(v: &TrialView) -> Markup {
    let t = &v.trial;
    let k = t.task.as_ref();
    html! {
        section class="trial" id=(v.anchor()) data-file=(t.file) data-participant=(t.participant) data-condition=(v.condition()) data-status=(t.status.word()) data-device=(t.device.mapping) {
            h3 { (t.participant) " · " (k.map_or("no task", |k| k.id.as_str())) " · trial " (t.trial_num) " · " span class=(format!("status {}", t.status.word())) { (t.status.word()) } }
            p class="source" { "Source: re-simulated from the recording's input events" @if t.synthetic { " (a synthetic participant, grove synth)" } @else { " (recorded from a person)" } "; " (t.status.word()) "." }
            table class="numbers" {
                tr { th { "task time (s)" } td { (num("time_s", k.filter(|k| k.completed).map(|k| k.time_s), 2)) } th { "completed" } td { (k.map_or("no task", |k| if k.completed { "yes" } else { "no" })) } }
                tr { th { "errors" } td { (num("errors", k.map(|k| k.errors as f64), 0)) } th { "removals / off target / released green" } td { @if let Some(k) = k { (k.error_kinds.removals) " / " (k.error_kinds.off_target) " / " (k.error_kinds.released_green) } } }
                tr { th { "trees" } td { (num("trees", k.map(|k| k.trees.len() as f64), 0)) } th { "model types" } td { (num("model_types", k.map(|k| k.model_types as f64), 0)) } }
                tr { th { "aiming (s)" } td { (num("aiming_s", k.map(|k| k.aiming_s), 2)) } th { "menu (s)" } td { (num("menu_s", k.map(|k| k.menu_s), 2)) } }
                tr { th { "manipulating (s)" } td { (num("manipulating_s", k.map(|k| k.manipulating_s), 2)) } th { "ray path (m)" } td { (num("ray_path_m", k.map(|k| k.ray_path_m as f64), 2)) } }
                tr { th { "menu opens" } td { (num("menu_opens", k.map(|k| k.menu_opens as f64), 0)) } th { "ticks re-simulated" } td { (t.ticks) } }
                tr { th { "device" } td class="device" { (t.device.mapping) " (" (t.device.target_ray_mode) ", " (t.device.profile) ")" } th { "layout" } td class="layout" { (k.map_or(String::new(), crate::study::csv_out::layout)) } }
            }
            p { "Recording: " code { (v.path.display()) } " — open it at the task's start: " code class="cmd" { (view_command(v, k.map_or(0, |k| k.start_tick))) } }
            @if let Some(e) = &t.error { p class="problem" { (e) } }
            @if let Some(d) = &v.divergence {
                div class="divergence" {
                    h4 { "Divergence" }
                    p { "First diverging checkpoint: tick " strong class="div-tick" { (d.tick) } " (" (format!("{:.2}", d.tick as f64 / 60.0)) " s); expected hash " code { (d.expected_hash) } ", re-simulated " code { (d.actual_hash) } "." }
                    @if d.differing.is_empty() { p { "The footer's final hash differs; the footer carries no per-entity hashes." } }
                    @else {
                        table class="differing" { thead { tr { th { "entity" } th { "component" } } } tbody { @for x in &d.differing { tr { td { (x.entity) } td { (x.component) } } } } }
                    }
                }
            }
            @if let Some(e) = &v.trace_error { p class="problem" { "No timeline: " (e) } }
            @if let Some(tr) = &v.trace {
                h4 { "Events" }
                (figures::timeline(tr, t.ticks, k))
                @if let Some(k) = k.filter(|k| !k.trees.is_empty()) {
                    h4 { "Time each tree took" }
                    (figures::durations(k))
                }
            }
            @if !v.frames.is_empty() {
                h4 { "Filmstrip (head camera)" }
                div class="filmstrip" {
                    @for (m, uri) in &v.frames {
                        figure data-tick=(m.tick) {
                            img src=(uri) width="320" height="180" alt=(format!("the head camera at tick {}", m.tick));
                            figcaption { (format!("{:.2}", m.tick as f64 / 60.0)) " s · " (m.label) br; code class="cmd" { (view_command(v, m.tick)) } }
                        }
                    }
                }
            }
        }
    }
}
