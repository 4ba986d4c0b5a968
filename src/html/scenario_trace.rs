//! A scenario's trace (`grove test --trace DIR`, and every failed scenario under `--keep DIR`):
//! one self-contained HTML page, as a browser test's trace viewer shows a test. Each step with
//! its ticks and what it did (planted, selected, nothing …); a frame before and after it from
//! the head and from above, with the ray, the point it meets and the selection drawn; the
//! failing step and its message highlighted; the `grove view FILE --at TICK` command of each
//! step. Nothing is loaded from the network: the frames are JPEG data URIs (each tick's once, in
//! a JSON table the page's script hands to the images), the style and script inline.
//!
//! The scenario is run once more for it ([`run_traced`]): the same run, deterministic, with a
//! frame rendered at the start and after each step that ran a tick (320 × 180, lavapipe where
//! there is no GPU). Without a GPU the page is written without pictures, saying why.

use std::collections::BTreeMap;
use std::path::Path;

use glam::{Vec2, Vec3};
use grove_systems::Sim;
use grove_systems::scenario::Loaded;
use grove_systems::scenario::observe::Snapshot;
use grove_systems::scenario::run::{Failure, Outcome, RunOptions, StepTrace, run_traced};
use maud::{Markup, PreEscaped, html};

use super::HtmlError;
use super::shots::{FRAME_SIZE, Shots};
use crate::render::TopView;

const CSS: &str = include_str!("scenario_trace.css");
const JS: &str = include_str!("scenario_trace.js");

/// How far a ray that meets nothing is drawn, metres.
const RAY_DRAWN: f32 = 30.0;

/// What a trace shows, gathered from one traced run.
pub struct Traced {
    /// The run's outcome.
    pub outcome: Outcome,
    /// Each step that ran.
    pub steps: Vec<StepTrace>,
    /// Per tick, its head and top frames as data URIs.
    pub frames: BTreeMap<u64, (String, String)>,
    /// Why there are no pictures, if there are none.
    pub no_pictures: Option<String>,
    /// The rectangle the top view shows.
    pub view: TopView,
}

/// The rectangle around every ray, hit, tree and target of the run, with a margin, in the
/// frames' shape.
fn top_view(steps: &[StepTrace]) -> TopView {
    let mut pts: Vec<Vec2> = Vec::new();
    for s in steps.iter().flat_map(|s| [&s.before, &s.after]) {
        pts.push(Vec2::new(s.ray_origin.x, s.ray_origin.z));
        let end = s.ray_end(RAY_DRAWN.min(12.0));
        pts.push(Vec2::new(end.x, end.z));
        pts.extend(s.trees.iter().chain(&s.targets).map(|&(x, z)| Vec2::new(x, z)));
    }
    let (mut min, mut max) =
        pts.iter().fold((Vec2::splat(f32::MAX), Vec2::splat(f32::MIN)), |(a, b), p| (a.min(*p), b.max(*p)));
    if pts.is_empty() {
        (min, max) = (Vec2::splat(-10.0), Vec2::splat(10.0));
    }
    let (min, max) = (min - Vec2::splat(2.0), max + Vec2::splat(2.0));
    let c = (min + max) * 0.5;
    let aspect = FRAME_SIZE.0 as f32 / FRAME_SIZE.1 as f32;
    let mut half = ((max - min) * 0.5).max(Vec2::splat(4.0));
    if half.x / half.y < aspect {
        half.x = half.y * aspect;
    } else {
        half.y = half.x / aspect;
    }
    TopView { min: c - half, max: c + half, eye_height: 60.0 }
}

/// Runs the scenario once more, rendering a frame pair at every tick a step ended on.
pub fn trace(loaded: &Loaded, options: &RunOptions) -> Result<Traced, grove_systems::scenario::RunError> {
    // The rectangle comes from the run itself: a first run without pictures finds it.
    let (_, steps) = run_traced(loaded, options, &mut |_| {})?;
    let view = top_view(&steps);
    let mut shots = Shots::new().map_err(|e| e.to_string());
    let mut frames = BTreeMap::new();
    let mut failed: Option<String> = None;
    let mut shoot = |sim: &Sim| {
        let Ok(shots) = shots.as_mut() else { return };
        if failed.is_some() {
            return;
        }
        let tick = grove_systems::scenario::observe::tick(sim);
        let pair = shots.frame_pair(sim, view);
        match pair {
            Ok(p) => {
                frames.insert(tick, p);
            }
            Err(e) => failed = Some(e.to_string()),
        }
    };
    let (outcome, steps) = run_traced(loaded, options, &mut shoot)?;
    let no_pictures = match (shots, failed) {
        (Err(e), _) => Some(e),
        (_, Some(e)) => Some(e),
        _ => None,
    };
    if no_pictures.is_some() {
        frames.clear();
    }
    Ok(Traced { outcome, steps, frames, no_pictures, view })
}

fn p3(p: Vec3) -> String {
    format!("({:.2}, {:.2}, {:.2})", p.x, p.y, p.z)
}

/// The view from above at one tick: the rendered ground (filled in by the script), the trees'
/// bases, the targets (numbered from 1), the ray, the point it meets and the selection.
fn top_svg(view: &TopView, s: &Snapshot, frame: Option<&str>) -> Markup {
    let (w, h) = (view.max.x - view.min.x, view.max.y - view.min.y);
    let r = w / 320.0;
    let f = |v: f32| format!("{v:.3}");
    let end = s.ray_end(RAY_DRAWN);
    html! {
        svg class="top" viewBox=(format!("{} {} {} {}", f(view.min.x), f(view.min.y), f(w), f(h))) width="320" height="180" xmlns="http://www.w3.org/2000/svg" {
            rect x=(f(view.min.x)) y=(f(view.min.y)) width=(f(w)) height=(f(h)) fill="#6f8a4f" {}
            @if let Some(id) = frame { image class="top-frame" data-frame=(id) x=(f(view.min.x)) y=(f(view.min.y)) width=(f(w)) height=(f(h)) preserveAspectRatio="none" {} }
            @for (x, z) in &s.trees { circle class="tree" cx=(f(*x)) cy=(f(*z)) r=(f(r * 3.0)) fill="none" stroke="#0b3d0b" stroke-width=(f(r)) {} }
            @for (i, (x, z)) in s.targets.iter().enumerate() {
                circle class="target" cx=(f(*x)) cy=(f(*z)) r=(f(r * 5.0)) fill="none" stroke="#ff4fd8" stroke-width=(f(r)) {}
                text x=(f(x + r * 6.0)) y=(f(z - r * 6.0)) font-size=(f(r * 10.0)) fill="#fff" { (i + 1) }
            }
            @if let Some(b) = &s.selected {
                @let (sy, cy) = b.yaw.sin_cos();
                @let corners = [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(a, c)| {
                    let (lx, lz) = (a * b.half_extents.x, c * b.half_extents.z);
                    // Rotation about +Y: x' = x cos + z sin, z' = -x sin + z cos.
                    format!("{},{}", f(b.center.x + lx * cy + lz * sy), f(b.center.z - lx * sy + lz * cy))
                });
                polygon class="selection" points=(corners.join(" ")) fill="none" stroke="#ffd600" stroke-width=(f(r * 1.5)) {}
            }
            line class="ray" x1=(f(s.ray_origin.x)) y1=(f(s.ray_origin.z)) x2=(f(end.x)) y2=(f(end.z)) stroke="#fff59d" stroke-width=(f(r * 1.2)) {}
            circle class="controller" cx=(f(s.ray_origin.x)) cy=(f(s.ray_origin.z)) r=(f(r * 2.5)) fill="#fff" {}
            @if let Some(hit) = s.hit { circle class="hit" cx=(f(hit.x)) cy=(f(hit.z)) r=(f(r * 3.5)) fill="#e53935" stroke="#fff" stroke-width=(f(r)) {} }
        }
    }
}

/// One side (before or after) of a step: its tick, the two frames and what the ray met.
fn side(class: &str, view: &TopView, s: &Snapshot, frames: &BTreeMap<u64, (String, String)>) -> Markup {
    let has = frames.contains_key(&s.tick);
    html! {
        figure class=(class) data-tick=(s.tick) {
            figcaption { (class) " · tick " (s.tick) }
            div class="pair" {
                @if has { img class="head" data-frame=(format!("h{}", s.tick)) width=(FRAME_SIZE.0) height=(FRAME_SIZE.1) alt=(format!("the head's view at tick {}", s.tick)); }
                (top_svg(view, s, has.then(|| format!("t{}", s.tick)).as_deref()))
            }
            p class="met" { "ray from " (p3(s.ray_origin)) " meets " (s.met) }
            @if let Some(b) = &s.selected { p class="sel" { "selected: " (b.words) } }
        }
    }
}

fn shell_quote(p: &str) -> String {
    if p.chars().all(|c| c.is_ascii_alphanumeric() || "/._-+".contains(c)) {
        p.to_string()
    } else {
        format!("'{}'", p.replace('\'', "'\\''"))
    }
}

/// The page.
pub fn page(loaded: &Loaded, t: &Traced, recording: &Path) -> String {
    let failure: Option<&Failure> = t.outcome.failure.as_ref();
    let failed_step = failure.and_then(|f| f.step);
    let rec = shell_quote(&recording.display().to_string());
    let frames_json = serde_json::to_string(
        &t.frames
            .iter()
            .flat_map(|(tick, (h, top))| [(format!("h{tick}"), h.as_str()), (format!("t{tick}"), top.as_str())])
            .collect::<BTreeMap<_, _>>(),
    )
    .unwrap_or_else(|_| "{}".into());
    let body = html! {
        header {
            h1 { "grove test trace: " (loaded.name) }
            p { "File " code { (loaded.path.display()) } " · scene " code { (loaded.scene_ref) } " · seed " (loaded.seed) " · " (t.outcome.ticks) " ticks · recording " code { (recording.display()) } }
            @match failure {
                None => p class="verdict pass" id="verdict" { "pass" },
                Some(f) => p class="verdict fail" id="verdict" { "FAIL " (f.to_string()) " " a href=(f.step.map_or("#end".to_string(), |n| format!("#step-{n}"))) { "(go to it)" } },
            }
            @if let Some(n) = &t.no_pictures { p class="problem" id="no-pictures" { "No pictures in this trace: " (n) } }
        }
        div class="layout" {
            nav class="steps" {
                ol {
                    @for s in &t.steps {
                        li class=[(failed_step == Some(s.number)).then_some("failed")] { a href=(format!("#step-{}", s.number)) { span class="n" { (s.number) } " " (s.text) } span class="ticks" { (s.before.tick) "–" (s.after.tick) } }
                    }
                    @if failure.is_some_and(|f| f.step.is_none()) { li class="failed" { a href="#end" { "end expectations" } } }
                }
            }
            main {
                @for s in &t.steps {
                    @let failed = failed_step == Some(s.number);
                    section class=(if failed { "step failed" } else { "step" }) id=(format!("step-{}", s.number)) data-step=(s.number) {
                        h2 { span class="n" { (s.number) } " " code { (s.text) } span class="ticks" { " ticks " (s.before.tick) " → " (s.after.tick) } }
                        p class="did" { @if s.did.is_empty() { "did: nothing" } @else { "did: " (s.did.join("; ")) } }
                        @if failed { @if let Some(f) = failure { p class="message" { (f.message) } } }
                        div class="sides" { (side("before", &t.view, &s.before, &t.frames)) (side("after", &t.view, &s.after, &t.frames)) }
                        p { "Open it: " code class="cmd" { "grove view " (rec) " --at " (s.before.tick) } }
                    }
                }
                section class=(if failure.is_some_and(|f| f.step.is_none()) { "end failed" } else { "end" }) id="end" {
                    h2 { "End expectations" }
                    ul { @for e in &loaded.scenario.expect { li { code { (e.text()) } } } }
                    @if let Some(f) = failure.filter(|f| f.step.is_none()) { p class="message" { (f.to_string()) } }
                    @if failure.is_some_and(|f| f.step.is_some()) { p { "Not checked: the run stopped at the failing step." } }
                }
            }
        }
        script type="application/json" id="frames" { (PreEscaped(frames_json.replace("</", "<\\/"))) }
    };
    super::page::self_contained(&format!("grove test trace: {}", loaded.name), CSS, JS, body)
}

/// Traces a scenario into `out` (through a temporary file and a rename); `recording` is where
/// its recording is, for the `grove view` commands.
pub fn write(loaded: &Loaded, options: &RunOptions, recording: &Path, out: &Path) -> Result<Traced, HtmlError> {
    let traced = trace(loaded, options)
        .map_err(|e| HtmlError::Write { path: out.display().to_string(), reason: e.to_string() })?;
    let text = page(loaded, &traced, recording);
    crate::atomic_write::write_atomic(out, text.as_bytes())
        .map_err(|e| HtmlError::Write { path: out.display().to_string(), reason: e.to_string() })?;
    Ok(traced)
}
