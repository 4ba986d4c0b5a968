//! One trial's figures as SVG: its events on a time axis (button presses, plantings, removals,
//! selections, moves and snaps, errors, task marks) and the time each tree took as bars.

use grove_systems::events::{Happening, LogEntry};
use grove_systems::task::TaskReport;
use maud::{Markup, html};

use super::area::tree_durations;
use super::trace::Trace;

/// Ticks per second of the study's simulation (reports say seconds = ticks / 60).
const TPS: f64 = 60.0;

/// The rows of the timeline: a label and which log kinds go there.
const ROWS: &[(&str, &[&str])] = &[
    ("planted", &["planted"]),
    ("removed", &["removed"]),
    ("selected", &["selected", "deselected"]),
    ("moved / snapped", &["moved", "snapped", "snap_armed", "snap_disarmed", "scaled", "rotated"]),
    ("errors", &["released_green"]),
    ("menu", &["menu_opened", "model_chosen"]),
    ("task", &["task_started", "task_completed", "task_ended"]),
];

fn colour(kind: &str) -> &'static str {
    match kind {
        "trigger" | "planted" | "task_completed" => "#2e7d32",
        "bumper" | "removed" | "released_green" => "#c62828",
        "menu" | "menu_opened" | "model_chosen" => "#6a1b9a",
        "snapped" | "moved" => "#1565c0",
        "task_started" | "task_ended" => "#000",
        _ => "#757575",
    }
}

fn words(e: &LogEntry) -> String {
    match &e.what {
        Happening::Planted { position, .. } => format!("planted at ({:.2}, {:.2})", position.x, position.z),
        Happening::Snapped { position, .. } => format!("snapped at ({:.2}, {:.2})", position.x, position.z),
        Happening::Moved { position, .. } => format!("moved to ({:.2}, {:.2})", position.x, position.z),
        Happening::TaskStarted { task } => format!("task {task} started"),
        w => w.kind().replace('_', " "),
    }
}

/// The events of a trial on a time axis, seconds since the recording's start.
pub fn timeline(trace: &Trace, ticks: u64, report: Option<&TaskReport>) -> Markup {
    let (w, left, row_h) = (960.0, 120.0, 22.0);
    let rows = ROWS.len() + 1;
    let h = row_h * rows as f64 + 34.0;
    let span = (ticks.max(1)) as f64 / TPS;
    let x = |tick: u64| left + (w - left - 10.0) * (tick as f64 / TPS) / span;
    let step =
        [1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 60.0, 120.0, 300.0].into_iter().find(|s| span / s <= 12.0).unwrap_or(600.0);
    let axis_y = row_h * rows as f64 + 6.0;
    html! {
        svg class="timeline" viewBox=(format!("0 0 {w} {h}")) width="100%" {
            @if let Some(r) = report {
                rect x=(x(r.start_tick)) y="0" width=((x(r.end_tick) - x(r.start_tick)).max(0.5)) height=(axis_y) fill="#e8f5e9" {
                    title { "the task: " (format!("{:.2}", r.time_s)) " s" }
                }
            }
            text x="4" y=(row_h * 0.7) font-size="12" { "buttons" }
            @for p in &trace.presses {
                rect class="ev" data-kind=(p.button) x=(x(p.tick) - 1.0) y="4" width="2" height=(row_h - 8.0) fill=(colour(&p.button)) {
                    title { (p.button) " at " (format!("{:.2}", p.tick as f64 / TPS)) " s (tick " (p.tick) ")" }
                }
            }
            @for (i, (label, kinds)) in ROWS.iter().enumerate() {
                text x="4" y=(row_h * (i as f64 + 1.7)) font-size="12" { (label) }
                @for e in trace.log.iter().filter(|e| kinds.contains(&e.what.kind())) {
                    circle class="ev" data-kind=(e.what.kind()) cx=(x(e.tick)) cy=(row_h * (i as f64 + 1.5)) r="4" fill=(colour(e.what.kind())) {
                        title { (words(e)) " at " (format!("{:.2}", e.tick as f64 / TPS)) " s (tick " (e.tick) ")" }
                    }
                }
            }
            line x1=(left) y1=(axis_y) x2=(w - 10.0) y2=(axis_y) stroke="#000" {}
            @for k in 0..=((span / step) as usize) {
                @let t = k as f64 * step;
                line x1=(x((t * TPS) as u64)) y1=(axis_y) x2=(x((t * TPS) as u64)) y2=(axis_y + 4.0) stroke="#000" {}
                text x=(x((t * TPS) as u64)) y=(axis_y + 16.0) font-size="11" text-anchor="middle" { (t) " s" }
            }
        }
    }
}

/// The seconds each tree took (since the previous tree, or the task start), in planting order.
pub fn durations(report: &TaskReport) -> Markup {
    let d = tree_durations(report);
    let max = d.iter().map(|x| x.1).fold(1e-9, f64::max);
    let (w, left, bar_h) = (960.0, 230.0, 20.0);
    let h = bar_h * d.len().max(1) as f64 + 8.0;
    html! {
        svg class="durations" viewBox=(format!("0 0 {w} {h}")) width="100%" {
            @for (i, (target, s)) in d.iter().enumerate() {
                @let model = report.trees.iter().find(|t| t.target == *target).map_or("", |t| t.model.as_str());
                text x="4" y=(bar_h * (i as f64 + 0.75)) font-size="12" { "#" (i + 1) " target " (target + 1) " (" (model) ")" }
                rect class="bar" data-target=(target) data-seconds=(s) x=(left) y=(bar_h * i as f64 + 3.0) width=(((w - left - 70.0) * s / max).max(1.0)) height=(bar_h - 6.0) fill="#2e86c1" {}
                text x=(left + (w - left - 70.0) * s / max + 4.0) y=(bar_h * (i as f64 + 0.75)) font-size="12" { (format!("{s:.2}")) " s" }
            }
        }
    }
}
