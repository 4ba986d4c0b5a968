//! `grove aerial layers SUMMER WINTER --out FILE`: the canopy's layer masks (see
//! `docs/aerial.md`): one treetop mask per layer with the window side growing from `--k` at the
//! crown base to `--k-top` at the top, packed one bit per layer (bit i: layer i) into an 8-bit
//! RGB PNG whose three channels hold the same byte. Computed in memory, for pairs that fit it.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{anyhow, bail};
use clap::Args;
use grove::aerial::Segmenter;
use grove::aerial::layers::{layer_ks, layer_masks};
use grove::aerial::raster::{RgbImage, check_writable, write_png};
use indicatif::{ProgressBar, ProgressStyle};

/// Arguments of `grove aerial layers`.
#[derive(Args)]
pub struct LayersArgs {
    /// The summer photograph: an 8-bit RGB PNG or TIFF.
    pub summer: PathBuf,
    /// The winter photograph of the same area, registered, of the same size.
    pub winter: PathBuf,
    /// The layer-mask PNG to write.
    #[arg(long)]
    pub out: PathBuf,
    /// The number of canopy layers (1..=8), one bit each.
    #[arg(long, default_value_t = 6)]
    pub layers: u32,
    /// The window side of the lowest layer (odd).
    #[arg(long, default_value_t = 3)]
    pub k: u32,
    /// The window side of the highest layer (odd, at least --k): larger rounds the crowns more.
    #[arg(long, default_value_t = 31)]
    pub k_top: u32,
    /// A treetop needs more than s·n green summer texels in its window (0 <= s < 1).
    #[arg(long, default_value_t = 0.5)]
    pub s: f64,
    /// A treetop needs more than w·n not-green winter texels in its window (0 <= w < 1).
    #[arg(long, default_value_t = 0.5)]
    pub w: f64,
    /// Skip the histogram equalisation of both images.
    #[arg(long)]
    pub no_equalize: bool,
    /// Overwrite the output if it exists.
    #[arg(long)]
    pub force: bool,
}

/// Runs `grove aerial layers`.
pub fn run(a: LayersArgs) -> anyhow::Result<ExitCode> {
    let ks = layer_ks(a.layers, a.k, a.k_top).map_err(|e| anyhow!(e))?;
    grove::aerial::MaskParams { k: a.k, s: a.s, w: a.w }.validate().map_err(|e| anyhow!(e))?;
    if !a.out.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
        bail!("{}: --out must name a .png file", a.out.display());
    }
    check_writable(std::slice::from_ref(&a.out), a.force).map_err(|e| anyhow!(e))?;
    let summer = RgbImage::load(&a.summer, "summer image").map_err(|e| anyhow!(e))?;
    let winter = RgbImage::load(&a.winter, "winter image").map_err(|e| anyhow!(e))?;
    if (summer.width, summer.height) != (winter.width, winter.height) {
        bail!(
            "the summer image is {} x {} but the winter image is {} x {}; the pair must be registered and of equal size",
            summer.width,
            summer.height,
            winter.width,
            winter.height
        );
    }
    let bar = ProgressBar::new(u64::from(a.layers) + 1);
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len}").unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message("layer masks");
    let seg = Segmenter::new(&summer, &winter, !a.no_equalize).map_err(|e| anyhow!(e))?;
    drop((summer, winter));
    bar.inc(1);
    let mut packed = vec![0u8; seg.width as usize * seg.height as usize];
    for (i, k) in ks.iter().enumerate() {
        let one = layer_masks(&seg, &[*k], a.s, a.w);
        for (p, m) in packed.iter_mut().zip(&one) {
            *p |= m << i;
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let rgb: Vec<u8> = packed.iter().flat_map(|&b| [b, b, b]).collect();
    write_png(&a.out, seg.width, seg.height, 3, &rgb).map_err(|e| anyhow!(e))?;
    let ks_text: Vec<String> = ks.iter().map(u32::to_string).collect();
    println!(
        "{}: {} layers of {} x {} texels, k = {}",
        a.out.display(),
        a.layers,
        seg.width,
        seg.height,
        ks_text.join(", ")
    );
    Ok(ExitCode::SUCCESS)
}

/// The photographs `grove aerial scene --aerial` drapes under the scene.
#[derive(Args, Clone)]
pub struct AerialSceneArgs {
    /// Drape the pair under the scene instead of placing tree models at the crowns: an `aerial`
    /// section naming the photographs, the layer masks and the crowns file (each in the scene's
    /// folder or below it), whose crowns become trees drawn as canopy layers.
    #[arg(long, requires_all = ["summer", "winter"])]
    pub aerial: bool,
    /// With --aerial: the summer photograph.
    #[arg(long, requires = "aerial")]
    pub summer: Option<PathBuf>,
    /// With --aerial: the winter photograph.
    #[arg(long, requires = "aerial")]
    pub winter: Option<PathBuf>,
    /// With --aerial: the layer masks of `grove aerial layers` (without them no canopy is drawn).
    #[arg(long, requires = "aerial")]
    pub layers: Option<PathBuf>,
}

/// `path` relative to the folder `dir`, which must hold it (at any depth); one line otherwise.
fn relative_to(path: &std::path::Path, dir: &std::path::Path) -> anyhow::Result<String> {
    let abs =
        path.canonicalize().map_err(|e| anyhow!("{}: {}", path.display(), grove_systems::scene::io_message(&e)))?;
    let base =
        dir.canonicalize().map_err(|e| anyhow!("{}: {}", dir.display(), grove_systems::scene::io_message(&e)))?;
    let rel = abs
        .strip_prefix(&base)
        .map_err(|_| anyhow!("{}: must lie in the scene's folder {} or below it", path.display(), dir.display()))?;
    rel.to_str().map(str::to_string).ok_or_else(|| anyhow!("{}: the path is not valid UTF-8", path.display()))
}

/// Turns a scene of trees at crowns into one with the pair draped under it: no trees, an
/// `aerial` section whose crowns file makes them. The photographs' centre is the world origin
/// (as `grove aerial scene` places trees). `scene_dir` is the written scene's folder.
pub fn drape(
    scene: &mut grove_systems::scene::Scene,
    a: &AerialSceneArgs,
    crowns: &std::path::Path,
    size_m: (f64, f64),
    gsd_m: f64,
    min_radius_m: f64,
    scene_dir: &std::path::Path,
) -> anyhow::Result<()> {
    let (Some(summer), Some(winter)) = (&a.summer, &a.winter) else { bail!("--aerial needs --summer and --winter") };
    scene.trees.clear();
    scene.aerial = Some(grove_systems::aerial::AerialDef {
        summer: relative_to(summer, scene_dir)?,
        winter: relative_to(winter, scene_dir)?,
        layers: a.layers.as_deref().map(|l| relative_to(l, scene_dir)).transpose()?,
        gsd_m: gsd_m as f32,
        origin: glam::Vec2::new(-size_m.0 as f32 / 2.0, -size_m.1 as f32 / 2.0),
        elevation: 0.0,
        crowns: Some(relative_to(crowns, scene_dir)?),
        model: "broadleaf-mesh".into(),
        min_radius_m: min_radius_m as f32,
        height_per_radius: 3.0,
        layer_count: 6,
        crown_list: Vec::new(),
    });
    scene.validate().map_err(|e| anyhow!(e))
}
