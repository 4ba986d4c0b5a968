//! `grove aerial`: treetops from summer and winter aerial photographs (see `docs/aerial.md`).
//!
//! - `grove aerial segment --summer S --winter W [--k 3] [--no-equalize] [--s 0.5 --w 0.5] [--gsd 0.1] --out DIR [--json]`
//! - `grove aerial scene --crowns DIR/crowns.csv --out SCENE.ron`
//! - `grove aerial synth --size N --seed S --out DIR`
//! - `grove aerial eval --pair DIR [--k 1,3,5,7,9]`: quality and speed against a synthetic pair's truth
//! - `grove aerial tile IMAGE --out DIR [--tile 256] [--force]`: a tiled mip pyramid (`tile.rs`)
//! - `grove aerial flight --pyramid DIR`: the clipmap's CPU half on a scripted flight (`flight.rs`)
//!
//! Outputs are written through temporary files and never replace existing files without
//! `--force`; bad input is one line on stderr and exit code 2.

pub mod bench;
pub mod flight;
pub mod layers;
pub mod tile;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{anyhow, bail};
use clap::{Args, Subcommand, ValueEnum};
use grove::aerial::crowns::{self, Summary};
use grove::aerial::eval::{Quality, Truth, evaluate};
use grove::aerial::raster::{RgbImage, check_writable, write_atomic, write_png};
use grove::aerial::scene::{SceneOptions, scene_from_crowns, scene_text};
use grove::aerial::synth::{Park, SIZE_RANGE, write_pair};
use grove::aerial::{MaskParams, Segmenter, label_crowns};
use grove_systems::catalogue::ModelKind;
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::json;

/// Subcommands of `grove aerial`.
#[derive(Subcommand)]
pub enum AerialCommand {
    /// Find deciduous treetops in a registered summer/winter pair: mask.png, crowns.csv, summary.json.
    Segment(SegmentArgs),
    /// Write a scene with a ground plane of the photographed size and a tree at each crown.
    Scene(SceneArgs),
    /// Render a synthetic park straight down in summer and winter: summer.png, winter.png, truth.csv.
    Synth(SynthArgs),
    /// Score masks of a synthetic pair against its truth for several k, with and without equalisation.
    Eval(EvalArgs),
    /// The canopy's layer masks: one treetop mask per layer, k growing with height, one bit each.
    Layers(layers::LayersArgs),
    /// A camera flight over a scene's aerial photographs, with and without the canopy: frame time, upload, memory.
    Bench(bench::AerialBenchArgs),
    /// Cut a photograph of any size into a tiled mip pyramid on disk, streaming (docs/aerial-tiles.md).
    Tile(tile::TileArgs),
    /// Fly a camera over a pyramid and measure the clipmap's CPU half: update time, texels per frame, memory.
    Flight(flight::FlightArgs),
}

/// The treetop rule's options, shared by `segment` and `eval`.
#[derive(Args, Clone)]
pub struct RuleArgs {
    /// A treetop needs more than s·n green summer texels in its k × k window (0 <= s < 1).
    #[arg(long, default_value_t = 0.5)]
    pub s: f64,
    /// A treetop needs more than w·n not-green winter texels in its window (0 <= w < 1).
    #[arg(long, default_value_t = 0.5)]
    pub w: f64,
    /// Worker threads (default: one per core); the result is the same for any number.
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Arguments of `grove aerial segment`.
#[derive(Args)]
pub struct SegmentArgs {
    /// The summer photograph: an 8-bit RGB PNG or TIFF.
    #[arg(long)]
    pub summer: PathBuf,
    /// The winter photograph of the same area, registered, of the same size.
    #[arg(long)]
    pub winter: PathBuf,
    /// The neighbourhood side in texels (odd, 1..=255).
    #[arg(long, default_value_t = 3)]
    pub k: u32,
    /// Skip the histogram equalisation of both images.
    #[arg(long)]
    pub no_equalize: bool,
    #[command(flatten)]
    pub rule: RuleArgs,
    /// Ground sample distance, metres per texel.
    #[arg(long, default_value_t = 0.1)]
    pub gsd: f64,
    /// The output folder (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Print counts and timings as JSON.
    #[arg(long)]
    pub json: bool,
    /// Overwrite outputs that already exist.
    #[arg(long)]
    pub force: bool,
}

/// Model kind of the trees a scene gets.
#[derive(Clone, Copy, ValueEnum)]
pub enum Models {
    /// Alpha-clipped cards: cheap to draw.
    Billboard,
    /// Leaf geometry.
    Mesh,
}

/// Arguments of `grove aerial scene`.
#[derive(Args)]
pub struct SceneArgs {
    /// The crowns file written by `grove aerial segment` (its summary.json must be beside it).
    #[arg(long)]
    pub crowns: PathBuf,
    /// The scene file to write (RON).
    #[arg(long)]
    pub out: PathBuf,
    /// Crowns with a smaller equivalent radius are left out as noise, metres.
    #[arg(long, default_value_t = 0.5)]
    pub min_radius: f64,
    /// Billboard or mesh tree models.
    #[arg(long, value_enum, default_value_t = Models::Billboard)]
    pub models: Models,
    /// The scene's name.
    #[arg(long, default_value = "aerial")]
    pub name: String,
    /// Latitude of the site, degrees north.
    #[arg(long, default_value_t = 47.3769, allow_hyphen_values = true)]
    pub lat: f64,
    /// Longitude of the site, degrees east.
    #[arg(long, default_value_t = 8.5417, allow_hyphen_values = true)]
    pub lon: f64,
    /// UTC time of the sun, RFC 3339.
    #[arg(long, default_value = "2026-06-21T10:00:00Z")]
    pub utc: String,
    #[command(flatten)]
    pub drape: layers::AerialSceneArgs,
    /// Overwrite the scene if it exists.
    #[arg(long)]
    pub force: bool,
}

/// Arguments of `grove aerial synth`.
#[derive(Args)]
pub struct SynthArgs {
    /// Image side, texels (16..=65536).
    #[arg(long, default_value_t = 2048)]
    pub size: u32,
    /// The seed of the park's layout and textures.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Ground sample distance, metres per texel.
    #[arg(long, default_value_t = 0.1)]
    pub gsd: f64,
    /// The output folder (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Overwrite outputs that already exist.
    #[arg(long)]
    pub force: bool,
}

/// Arguments of `grove aerial eval`.
#[derive(Args)]
pub struct EvalArgs {
    /// A folder written by `grove aerial synth` (summer.png, winter.png, truth.csv).
    #[arg(long)]
    pub pair: PathBuf,
    /// Window sides to score, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1,3,5,7,9")]
    pub k: Vec<u32>,
    #[command(flatten)]
    pub rule: RuleArgs,
    /// Crowns with a smaller equivalent radius are not counted as detections, metres.
    #[arg(long, default_value_t = 0.5)]
    pub min_radius: f64,
    /// Time each mask this many times and report the median.
    #[arg(long, default_value_t = 1)]
    pub repeat: u32,
    /// Print the results as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Runs `grove aerial ...`.
pub fn run(cmd: AerialCommand) -> anyhow::Result<ExitCode> {
    let threads = match &cmd {
        AerialCommand::Segment(a) => a.rule.threads,
        AerialCommand::Eval(a) => a.rule.threads,
        _ => None,
    };
    let pool = match threads {
        Some(n) if n == 0 || n > 256 => bail!("--threads {n} must be between 1 and 256"),
        Some(n) => rayon::ThreadPoolBuilder::new().num_threads(n).build()?,
        None => rayon::ThreadPoolBuilder::new().build()?,
    };
    pool.install(|| match cmd {
        AerialCommand::Segment(a) => segment(a),
        AerialCommand::Scene(a) => scene(a),
        AerialCommand::Synth(a) => synth(a),
        AerialCommand::Eval(a) => eval(a),
        AerialCommand::Layers(a) => layers::run(a),
        AerialCommand::Bench(a) => bench::run(a),
        AerialCommand::Tile(a) => tile::tile(a),
        AerialCommand::Flight(a) => flight::flight(a),
    })
}

fn rule(k: u32, r: &RuleArgs) -> anyhow::Result<MaskParams> {
    let p = MaskParams { k, s: r.s, w: r.w };
    p.validate().map_err(|e| anyhow!(e))?;
    Ok(p)
}

/// The range of a ground sample distance, metres per pixel: every position and area computed
/// from it then stays a finite number.
const GSD_RANGE: (f64, f64) = (1.0e-4, 1.0e3);

fn gsd_in_range(v: f64) -> anyhow::Result<()> {
    if !(GSD_RANGE.0..=GSD_RANGE.1).contains(&v) {
        bail!("--gsd {v} must be between {} and {} metres per pixel", GSD_RANGE.0, GSD_RANGE.1);
    }
    Ok(())
}

/// Creates the output folder, refusing a path that is a file.
fn out_dir(dir: &Path) -> anyhow::Result<()> {
    if dir.exists() && !dir.is_dir() {
        bail!("{}: exists and is not a folder", dir.display());
    }
    std::fs::create_dir_all(dir).map_err(|e| anyhow!("{}: {e}", dir.display()))
}

fn load_pair(summer: &Path, winter: &Path) -> anyhow::Result<(RgbImage, RgbImage)> {
    let (s, w) = rayon::join(|| RgbImage::load(summer, "summer image"), || RgbImage::load(winter, "winter image"));
    let (s, w) = (s.map_err(|e| anyhow!(e))?, w.map_err(|e| anyhow!(e))?);
    if (s.width, s.height) != (w.width, w.height) {
        bail!(
            "the summer image is {} x {} but the winter image is {} x {}; the pair must be registered and of equal size",
            s.width,
            s.height,
            w.width,
            w.height
        );
    }
    Ok((s, w))
}

fn segment(a: SegmentArgs) -> anyhow::Result<ExitCode> {
    let p = rule(a.k, &a.rule)?;
    gsd_in_range(a.gsd)?;
    let outputs = ["mask.png", "crowns.csv", "summary.json"].map(|f| a.out.join(f));
    check_writable(&outputs, a.force).map_err(|e| anyhow!(e))?;
    let t0 = Instant::now();
    let (summer, winter) = load_pair(&a.summer, &a.winter)?;
    let t_read = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let seg = Segmenter::new(&summer, &winter, !a.no_equalize).map_err(|e| anyhow!(e))?;
    drop((summer, winter));
    let t_flags = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    let mask = seg.mask(&p);
    let t_mask = t2.elapsed().as_secs_f64();
    let t3 = Instant::now();
    let found = label_crowns(&mask, seg.width, seg.height, a.gsd);
    let t_crowns = t3.elapsed().as_secs_f64();
    let treetop_texels = mask.iter().filter(|&&m| m != 0).count() as u64;
    let t4 = Instant::now();
    // Everything that can be refused is checked before the first file is written.
    crowns::check_finite(&found).map_err(|e| anyhow!("{}: {e}", outputs[1].display()))?;
    out_dir(&a.out)?;
    write_png(&outputs[0], seg.width, seg.height, 1, &mask).map_err(|e| anyhow!(e))?;
    crowns::write_csv(&outputs[1], &found).map_err(|e| anyhow!(e))?;
    let summary = Summary {
        width: seg.width,
        height: seg.height,
        gsd_m: a.gsd,
        k: p.k,
        s: p.s,
        w: p.w,
        equalize: !a.no_equalize,
        treetop_texels,
        crowns: found.len(),
    };
    let text = serde_json::to_string_pretty(&summary)?;
    write_atomic(&outputs[2], |w| {
        std::io::Write::write_all(w, text.as_bytes()).map_err(grove::aerial::AerialError::Io)
    })
    .map_err(|e| anyhow!(e))?;
    let t_write = t4.elapsed().as_secs_f64();
    if a.json {
        crate::cli::print_json(&json!({
            "width": seg.width,
            "height": seg.height,
            "k": p.k,
            "equalize": !a.no_equalize,
            "treetop_texels": treetop_texels,
            "crowns": found.len(),
            "threads": rayon::current_num_threads(),
            "seconds": {
                "read": t_read,
                "equalize_and_flags": t_flags,
                "mask": t_mask,
                "segment": t_flags + t_mask,
                "crowns": t_crowns,
                "write": t_write,
                "total": t0.elapsed().as_secs_f64(),
            },
        }))?;
    } else {
        println!(
            "{}: {} x {} texels, k = {}, equalised: {}, {} treetop texels ({:.1} %), {} crowns; segmented in {:.3} s",
            a.out.display(),
            seg.width,
            seg.height,
            p.k,
            !a.no_equalize,
            treetop_texels,
            100.0 * treetop_texels as f64 / (seg.width as f64 * seg.height as f64),
            found.len(),
            t_flags + t_mask
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn scene(a: SceneArgs) -> anyhow::Result<ExitCode> {
    if !(a.min_radius.is_finite() && a.min_radius >= 0.0) {
        bail!("--min-radius {} must be a non-negative number of metres", a.min_radius);
    }
    check_writable(std::slice::from_ref(&a.out), a.force).map_err(|e| anyhow!(e))?;
    let summary = crowns::read_summary(&a.crowns).map_err(|e| anyhow!(e))?;
    let found = crowns::read_csv(&a.crowns).map_err(|e| anyhow!(e))?;
    let opts = SceneOptions {
        name: a.name.clone(),
        size_m: (summary.width as f64 * summary.gsd_m, summary.height as f64 * summary.gsd_m),
        min_radius_m: a.min_radius,
        kind: match a.models {
            Models::Billboard => ModelKind::Billboard,
            Models::Mesh => ModelKind::Mesh,
        },
        sun: (a.lat, a.lon, a.utc.clone()),
    };
    let (mut scene, skipped) = scene_from_crowns(&found, &opts).map_err(|e| anyhow!("{}: {e}", a.out.display()))?;
    let trees = scene.trees.len();
    if a.drape.aerial {
        let dir = a.out.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        out_dir(dir)?;
        layers::drape(&mut scene, &a.drape, &a.crowns, opts.size_m, summary.gsd_m, a.min_radius, dir)
            .map_err(|e| anyhow!("{}: {e}", a.out.display()))?;
    }
    let text = scene_text(&scene, &a.crowns.display().to_string()).map_err(|e| anyhow!("{}: {e}", a.out.display()))?;
    if let Some(dir) = a.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        out_dir(dir)?;
    }
    write_atomic(&a.out, |w| std::io::Write::write_all(w, text.as_bytes()).map_err(grove::aerial::AerialError::Io))
        .map_err(|e| anyhow!(e))?;
    println!(
        "{}: {} trees on {:.1} x {:.1} m ({} crowns under {} m left out)",
        a.out.display(),
        trees,
        opts.size_m.0,
        opts.size_m.1,
        skipped,
        a.min_radius
    );
    Ok(ExitCode::SUCCESS)
}

fn synth(a: SynthArgs) -> anyhow::Result<ExitCode> {
    if !(SIZE_RANGE.0..=SIZE_RANGE.1).contains(&a.size) {
        bail!("--size {} must be between {} and {} texels", a.size, SIZE_RANGE.0, SIZE_RANGE.1);
    }
    gsd_in_range(a.gsd)?;
    let outputs = ["summer.png", "winter.png", "truth.csv", "distractors.csv"].map(|f| a.out.join(f));
    check_writable(&outputs, a.force).map_err(|e| anyhow!(e))?;
    out_dir(&a.out)?;
    let park = Park::layout(a.size, a.gsd, a.seed);
    let bar = ProgressBar::new(a.size as u64);
    bar.set_style(
        ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} rows {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_prefix("synth");
    let t0 = Instant::now();
    write_pair(&park, &a.out, &|rows| bar.set_position(rows)).map_err(|e| anyhow!(e))?;
    bar.finish_and_clear();
    let deciduous = park.trees.iter().filter(|t| t.species.deciduous()).count();
    println!(
        "{}: {} x {} texels ({:.1} m square), {} trees ({} deciduous, {} conifers), {} green distractors, in {:.1} s",
        a.out.display(),
        a.size,
        a.size,
        a.size as f64 * a.gsd,
        park.trees.len(),
        deciduous,
        park.trees.len() - deciduous,
        park.distractors.len(),
        t0.elapsed().as_secs_f64()
    );
    Ok(ExitCode::SUCCESS)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn eval(a: EvalArgs) -> anyhow::Result<ExitCode> {
    if a.k.is_empty() {
        bail!("--k needs at least one window side");
    }
    let params: Vec<MaskParams> = a.k.iter().map(|&k| rule(k, &a.rule)).collect::<anyhow::Result<_>>()?;
    if a.repeat == 0 || a.repeat > 100 {
        bail!("--repeat {} must be between 1 and 100", a.repeat);
    }
    if !(a.min_radius.is_finite() && a.min_radius >= 0.0) {
        bail!("--min-radius {} must be a non-negative number of metres", a.min_radius);
    }
    let truth = Truth::read(&a.pair).map_err(|e| anyhow!(e))?;
    let (summer, winter) = load_pair(&a.pair.join("summer.png"), &a.pair.join("winter.png"))?;
    let gsd = truth.trees.first().map_or(0.1, |t| t.radius_m / t.radius_px);
    let (w, h) = (summer.width, summer.height);
    let mut rows = Vec::new();
    for equalize in [false, true] {
        let t0 = Instant::now();
        let seg = Segmenter::new(&summer, &winter, equalize).map_err(|e| anyhow!(e))?;
        let t_flags = t0.elapsed().as_secs_f64();
        for p in &params {
            let mut times = Vec::new();
            let mut mask = Vec::new();
            for _ in 0..a.repeat {
                let t = Instant::now();
                mask = seg.mask(p);
                times.push(t.elapsed().as_secs_f64());
            }
            let t = Instant::now();
            let found = label_crowns(&mask, w, h, gsd);
            let t_crowns = t.elapsed().as_secs_f64();
            let q = evaluate(&mask, &found, &truth, w, h, a.min_radius / gsd);
            rows.push((equalize, p.k, q, t_flags, median(times), t_crowns));
        }
    }
    if a.json {
        let list: Vec<_> = rows
            .iter()
            .map(|(eq, k, q, tf, tm, tc)| json!({"equalize": eq, "k": k, "quality": q, "seconds": {"equalize_and_flags": tf, "mask": tm, "crowns": tc}}))
            .collect();
        crate::cli::print_json(
            &json!({"width": w, "height": h, "threads": rayon::current_num_threads(), "results": list}),
        )?;
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "{}: {w} x {h} texels, {} trees, {} threads",
        a.pair.display(),
        truth.trees.len(),
        rayon::current_num_threads()
    );
    println!(
        "| equalised | k | mask P | mask R | mask F1 | F1 outside distractors | centre P | centre R | centre F1 | crowns | conifer texels in mask | distractor texels in mask | flags s | mask s |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (eq, k, q, tf, tm, _) in &rows {
        println!(
            "| {} | {k} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {} | {} | {} | {tf:.3} | {tm:.3} |",
            if *eq { "yes" } else { "no" },
            q.mask.precision,
            q.mask.recall,
            q.mask.f1,
            q.mask_outside_distractors.f1,
            q.centres.precision,
            q.centres.recall,
            q.centres.f1,
            q.crowns,
            percent(q.conifer_texels_in_mask, q.conifer_texels),
            distractor_text(q)
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn percent(a: u64, b: u64) -> String {
    if b == 0 { "-".into() } else { format!("{:.1} %", 100.0 * a as f64 / b as f64) }
}

fn distractor_text(q: &Quality) -> String {
    q.distractors.iter().map(|(k, (n, m))| format!("{k} {}", percent(*m, *n))).collect::<Vec<_>>().join(", ")
}
