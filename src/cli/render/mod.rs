//! `grove render`: draw a scene, a frame sequence or any glTF 2.0 model to PNG, offscreen.
//!
//! - `grove render --scene FILE --out PNG [--width W --height H] [--no-shadows] [--no-water] [--no-grass]
//!   [--overlay none|interaction]` (the overlay defaults to `interaction` for `--replay` only)
//! - `grove render --scene FILE --frames N --fps F --out DIR [--time-rate R]`
//! - `grove render --model FILE --out PNG [--background sky|transparent] [--tick T]`
//! - `grove render --replay FILE --video OUT.mp4 [--camera head|shoulder|top|orbit] [--from T]
//!   [--to T] [--fps F] [--speed S] [--ghosts DIR]` (`video.rs`, which `main.rs` calls
//!   when `--video` is given, and `grove::video`)
//!
//! The renderer draws whatever [`Sim`] it is given ([`render_sim`]), so a world from a replay or
//! any other source can be rendered the same way.

pub mod video;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{anyhow, bail};
use clap::Args;
use grove::atomic_write::write_via_temp;
use grove::render::offscreen::{self, Gpu};
use grove::render::{RenderOptions, Renderer};
use grove_systems::Sim;

/// Arguments of `grove render`.
#[derive(Args)]
pub struct RenderArgs {
    /// The scene file (RON) to render.
    #[arg(long, conflicts_with_all = ["model", "replay"], required_unless_present_any = ["model", "replay"])]
    pub scene: Option<PathBuf>,
    /// A recording: render the world at --tick as the headless replay computes it, or the whole
    /// recording as a video (--video).
    #[arg(long, conflicts_with = "model")]
    pub replay: Option<PathBuf>,
    /// The tick of --replay to render; with --model, the model in the study's wind after this
    /// many ticks (without it, the model stands in calm air at tick 0).
    #[arg(long, conflicts_with_all = ["video", "frames"])]
    pub tick: Option<u64>,
    /// Write --replay as a video: H.264 in MP4, from --from to --to at --fps frames a second.
    #[arg(long, value_name = "OUT.mp4", requires = "replay", conflicts_with_all = ["out", "frames"])]
    pub video: Option<PathBuf>,
    /// The video's camera: the participant's `head`, over the `shoulder`, the task area from the
    /// `top`, or an `orbit` around it.
    #[arg(long, value_enum, default_value_t = grove::video::camera::CameraKind::Head, requires = "video")]
    pub camera: grove::video::camera::CameraKind,
    /// The video's first tick: a tick, or `task-start` / `task-end` (default: the recording's
    /// first tick).
    #[arg(long, value_name = "T", requires = "video")]
    pub from: Option<grove::video::Mark>,
    /// The video's last tick: a tick, or `task-start` / `task-end` (default: the recording's end).
    #[arg(long, value_name = "T", requires = "video")]
    pub to: Option<grove::video::Mark>,
    /// Simulated seconds per second of video (2: twice as fast as it happened).
    #[arg(long, default_value_t = 1.0, requires = "video")]
    pub speed: f64,
    /// A folder of recordings: every other recording of the same task in it is drawn at once,
    /// aligned at the task's start, each participant's head and ray in its own colour.
    #[arg(long, value_name = "DIR", requires = "video")]
    pub ghosts: Option<PathBuf>,
    /// A glTF 2.0 model (.gltf or .glb) to render alone, framed from its bounds.
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Behind --model: its stage (`sky`, the default: the ground and the sky), or nothing (`transparent`: the
    /// model alone, each pixel's alpha its coverage; the light and shadows are the stage's).
    #[arg(long, value_enum)]
    pub background: Option<Background>,
    /// The output PNG, or the output folder with --frames.
    #[arg(long, required_unless_present = "video")]
    pub out: Option<PathBuf>,
    /// Image width, pixels.
    #[arg(long, default_value_t = 1280)]
    pub width: u32,
    /// Image height, pixels.
    #[arg(long, default_value_t = 720)]
    pub height: u32,
    /// Turn the sun's shadow map off.
    #[arg(long)]
    pub no_shadows: bool,
    /// Leave the scene's water out (no reflection and refraction passes, no surface).
    #[arg(long)]
    pub no_water: bool,
    /// Leave out the scene's grass patches (shells and blades).
    #[arg(long)]
    pub no_grass: bool,
    /// Draw a blade lawn up to a hard edge, without its fade into the ground (for comparing with
    /// images drawn before the fade).
    #[arg(long)]
    pub no_blade_fade: bool,
    /// The interaction visuals (the controller's ray, hit marker, selection, targets): `none` or
    /// `interaction`. Default: `interaction` for --replay, `none` for --scene and --model.
    #[arg(long, value_enum)]
    pub overlay: Option<Overlay>,
    /// Draw trees whose bounding sphere covers fewer pixels than this as impostors (0: never;
    /// --model always draws the mesh).
    #[arg(long, default_value_t = grove::render::DEFAULT_IMPOSTOR_PIXELS, value_parser = crate::cli::bench::args::non_negative)]
    pub impostor_pixels: f32,
    /// Write a sequence of this many frames into the folder --out (with --scene, or with --model
    /// to see the model sway in the study's wind).
    #[arg(long, conflicts_with = "replay")]
    pub frames: Option<u32>,
    /// Frames per second of the sequence (simulated time between frames is 1/fps) or of the
    /// video (a whole number from 1 to 120).
    #[arg(long, default_value_t = 30.0)]
    pub fps: f64,
    /// Set the sun's time rate (sun seconds per simulated second), e.g. 3600 for an hour per second.
    #[arg(long)]
    pub time_rate: Option<f64>,
    /// Overwrite an existing output file.
    #[arg(long)]
    pub force: bool,
    /// Colour the levels of the aerial photographs' clipmaps (a scene with an `aerial` section).
    #[arg(long)]
    pub debug_lod: bool,
    /// Draw the photographed crowns as tree models instead of canopy layers.
    #[arg(long)]
    pub no_canopy: bool,
    /// A model-bank folder (repeatable) whose models the scene or recording names; GROVE_BANK's
    /// folders come after these.
    #[arg(long = "bank", value_name = "DIR")]
    pub banks: Vec<PathBuf>,
}

/// What `grove render --model` draws behind the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Background {
    /// The model's stage: a ground plane under it and the sky.
    Sky,
    /// Nothing: the model alone on a transparent image, its alpha the coverage.
    Transparent,
}

/// The last tick `grove render --model FILE --tick T` simulates: an hour at 60 ticks a second.
const MAX_MODEL_TICK: u64 = 216_000;

/// Which interaction visuals `grove render` draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Overlay {
    /// None: the scene as a landscape.
    None,
    /// The controller's ray, the hit marker, the anchor ball, the selection and the targets.
    Interaction,
}

/// Renders one world with an existing renderer and saves it (through a temporary file and a
/// rename, so a failed render or save leaves no file).
pub fn render_sim(gpu: &Gpu, renderer: &mut Renderer, sim: &Sim, out: &Path) -> anyhow::Result<()> {
    let img = offscreen::render_image(gpu, renderer, sim)?;
    write_via_temp(out, |tmp| Ok(offscreen::save_png(&img, tmp)?))
}

/// The renderer's options from the arguments: `--no-shadows`, `--no-water`, `--no-grass`,
/// `--no-blade-fade`, `--overlay` and `--background` are applied here and nowhere else.
fn options(args: &RenderArgs) -> RenderOptions {
    let overlay = args.overlay.unwrap_or(if args.replay.is_some() { Overlay::Interaction } else { Overlay::None });
    let sky = args.background.unwrap_or(Background::Sky) == Background::Sky;
    RenderOptions { shadows: !args.no_shadows, water: !args.no_water, grass: !args.no_grass, blade_edge_fade: !args.no_blade_fade, overlay: overlay == Overlay::Interaction, impostor_pixels: args.impostor_pixels, canopy: !args.no_canopy, background: sky, clear: if sky { wgpu::Color::BLACK } else { wgpu::Color::TRANSPARENT }, ..Default::default() }
}

/// A renderer for the arguments' size and options, with the bank models `sim`'s catalogue holds
/// (found in the scene's banks, then the session's).
/// The scene's photographs are opened before the GPU (`Gpu::new` after this), so that a bad
/// file is refused at once.
pub(super) fn renderer(gpu: &Gpu, args: &RenderArgs, sim: &Sim, scene: &grove_systems::scene::Scene, aerial: Option<grove::render::aerial_ground::AerialSources>) -> anyhow::Result<Renderer> {
    let mut renderer = Renderer::new(&gpu.device, &gpu.queue, offscreen::FORMAT, args.width, args.height)?;
    renderer.options = options(args);
    grove::bank::load_for_scene(&mut renderer, scene, &args.banks, sim.catalogue()).map_err(|e| anyhow!(e))?;
    if let Some(aerial) = aerial {
        renderer.features.aerial.set(aerial)?;
        // A still image shows the photographs as loaded: wait (briefly) for their tiles.
        renderer.features.aerial.settle(sim, renderer.size(), std::time::Duration::from_secs(20))?;
    }
    Ok(renderer)
}

pub(super) fn check_size(w: u32, h: u32) -> anyhow::Result<()> {
    if !(1..=8192).contains(&w) || !(1..=8192).contains(&h) {
        bail!("--width and --height must be between 1 and 8192 (got {w}x{h})");
    }
    Ok(())
}

/// An output file's flag and kind, for the messages of [`check_out_file`].
pub(super) struct OutFile {
    /// The flag that names it, e.g. `--out`.
    pub flag: &'static str,
    /// Its extension, without the dot.
    pub ext: &'static str,
    /// What a file name must be, after "needs", e.g. `a PNG`.
    pub name: &'static str,
    /// What the flag must name, after "must name".
    pub kind: &'static str,
}

/// `--out` of a still.
pub(super) const PNG_OUT: OutFile = OutFile { flag: "--out", ext: "png", name: "a PNG", kind: "a .png file (grove renders PNG only)" };

/// Refuses an output path that is a folder, has another extension, exists (without `--force`)
/// or lies in a missing folder.
pub(super) fn check_out_file(out: &Path, force: bool, file: &OutFile) -> anyhow::Result<()> {
    if out.is_dir() {
        bail!("{}: is a directory; {} needs {} file name", out.display(), file.flag, file.name);
    }
    if !out.extension().is_some_and(|e| e.eq_ignore_ascii_case(file.ext)) {
        bail!("{}: {} must name {}", out.display(), file.flag, file.kind);
    }
    if out.exists() && !force {
        bail!("{}: already exists (use --force to overwrite)", out.display());
    }
    if let Some(parent) = out.parent() {
        if !parent.as_os_str().is_empty() && !parent.is_dir() {
            bail!("{}: folder does not exist", parent.display());
        }
    }
    Ok(())
}

/// Checks the --frames arguments and prepares the folder: the ticks between frames.
fn frames_setup(args: &RenderArgs, out: &Path, n: u32, dt: f32) -> anyhow::Result<u64> {
    if n == 0 || n > 100_000 {
        bail!("--frames must be between 1 and 100000");
    }
    if !(args.fps.is_finite() && args.fps > 0.0 && args.fps <= 1000.0) {
        bail!("--fps must be in (0, 1000]");
    }
    if out.is_file() {
        bail!("{}: is a file; with --frames, --out names a folder", out.display());
    }
    std::fs::create_dir_all(out).map_err(|e| anyhow!("{}: cannot create folder ({e})", out.display()))?;
    let first = out.join("frame_00000.png");
    if first.exists() && !args.force {
        bail!("{}: already exists (use --force to overwrite)", first.display());
    }
    Ok(((1.0 / args.fps) / dt as f64).round().max(1.0) as u64)
}

/// A `--model` file read and checked as a bank model is ([`grove::bank::validate_gltf`]),
/// before the GPU starts; what it uses that grove does not draw is printed as warnings.
fn load_model_checked(model: &Path) -> anyhow::Result<grove::models::ModelData> {
    let data = grove::bank::validate_gltf(model).map_err(|e| anyhow!(e))?;
    for w in &data.warnings {
        eprintln!("warning: {w}");
    }
    Ok(data)
}

/// `--model FILE --frames N`: the model alone on its stage in the study scene's wind, so that its
/// wind channels (its own, or those grove computes, docs/model-bank.md) show as motion.
fn model_frames(args: &RenderArgs, out: &Path, model: &Path, n: u32) -> anyhow::Result<ExitCode> {
    let data = load_model_checked(model)?;
    let id = grove_systems::catalogue::ModelId(0);
    let mut sim = grove_systems::stage::model_stage(data.bounds, args.width as f32 / args.height as f32, false, id).map_err(|e| anyhow!(e))?;
    grove_systems::stage::in_study_wind(&mut sim).map_err(|e| anyhow!(e))?;
    let ticks_per_frame = frames_setup(args, out, n, sim.dt())?;
    let gpu = Gpu::new()?;
    let mut renderer = Renderer::empty(&gpu.device, &gpu.queue, offscreen::FORMAT, args.width, args.height, &grove::render::default_assets_dir())?;
    // The model alone on its stage is shown as itself: never as an impostor.
    renderer.options = RenderOptions { impostor_pixels: 0.0, far_pixels: 0.0, ..options(args) };
    renderer.features.trees.set_model(id, &data);
    let bar = indicatif::ProgressBar::new(n as u64);
    for f in 0..n {
        if f > 0 {
            sim.run(ticks_per_frame);
        }
        render_sim(&gpu, &mut renderer, &sim, &out.join(format!("frame_{f:05}.png")))?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    println!("{}: wrote {n} frames of {} in the study's wind, {ticks_per_frame} ticks apart, on {}", out.display(), model.display(), gpu.adapter_name());
    Ok(ExitCode::SUCCESS)
}

/// Runs `grove render`.
pub fn run(args: RenderArgs) -> anyhow::Result<ExitCode> {
    check_size(args.width, args.height)?;
    if args.background.is_some() && args.model.is_none() {
        bail!("--background goes with --model FILE only");
    }
    let out = args.out.clone().ok_or_else(|| anyhow!("give --out FILE (or --video OUT.mp4 with --replay)"))?;
    let out = out.as_path();
    if let (Some(model), Some(n)) = (&args.model, args.frames) {
        return model_frames(&args, out, model, n);
    }
    if let Some(model) = &args.model {
        check_out_file(out, args.force, &PNG_OUT)?;
        if args.tick.is_some_and(|t| t > MAX_MODEL_TICK) {
            bail!("--tick with --model must be at most {MAX_MODEL_TICK} (an hour at 60 ticks a second)");
        }
        let data = load_model_checked(model)?;
        let gpu = Gpu::new()?;
        let img = offscreen::render_model_data(&gpu, &data, args.width, args.height, options(&args), args.tick)?;
        write_via_temp(out, |tmp| Ok(offscreen::save_png(&img, tmp)?))?;
        let at = args.tick.map_or(String::new(), |t| format!(" at tick {t} in the study's wind"));
        println!("{}: rendered {}{at} ({}x{}) on {}", out.display(), model.display(), args.width, args.height, gpu.adapter_name());
        return Ok(ExitCode::SUCCESS);
    }
    if let Some(replay) = &args.replay {
        let tick = args.tick.ok_or_else(|| anyhow!("--replay needs --tick N (one picture) or --video OUT.mp4"))?;
        check_out_file(out, args.force, &PNG_OUT)?;
        let options = grove_systems::replay::ReplayOptions { until: Some(tick), banks: grove::bank::session_dirs(&args.banks), ..Default::default() };
        let outcome = grove_systems::replay::replay_file(replay, &options).map_err(|e| anyhow!("{e}"))?;
        if outcome.sim.tick() < tick {
            bail!("{}: the recording ends at tick {}, before --tick {tick}", replay.display(), outcome.sim.tick());
        }
        let scene = grove_systems::replay::scene_ref::resolve_scene(&outcome.header.scene, replay.parent()).map_err(|e| anyhow!(e))?;
        let aerial = grove::render::aerial_ground::open::open_sources(&scene, args.debug_lod).map_err(|e| anyhow!(e))?;
        let gpu = Gpu::new()?;
        let mut renderer = renderer(&gpu, &args, &outcome.sim, &scene, aerial)?;
        render_sim(&gpu, &mut renderer, &outcome.sim, out)?;
        println!("{}: rendered {} at tick {} ({}x{}) on {}", out.display(), replay.display(), tick, args.width, args.height, gpu.adapter_name());
        return Ok(ExitCode::SUCCESS);
    }
    let scene_path = args.scene.as_ref().ok_or_else(|| anyhow!("give --scene FILE, --replay FILE --tick N or --model FILE"))?;
    if args.tick.is_some() {
        bail!("--tick goes with --replay or --model, not with --scene (use --frames for a sequence)");
    }
    let mut scene = crate::cli::load_scene(scene_path)?;
    if let Some(rate) = args.time_rate {
        if !rate.is_finite() {
            bail!("--time-rate must be a finite number");
        }
        scene.sun.time_rate = rate;
    }
    let banks = grove::bank::open_for_scene(&scene, &args.banks).map_err(|e| anyhow!("{}: {e}", scene_path.display()))?;
    let (catalogue, _) = banks.session_catalogue().map_err(|e| anyhow!(e))?;
    let mut sim = Sim::from_scene_with(&scene, scene.seed, catalogue).map_err(|e| anyhow!("{}: {e}", scene_path.display()))?;
    match args.frames {
        None => {
            check_out_file(out, args.force, &PNG_OUT)?;
            let aerial = grove::render::aerial_ground::open::open_sources(&scene, args.debug_lod).map_err(|e| anyhow!(e))?;
            let gpu = Gpu::new()?;
            let mut renderer = renderer(&gpu, &args, &sim, &scene, aerial)?;
            render_sim(&gpu, &mut renderer, &sim, out)?;
            println!("{}: rendered {} at tick {} ({}x{}) on {}", out.display(), scene_path.display(), sim.tick(), args.width, args.height, gpu.adapter_name());
        }
        Some(n) => {
            let ticks_per_frame = frames_setup(&args, out, n, scene.dt)?;
            let aerial = grove::render::aerial_ground::open::open_sources(&scene, args.debug_lod).map_err(|e| anyhow!(e))?;
            let gpu = Gpu::new()?;
            let mut renderer = renderer(&gpu, &args, &sim, &scene, aerial)?;
            for f in 0..n {
                if f > 0 {
                    sim.run(ticks_per_frame);
                }
                render_sim(&gpu, &mut renderer, &sim, &out.join(format!("frame_{f:05}.png")))?;
            }
            println!(
                "{}: wrote {n} frames, {ticks_per_frame} ticks apart ({:.4} s simulated per frame), on {}",
                out.display(),
                ticks_per_frame as f64 * scene.dt as f64,
                gpu.adapter_name()
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
