//! The task area from above, per condition: where every participant's ray hit (a heatmap), the
//! path of every tree moved from grab to release, the planted trees against their targets with
//! the error vectors, the interaction errors, and per target the time to satisfy it and the
//! errors near it. Drawn as SVG in world coordinates (X east, Z south: north is up) over the
//! renderer's orthographic picture of the scene.

use std::collections::BTreeMap;

use crate::render::TopView;
use glam::{Vec2, Vec3};
use grove_systems::events::Happening;
use grove_systems::task::{TargetDef, TaskDef, TaskReport};
use maud::{Markup, PreEscaped, html};

use super::trace::{CELL_M, Trace};

/// One trial as the task area sees it.
pub struct AreaTrial<'a> {
    /// Participant id.
    pub participant: &'a str,
    /// The task outcome, if the recording ran a task.
    pub report: Option<&'a TaskReport>,
    /// The re-simulation's trace.
    pub trace: &'a Trace,
}

/// An interaction error placed on the map.
#[derive(Clone, Debug)]
pub struct ErrorMark {
    /// Participant id.
    pub participant: String,
    /// `removal`, `off target` or `released green`.
    pub kind: &'static str,
    /// Where, (X, Z) metres.
    pub at: Vec2,
}

/// Per target, over the participants of a condition.
#[derive(Clone, Debug)]
pub struct TargetStats {
    /// The target's index in the task file.
    pub index: usize,
    /// Its model.
    pub model: String,
    /// Where it is, metres.
    pub position: Vec3,
    /// Trials that satisfied it, of `trials`.
    pub satisfied: usize,
    /// Trials of the condition.
    pub trials: usize,
    /// Mean seconds the tree took (since the previous tree in planting order, or the task start).
    pub mean_took_s: Option<f64>,
    /// The slowest participant on this target and their seconds.
    pub slowest: Option<(String, f64)>,
    /// Mean horizontal distance from the target to where its tree stood, metres.
    pub mean_error_m: Option<f64>,
    /// Interaction errors nearest this target.
    pub errors: usize,
}

/// One condition's task area.
pub struct Area {
    /// The condition (the task's mode or technique; `no task` for recordings without one).
    pub condition: String,
    /// The task's targets (none without a task definition).
    pub targets: Vec<TargetDef>,
    /// The rectangle shown.
    pub view: TopView,
    /// Ray hit cells per participant.
    pub heat: BTreeMap<String, BTreeMap<(i32, i32), u32>>,
    /// Moved trees' paths per participant.
    pub paths: Vec<(String, Vec<Vec2>)>,
    /// Planted trees: participant, target index, where the tree stood.
    pub planted: Vec<(String, usize, Vec2)>,
    /// Interaction errors.
    pub errors: Vec<ErrorMark>,
    /// Per target.
    pub per_target: Vec<TargetStats>,
}

fn xz(p: Vec3) -> Vec2 {
    Vec2::new(p.x, p.z)
}

/// The interaction errors of a trial during its task, placed where the tree was.
/// As the task system counts them: in manual mode a new tree appears in front of the user, so
/// only a snap is a placement there.
fn error_marks(participant: &str, report: Option<&TaskReport>, trace: &Trace, def: Option<&TaskDef>) -> Vec<ErrorMark> {
    let (targets, tolerance) = def.map_or((&[][..], 0.5), |d| (&d.targets[..], d.tolerance));
    let plant_places = def.is_none_or(|d| d.mode == grove_systems::mode::Mode::RayCasting);
    let (start, end) = report.map_or((0, u64::MAX), |r| (r.start_tick, r.end_tick));
    let mut at: BTreeMap<u64, Vec2> = BTreeMap::new();
    let mut out = Vec::new();
    let off = |p: Vec2| !targets.is_empty() && targets.iter().all(|t| xz(t.position).distance(p) > tolerance);
    for e in &trace.log {
        let during = e.tick >= start && e.tick <= end;
        let mut mark = |kind: &'static str, p: Option<Vec2>| {
            if let (true, Some(p)) = (during, p) {
                out.push(ErrorMark { participant: participant.to_string(), kind, at: p });
            }
        };
        match &e.what {
            Happening::Planted { tree, position, .. } | Happening::Snapped { tree, position } => {
                at.insert(*tree, xz(*position));
                let placement = plant_places || matches!(e.what, Happening::Snapped { .. });
                if placement && off(xz(*position)) {
                    mark("off target", Some(xz(*position)));
                }
            }
            Happening::Moved { tree, position } => {
                at.insert(*tree, xz(*position));
            }
            Happening::Removed { tree, .. } => mark("removal", at.get(tree).copied()),
            Happening::ReleasedGreen { tree } => mark("released green", at.get(tree).copied()),
            _ => {}
        }
    }
    out
}

/// How long each satisfied target's tree took: (target, seconds since the previous tree in
/// planting order, or since the task start for the first).
pub fn tree_durations(r: &TaskReport) -> Vec<(usize, f64)> {
    let mut trees: Vec<_> = r.trees.iter().collect();
    trees.sort_by_key(|t| t.tick);
    let mut prev = 0.0;
    trees
        .iter()
        .map(|t| {
            let took = t.time_s - prev;
            prev = t.time_s;
            (t.target, took)
        })
        .collect()
}

fn mean(xs: &[f64]) -> Option<f64> {
    (!xs.is_empty()).then(|| xs.iter().sum::<f64>() / xs.len() as f64)
}

/// The rectangle that holds the targets, the planted trees, the moved trees and the cells the
/// ray hit most, with a margin.
fn bounds(
    targets: &[TargetDef],
    planted: &[(String, usize, Vec2)],
    paths: &[(String, Vec<Vec2>)],
    heat: &BTreeMap<String, BTreeMap<(i32, i32), u32>>,
) -> TopView {
    let mut pts: Vec<Vec2> = targets.iter().map(|t| xz(t.position)).collect();
    pts.extend(planted.iter().map(|p| p.2));
    pts.extend(paths.iter().flat_map(|p| p.1.iter().copied()));
    let (total, max) = total_heat(heat);
    pts.extend(
        total
            .iter()
            .filter(|(_, n)| **n * 50 >= max)
            .map(|((x, z), _)| Vec2::new((*x as f32 + 0.5) * CELL_M, (*z as f32 + 0.5) * CELL_M)),
    );
    let (mut min, mut maxp) = (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN));
    for p in pts.iter().filter(|p| p.is_finite() && p.abs().max_element() < 1e4) {
        min = min.min(*p);
        maxp = maxp.max(*p);
    }
    if min.x > maxp.x {
        (min, maxp) = (Vec2::splat(-10.0), Vec2::splat(10.0));
    }
    let (mut min, mut maxp) = (min - Vec2::splat(2.5), maxp + Vec2::splat(2.5));
    // At most 120 m across, around the centre; at least 10 m.
    let c = (min + maxp) * 0.5;
    let half = ((maxp - min) * 0.5).clamp(Vec2::splat(5.0), Vec2::splat(60.0));
    (min, maxp) = (c - half, c + half);
    TopView { min, max: maxp, eye_height: 60.0 }
}

/// Gathers one condition's task area from its trials.
pub fn gather(condition: &str, trials: &[AreaTrial<'_>]) -> Area {
    let def = trials.iter().find_map(|t| t.report).and_then(|r| TaskDef::builtin(&r.id));
    let targets = def.as_ref().map_or_else(Vec::new, |d| d.targets.clone());
    let mut heat: BTreeMap<String, BTreeMap<(i32, i32), u32>> = BTreeMap::new();
    let mut paths = Vec::new();
    let mut planted = Vec::new();
    let mut errors = Vec::new();
    for t in trials {
        let cells = heat.entry(t.participant.to_string()).or_default();
        for (c, n) in &t.trace.hits {
            *cells.entry(*c).or_insert(0) += n;
        }
        paths.extend(t.trace.paths.iter().map(|p| (t.participant.to_string(), p.points.clone())));
        if let Some(r) = t.report {
            planted.extend(
                r.trees.iter().map(|tree| {
                    (t.participant.to_string(), tree.target, Vec2::new(tree.position[0], tree.position[2]))
                }),
            );
        }
        errors.extend(error_marks(t.participant, t.report, t.trace, def.as_ref()));
    }
    let per_target = targets
        .iter()
        .enumerate()
        .map(|(i, target)| {
            let mut took = Vec::new();
            let mut slowest: Option<(String, f64)> = None;
            for t in trials {
                if let Some((_, s)) = t.report.and_then(|r| tree_durations(r).into_iter().find(|(k, _)| *k == i)) {
                    took.push(s);
                    if slowest.as_ref().is_none_or(|(_, m)| s > *m) {
                        slowest = Some((t.participant.to_string(), s));
                    }
                }
            }
            let dists: Vec<f64> =
                planted.iter().filter(|p| p.1 == i).map(|p| p.2.distance(xz(target.position)) as f64).collect();
            let near = |p: Vec2| {
                targets
                    .iter()
                    .enumerate()
                    .min_by(|a, b| xz(a.1.position).distance(p).total_cmp(&xz(b.1.position).distance(p)))
                    .map(|(k, _)| k)
            };
            TargetStats {
                index: i,
                model: target.model.clone(),
                position: target.position,
                satisfied: dists.len(),
                trials: trials.iter().filter(|t| t.report.is_some()).count(),
                mean_took_s: mean(&took),
                slowest,
                mean_error_m: mean(&dists),
                errors: errors.iter().filter(|e| near(e.at) == Some(i)).count(),
            }
        })
        .collect();
    let view = bounds(&targets, &planted, &paths, &heat);
    Area { condition: condition.to_string(), targets, view, heat, paths, planted, errors, per_target }
}

/// The summed cells of the participants shown, and their maximum.
pub fn total_heat(heat: &BTreeMap<String, BTreeMap<(i32, i32), u32>>) -> (BTreeMap<(i32, i32), u32>, u32) {
    let mut total: BTreeMap<(i32, i32), u32> = BTreeMap::new();
    for cells in heat.values() {
        for (c, n) in cells {
            *total.entry(*c).or_insert(0) += n;
        }
    }
    let max = total.values().copied().max().unwrap_or(0);
    (total, max)
}

/// A cell's opacity: the square root of its share of the busiest cell (report.js draws the same).
fn heat_opacity(n: u32, max: u32) -> f64 {
    if max == 0 { 0.0 } else { 0.05 + 0.9 * (n as f64 / max as f64).sqrt() }
}

fn f(v: f32) -> String {
    format!("{v:.2}")
}

/// The per-participant cells as JSON for report.js: `{"cell": m, "p": {"P01": [[x, z, n], …]}}`.
fn heat_json(a: &Area) -> String {
    let p: serde_json::Map<String, serde_json::Value> = a
        .heat
        .iter()
        .map(|(k, cells)| {
            (
                k.clone(),
                serde_json::json!(
                    cells.iter().map(|((x, z), n)| [*x as i64, *z as i64, *n as i64]).collect::<Vec<_>>()
                ),
            )
        })
        .collect();
    // "</" cannot end the script element early: JSON allows "<\/".
    serde_json::json!({"cell": CELL_M, "p": p}).to_string().replace("</", "<\\/")
}

/// The SVG of one condition's area over its picture (`image`, a data URI, when there is one).
pub fn area_svg(a: &Area, image: Option<&str>, id: &str) -> Markup {
    let v = &a.view;
    let (w, h) = (v.max.x - v.min.x, v.max.y - v.min.y);
    let (total, max) = total_heat(&a.heat);
    let r = (w.max(h) / 150.0).max(0.08);
    html! {
        script type="application/json" id=(format!("heat-{id}")) { (PreEscaped(heat_json(a))) }
        svg class="area" id=(format!("area-{id}")) data-condition=(a.condition) viewBox=(format!("{} {} {} {}", f(v.min.x), f(v.min.y), f(w), f(h))) preserveAspectRatio="xMidYMid meet" {
            @if let Some(img) = image {
                image href=(img) x=(f(v.min.x)) y=(f(v.min.y)) width=(f(w)) height=(f(h)) preserveAspectRatio="none" {}
            } @else {
                rect x=(f(v.min.x)) y=(f(v.min.y)) width=(f(w)) height=(f(h)) fill="#7a8f5a" {}
            }
            g class="heat" data-cell=(CELL_M) data-max=(max) {
                @for ((x, z), n) in &total {
                    rect x=(f(*x as f32 * CELL_M)) y=(f(*z as f32 * CELL_M)) width=(CELL_M) height=(CELL_M) data-n=(n) fill="#ff3b00" fill-opacity=(format!("{:.3}", heat_opacity(*n, max))) {}
                }
            }
            g class="targets" {
                @for (i, t) in a.targets.iter().enumerate() {
                    circle class="target" data-target=(i) cx=(f(t.position.x)) cy=(f(t.position.z)) r=(f(r * 4.0)) fill="none" stroke="#fff" stroke-width=(f(r * 0.8)) {
                        title { "target " (i + 1) ": " (t.model) }
                    }
                    text x=(f(t.position.x + r * 5.0)) y=(f(t.position.z - r * 5.0)) font-size=(f(r * 9.0)) fill="#fff" stroke="#000" stroke-width=(f(r * 0.3)) { (i + 1) }
                }
            }
            @for (p, points) in &a.paths {
                polyline class="pp path" data-p=(p) fill="none" stroke="#1e88e5" stroke-opacity="0.8" stroke-width=(f(r * 0.7)) points=(points.iter().map(|q| format!("{},{}", f(q.x), f(q.y))).collect::<Vec<_>>().join(" ")) {}
            }
            @for (p, target, at) in &a.planted {
                @if let Some(t) = a.targets.get(*target) {
                    line class="pp vector" data-p=(p) x1=(f(t.position.x)) y1=(f(t.position.z)) x2=(f(at.x)) y2=(f(at.y)) stroke="#ffeb3b" stroke-width=(f(r * 0.7)) {}
                }
                circle class="pp planted" data-p=(p) data-target=(target) cx=(f(at.x)) cy=(f(at.y)) r=(f(r * 1.5)) fill="#ffeb3b" stroke="#000" stroke-width=(f(r * 0.3)) {
                    title { (p) ", target " (target + 1) }
                }
            }
            @for e in &a.errors {
                path class="pp error" data-p=(e.participant) d=(format!("M{} {}l{} {}m0 {}l{} {}", f(e.at.x - r * 2.0), f(e.at.y - r * 2.0), f(r * 4.0), f(r * 4.0), f(-r * 4.0), f(-r * 4.0), f(r * 4.0))) stroke="#d50000" stroke-width=(f(r * 0.9)) {
                    title { (e.participant) ": " (e.kind) }
                }
            }
        }
    }
}
