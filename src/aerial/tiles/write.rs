//! The streaming pyramid writer behind `grove aerial tile`.
//!
//! Rows come from a [`RowSource`] in bands of `tile` rows. Each mip keeps one band (its width
//! times `tile` rows): when a band is full, or the mip's last row has arrived, its tiles are
//! encoded (in parallel over the band's columns) and the band is halved into the next mip's
//! band. Memory is therefore about two bands of mip 0, O(width · tile), for any height.
//!
//! The output goes into a hidden temporary folder beside the destination, which is renamed to
//! the destination only when every tile and `pyramid.ron` are written; an existing pyramid is
//! replaced only with `force`, and a folder that is not a pyramid is never replaced.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::source::{self, RowSource};
use super::{META_FILE, PyramidMeta, check_tile, fingerprint, levels_for, shrink, tile_path};
use crate::aerial::AerialError;

/// Options of [`tile_image`].
#[derive(Clone, Copy, Debug)]
pub struct TileOptions {
    /// Tile side, texels (a power of two, 16..=4096).
    pub tile: u32,
    /// Replace an existing pyramid at the destination.
    pub force: bool,
}

impl Default for TileOptions {
    fn default() -> Self {
        TileOptions { tile: 256, force: false }
    }
}

/// Tiles the PNG or TIFF at `image` into a pyramid folder at `out`. `progress` gets the number
/// of source rows read so far (out of the image's height). Errors are one line.
pub fn tile_image(
    image: &Path,
    out: &Path,
    opts: TileOptions,
    progress: &dyn Fn(u64, u64),
) -> Result<PyramidMeta, AerialError> {
    check_tile(opts.tile)?;
    check_destination(out, opts.force)?;
    let mut src = source::open(image)?;
    let tmp = temp_dir(out);
    let _ = std::fs::remove_dir_all(&tmp);
    let result = (|| {
        std::fs::create_dir_all(&tmp).map_err(|e| AerialError::Io(e).named(tmp.display()))?;
        let meta = write_pyramid(src.as_mut(), &tmp, opts.tile, progress)?;
        let text = ron::ser::to_string_pretty(&meta, ron::ser::PrettyConfig::default()).map_err(AerialError::Ron)?;
        let meta_path = tmp.join(META_FILE);
        let mut f = File::create(&meta_path).map_err(|e| AerialError::Io(e).named(meta_path.display()))?;
        f.write_all(text.as_bytes())
            .and_then(|_| f.sync_all())
            .map_err(|e| AerialError::Io(e).named(meta_path.display()))?;
        replace_dir(&tmp, out)?;
        Ok(meta)
    })();
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&tmp);
    }
    result
}

/// Refuses a destination that exists without `force`, that is a file, or that is a folder
/// holding something other than a pyramid.
fn check_destination(out: &Path, force: bool) -> Result<(), AerialError> {
    if !out.exists() {
        return Ok(());
    }
    if !out.is_dir() {
        return Err(AerialError::OutNotFolder(out.to_path_buf()));
    }
    let empty = std::fs::read_dir(out).map(|mut d| d.next().is_none()).unwrap_or(false);
    if empty {
        return Ok(());
    }
    if !out.join(META_FILE).is_file() {
        return Err(AerialError::OutNotPyramid(out.to_path_buf()));
    }
    if !force {
        return Err(AerialError::PyramidExists(out.to_path_buf()));
    }
    Ok(())
}

/// The hidden temporary folder beside `out`.
fn temp_dir(out: &Path) -> PathBuf {
    let name = out.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "pyramid".into());
    out.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

/// Moves the finished folder `tmp` to `out`, replacing what is there (already checked).
fn replace_dir(tmp: &Path, out: &Path) -> Result<(), AerialError> {
    if out.exists() {
        let old = out.with_file_name(format!(
            ".{}.old-{}",
            out.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default(),
            std::process::id()
        ));
        std::fs::rename(out, &old).map_err(|e| AerialError::MoveAside(e).named(out.display()))?;
        if let Err(e) = std::fs::rename(tmp, out) {
            let _ = std::fs::rename(&old, out);
            return Err(AerialError::Io(e).named(out.display()));
        }
        std::fs::remove_dir_all(&old).map_err(|e| AerialError::Io(e).named(old.display()))
    } else {
        std::fs::rename(tmp, out).map_err(|e| AerialError::Io(e).named(out.display()))
    }
}

/// One mip's band of rows waiting to be cut into tiles.
struct Band {
    width: u32,
    height: u32,
    /// Rows of this mip already passed on (written as tiles).
    done: u32,
    /// `filled` rows of `width · channels` bytes.
    rows: Vec<u8>,
    filled: u32,
}

/// Streams the source into tiles under `dir` and returns the metadata.
fn write_pyramid(
    src: &mut dyn RowSource,
    dir: &Path,
    tile: u32,
    progress: &dyn Fn(u64, u64),
) -> Result<PyramidMeta, AerialError> {
    let (width, height, ch) = (src.width(), src.height(), src.channels());
    let levels = levels_for(width, height, tile);
    let mut bands: Vec<Band> = (0..levels)
        .map(|m| Band { width: shrink(width, m), height: shrink(height, m), done: 0, rows: Vec::new(), filled: 0 })
        .collect();
    let line = width as usize * ch as usize;
    let mut chunk = vec![0u8; tile as usize * line];
    let mut first_row = Vec::new();
    let mut y = 0;
    while y < height {
        let n = tile.min(height - y);
        src.read_rows(&mut chunk, n).map_err(AerialError::RowReader)?;
        if y == 0 {
            first_row = chunk[..line].to_vec();
        }
        y += n;
        let last_row = (y == height).then(|| chunk[(n as usize - 1) * line..n as usize * line].to_vec());
        push_rows(&mut bands, 0, &chunk[..n as usize * line], n, ch, tile, dir)?;
        progress(y as u64, height as u64);
        if let Some(last) = last_row {
            return Ok(PyramidMeta::new(width, height, ch, tile, fingerprint(width, height, ch, &first_row, &last)));
        }
    }
    Err(AerialError::NoRows)
}

/// Appends `n` rows to mip `mip`'s band, writing and halving it whenever it is complete.
fn push_rows(
    bands: &mut [Band],
    mip: usize,
    data: &[u8],
    n: u32,
    ch: u8,
    tile: u32,
    dir: &Path,
) -> Result<(), AerialError> {
    let line = bands[mip].width as usize * ch as usize;
    let mut at = 0u32;
    while at < n {
        let b = &mut bands[mip];
        let take = (tile - b.filled).min(n - at);
        b.rows.extend_from_slice(&data[at as usize * line..(at + take) as usize * line]);
        b.filled += take;
        at += take;
        if b.filled == tile || b.done + b.filled == b.height {
            let ty = b.done / tile;
            write_band(b, mip as u32, ty, ch, tile, dir)?;
            let half = (mip + 1 < bands.len()).then(|| halve(&bands[mip], ch));
            let b = &mut bands[mip];
            b.done += b.filled;
            b.filled = 0;
            b.rows.clear();
            if let Some((rows, count)) = half {
                push_rows(bands, mip + 1, &rows, count, ch, tile, dir)?;
            }
        }
    }
    Ok(())
}

/// Writes the band's tiles (tile row `ty` of mip `mip`) as PNG files, in parallel.
fn write_band(b: &Band, mip: u32, ty: u32, ch: u8, tile: u32, dir: &Path) -> Result<(), AerialError> {
    let across = b.width.div_ceil(tile);
    let row_dir = tile_path(dir, mip, 0, ty).parent().map(Path::to_path_buf).unwrap_or_else(|| dir.to_path_buf());
    std::fs::create_dir_all(&row_dir).map_err(|e| AerialError::Io(e).named(row_dir.display()))?;
    let line = b.width as usize * ch as usize;
    (0..across).into_par_iter().try_for_each(|tx| {
        let x0 = tx * tile;
        let w = tile.min(b.width - x0);
        let c = ch as usize;
        let mut texels = Vec::with_capacity(w as usize * b.filled as usize * c);
        for y in 0..b.filled as usize {
            let s = y * line + x0 as usize * c;
            texels.extend_from_slice(&b.rows[s..s + w as usize * c]);
        }
        let path = tile_path(dir, mip, tx, ty);
        write_tile_png(&path, w, b.filled, ch, &texels).map_err(|e| e.named(path.display()))
    })
}

/// Encodes one tile as an 8-bit grey or RGB PNG.
pub(crate) fn write_tile_png(path: &Path, w: u32, h: u32, ch: u8, texels: &[u8]) -> Result<(), AerialError> {
    let file = File::create(path).map_err(AerialError::Io)?;
    let mut enc = png::Encoder::new(BufWriter::new(file), w, h);
    enc.set_color(if ch == 1 { png::ColorType::Grayscale } else { png::ColorType::Rgb });
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    let mut writer = enc.write_header().map_err(AerialError::Png)?;
    writer.write_image_data(texels).map_err(AerialError::Png)?;
    writer.finish().map_err(AerialError::Png)
}

/// Halves a band in both directions: each texel the rounded mean of the 2 × 2 (or fewer, at an
/// odd right or bottom edge) texels below it. Returns the rows and their count.
fn halve(b: &Band, ch: u8) -> (Vec<u8>, u32) {
    let c = ch as usize;
    let (w, h) = (b.width as usize, b.filled as usize);
    let (w2, h2) = (w.div_ceil(2), h.div_ceil(2));
    let mut out = vec![0u8; w2 * h2 * c];
    out.par_chunks_mut(w2 * c).enumerate().for_each(|(y2, row)| {
        let ys = [2 * y2, (2 * y2 + 1).min(h - 1)];
        let ny = if ys[0] == ys[1] { 1 } else { 2 };
        for x2 in 0..w2 {
            let xs = [2 * x2, (2 * x2 + 1).min(w - 1)];
            let nx = if xs[0] == xs[1] { 1 } else { 2 };
            for k in 0..c {
                let mut sum = 0u32;
                for &yy in &ys[..ny] {
                    for &xx in &xs[..nx] {
                        sum += b.rows[(yy * w + xx) * c + k] as u32;
                    }
                }
                let n = (nx * ny) as u32;
                row[x2 * c + k] = ((sum + n / 2) / n) as u8;
            }
        }
    });
    (out, h2 as u32)
}
