//! `grove play`: an interactive session in a window, optionally recorded.

pub mod view;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::anyhow;
use clap::Args;
use grove_systems::replay::{session_start_at, SessionFields};
use grove_systems::scene::Scene;
use grove_systems::task::TaskDef;
use grove_systems::Sim;

use crate::desktop::budget::{Budget, Quality};
use crate::desktop::play::PlayApp;
use crate::desktop::session::{create_recording, LiveSession};

/// Arguments of `grove play`.
#[derive(Args)]
pub struct PlayArgs {
    /// A scene file (RON); default: the built-in study scene.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Start this study task at once (ray-casting-7 or manual-7) instead of the start menu.
    #[arg(long)]
    pub task: Option<String>,
    /// Skip the start menu and start free planting.
    #[arg(long, conflicts_with = "task")]
    pub free: bool,
    /// The participant id written to the recording, e.g. P01.
    #[arg(long)]
    pub participant: Option<String>,
    /// Start with this interaction technique: ray-casting, manual or a registered plug-in
    /// (e.g. gaze-dwell; `docs/techniques.md`). A recording names a plug-in and its version.
    /// A study task brings its own technique, so this conflicts with --task.
    #[arg(long, value_name = "NAME", conflicts_with = "task")]
    pub technique: Option<String>,
    /// Record the session to this new file (never overwritten).
    #[arg(long)]
    pub record: Option<PathBuf>,
    /// The RNG seed (default: the scene's seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Draw a simple painted view instead of the wgpu renderer (faster on software GPUs).
    #[arg(long)]
    pub simple_view: bool,
    /// The 3D view's internal resolution: `auto` (lowered while frames take longer than 40 ms,
    /// then scaled up to the window), `full`, or a fixed scale between 0.3 and 1 (e.g. 0.5).
    #[arg(long, default_value = "auto", value_parser = parse_quality)]
    pub quality: Quality,
    /// Run for this many seconds from the first frame, then quit and print the frame rate as
    /// JSON (frames after the first 3 s; for measuring the window, e.g. under Xvfb).
    #[arg(long, value_name = "SECONDS", value_parser = parse_measure)]
    pub measure: Option<f64>,
    /// A model-bank folder (repeatable): its models join the menu after the shipped ones, and
    /// the scene may name them. GROVE_BANK's folders come after these.
    #[arg(long = "bank", value_name = "DIR")]
    pub banks: Vec<PathBuf>,
}

fn parse_measure(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 3.0 && v <= 3600.0 => Ok(v),
        _ => Err(format!("'{s}' is not a number of seconds above 3 (the warm-up) and at most 3600")),
    }
}

fn parse_quality(s: &str) -> Result<Quality, String> {
    s.parse()
}

/// Runs `grove play`.
pub fn run(args: PlayArgs) -> anyhow::Result<ExitCode> {
    let (scene, scene_name) = match &args.scene {
        Some(p) => {
            let scene = crate::cli::load_scene(p)?;
            let abs = std::fs::canonicalize(p).unwrap_or_else(|_| p.clone());
            (scene, abs.display().to_string())
        }
        None => (Scene::builtin("study").ok_or_else(|| anyhow!("the built-in study scene is missing"))?, "study".to_string()),
    };
    if let Some(t) = &args.task {
        if TaskDef::builtin(t).is_none() {
            return Err(anyhow!("--task {t}: unknown task; known: ray-casting-7, manual-7"));
        }
    }
    let techniques = grove_systems::technique::installed();
    let technique = match &args.technique {
        Some(name) => Some(techniques.get(name).ok_or_else(|| anyhow!("--technique: {}", techniques.unknown(name)))?),
        None => None,
    };
    let seed = args.seed.unwrap_or(scene.seed);
    let banks = grove::bank::open_for_scene(&scene, &args.banks).map_err(|e| anyhow!("{scene_name}: {e}"))?;
    let (catalogue, listed) = banks.session_catalogue().map_err(|e| anyhow!(e))?;
    crate::desktop::gpu::set_session_models(catalogue.clone(), grove::bank::model_files(&banks).map_err(|e| anyhow!(e))?);
    let sim = Sim::from_scene_with(&scene, seed, catalogue).map_err(|e| anyhow!("{scene_name}: {e}"))?;
    // The aerial photographs are opened here once, so a bad one is one line before the window.
    if grove::render::aerial_ground::open::open_sources(&scene, false).map_err(|e| anyhow!("{scene_name}: {e}"))?.is_some() {
        crate::desktop::gpu::set_session_aerial(scene.clone());
    }
    let recorder = match &args.record {
        Some(path) => {
            // The wall-clock start of the recording, so that reports order a participant's sessions.
            let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs() as i64);
            let fields = SessionFields {
                participant: args.participant.clone(),
                task: args.task.clone(),
                session_start: Some(session_start_at(now)),
                technique: technique.map(|t| t.name.to_string()),
                ..Default::default()
            };
            let mut header = fields.header(&scene_name, seed, scene.dt).map_err(|e| anyhow!("--{e}"))?;
            header.models = listed.clone();
            Some(create_recording(path, &header).map_err(|e| anyhow!(e))?)
        }
        None => None,
    };
    let mut session = LiveSession::new(sim, recorder);
    session.record_path = args.record.clone();
    if let Some(t) = technique {
        session.queue(grove_systems::input::InputEvent::SwitchTechnique { technique: t.name.to_string() }).map_err(|e| anyhow!(e))?;
    }
    let mut app = PlayApp::new(session, args.task.as_deref(), args.free).map_err(|e| anyhow!(e))?;
    app.ui.stats.recording = args.record.as_ref().map(|p| p.display().to_string());
    app.measure = args.measure.map(|seconds| crate::desktop::play::Measure { seconds, frames: 0, time: 0.0, scale_sum: 0.0, first_frame: None, cpu_start: None });
    if !args.simple_view {
        app.world3d.factory = Some(crate::desktop::gpu::make_renderer);
        app.world3d.budget = Budget::new(args.quality);
        app.thumbnails = Some(crate::desktop::gpu::render_thumbnails);
    }
    crate::desktop::window::run("grove play", app).map_err(|e| anyhow!(e))?;
    Ok(ExitCode::SUCCESS)
}
