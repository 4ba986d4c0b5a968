//! `grove aerial tile IMAGE --out DIR [--tile 256] [--force]`: a photograph of any size into a
//! tiled mip pyramid on disk (see `docs/aerial-tiles.md`), streamed with a progress bar.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::anyhow;
use clap::Args;
use grove::aerial::tiles::{TileOptions, tile_image};
use indicatif::{ProgressBar, ProgressStyle};

/// Arguments of `grove aerial tile`.
#[derive(Args)]
pub struct TileArgs {
    /// The photograph: an 8-bit grey or RGB PNG (not interlaced) or TIFF (strips or tiles).
    pub image: PathBuf,
    /// The pyramid folder to write (written under a temporary name, renamed when complete).
    #[arg(long)]
    pub out: PathBuf,
    /// Tile side, texels: a power of two from 16 to 4096.
    #[arg(long, default_value_t = 256)]
    pub tile: u32,
    /// Replace a pyramid that is already at --out (a folder that is not a pyramid is never replaced).
    #[arg(long)]
    pub force: bool,
}

/// Runs `grove aerial tile`.
pub fn tile(a: TileArgs) -> anyhow::Result<ExitCode> {
    let bar = ProgressBar::new(0);
    bar.set_style(
        ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} rows {elapsed} (eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_prefix("tile");
    let t0 = Instant::now();
    let meta = tile_image(&a.image, &a.out, TileOptions { tile: a.tile, force: a.force }, &|rows, of| {
        bar.set_length(of);
        bar.set_position(rows);
    })
    .map_err(|e| anyhow!(e))?;
    bar.finish_and_clear();
    let tiles: u64 = (0..meta.levels).map(|m| meta.tiles(m)).map(|(x, y)| x as u64 * y as u64).sum();
    println!(
        "{}: {} x {} texels, {} channel(s), {} mips of tiles of {}, {} tiles, fingerprint {}, in {:.1} s",
        a.out.display(),
        meta.width,
        meta.height,
        meta.channels,
        meta.levels,
        meta.tile,
        tiles,
        meta.fingerprint,
        t0.elapsed().as_secs_f64()
    );
    Ok(ExitCode::SUCCESS)
}
