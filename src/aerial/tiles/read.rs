//! The pyramid reader: a tile of any mip as RGBA8, and one clear line when a tile is missing,
//! truncated or does not belong to the pyramid.

use std::io::{BufReader, Read};
use std::path::{Path, PathBuf};

use super::{META_FILE, PyramidMeta, tile_path};
use crate::aerial::AerialError;

/// The largest `pyramid.ron` read, bytes.
const MAX_META_BYTES: u64 = 64 << 10;

/// Anything that gives tiles of a pyramid: the files on disk ([`Pyramid`]), or a stand-in in
/// tests. Shared with the clipmap's loader thread.
pub trait TileReader: Send + Sync {
    /// The pyramid's metadata.
    fn meta(&self) -> &PyramidMeta;
    /// Tile `(tx, ty)` of mip `mip` as `tile²` RGBA8 texels, rows from the top: alpha 255 inside
    /// the image, 0 (and colour 0) outside it. An error is one line.
    fn read_tile(&self, mip: u32, tx: u32, ty: u32) -> Result<Vec<u8>, AerialError>;
}

/// A pyramid folder written by `grove aerial tile`.
#[derive(Clone, Debug)]
pub struct Pyramid {
    dir: PathBuf,
    meta: PyramidMeta,
}

impl Pyramid {
    /// Opens the pyramid at `dir`: reads and checks `pyramid.ron`. Tiles are read on demand.
    pub fn open(dir: &Path) -> Result<Pyramid, AerialError> {
        let path = dir.join(META_FILE);
        if !dir.is_dir() {
            return Err(AerialError::NotPyramidFolder(dir.to_path_buf()));
        }
        let (file, _) =
            grove_systems::files::open(&path, grove_systems::files::Kind::Index).map_err(AerialError::NoPyramidMeta)?;
        let mut text = String::new();
        file.take(MAX_META_BYTES + 1)
            .read_to_string(&mut text)
            .map_err(|e| AerialError::Io(e).named(path.display()))?;
        if text.len() as u64 > MAX_META_BYTES {
            return Err(AerialError::MetaTooLong(MAX_META_BYTES >> 10).named(path.display()));
        }
        let meta: PyramidMeta = ron::from_str(&text)
            .map_err(|e| AerialError::Decode(e.to_string().replace('\n', " ")).named(path.display()))?;
        meta.validate().map_err(|e| e.named(path.display()))?;
        Ok(Pyramid { dir: dir.to_path_buf(), meta })
    }

    /// Opens the pyramid at `dir` and checks that it was made from the image whose
    /// [`fingerprint`](super::fingerprint) is `expected`.
    pub fn open_expecting(dir: &Path, expected: &str) -> Result<Pyramid, AerialError> {
        let p = Pyramid::open(dir)?;
        if !p.meta.fingerprint.eq_ignore_ascii_case(expected) {
            return Err(AerialError::OtherImage {
                dir: dir.to_path_buf(),
                found: p.meta.fingerprint.clone(),
                expected: expected.to_string(),
            });
        }
        Ok(p)
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The metadata.
    pub fn meta(&self) -> &PyramidMeta {
        &self.meta
    }

    /// Tile `(tx, ty)` of mip `mip` as RGBA8, see [`TileReader::read_tile`].
    pub fn read_tile(&self, mip: u32, tx: u32, ty: u32) -> Result<Vec<u8>, AerialError> {
        let m = &self.meta;
        if mip >= m.levels {
            return Err(AerialError::NoMip { mip, levels: m.levels }.named(self.dir.display()));
        }
        let (nx, ny) = m.tiles(mip);
        if tx >= nx || ty >= ny {
            return Err(AerialError::NoTile { tx, ty, mip, nx, ny }.named(self.dir.display()));
        }
        let path = tile_path(&self.dir, mip, tx, ty);
        let what = format!("{}: tile ({tx}, {ty}) of mip {mip}", self.dir.display());
        let (file, _) = grove_systems::files::open(&path, grove_systems::files::Kind::Image)
            .map_err(|e| AerialError::File(e).named(&what))?;
        let (w, h) = m.tile_extent(mip, tx, ty);
        let c = m.channels as usize;
        let mut dec = png::Decoder::new_with_limits(
            BufReader::new(file),
            png::Limits { bytes: 4 * (m.tile as usize).pow(2) + (1 << 20) },
        );
        dec.set_transformations(png::Transformations::IDENTITY);
        let mut reader =
            dec.read_info().map_err(|e| AerialError::Decode(e.to_string().replace('\n', " ")).named(&what))?;
        let info = reader.info();
        let expect_colour = if c == 1 { png::ColorType::Grayscale } else { png::ColorType::Rgb };
        if (info.width, info.height) != (w, h)
            || info.color_type != expect_colour
            || info.bit_depth != png::BitDepth::Eight
        {
            let foreign = AerialError::ForeignTile {
                width: info.width,
                height: info.height,
                colour: info.color_type,
                expected_width: w,
                expected_height: h,
                expected_colour: expect_colour,
            };
            return Err(foreign.named(&what));
        }
        let mut texels = vec![0u8; w as usize * h as usize * c];
        reader
            .next_frame(&mut texels)
            .map_err(|e| AerialError::DamagedTile(e.to_string().replace('\n', " ")).named(&what))?;
        let n = m.tile as usize;
        let mut rgba = vec![0u8; n * n * 4];
        for y in 0..h as usize {
            for x in 0..w as usize {
                let s = (y * w as usize + x) * c;
                let d = (y * n + x) * 4;
                if c == 1 {
                    rgba[d..d + 3].fill(texels[s]);
                } else {
                    rgba[d..d + 3].copy_from_slice(&texels[s..s + 3]);
                }
                rgba[d + 3] = 255;
            }
        }
        Ok(rgba)
    }
}

impl TileReader for Pyramid {
    fn meta(&self) -> &PyramidMeta {
        &self.meta
    }
    fn read_tile(&self, mip: u32, tx: u32, ty: u32) -> Result<Vec<u8>, AerialError> {
        Pyramid::read_tile(self, mip, tx, ty)
    }
}
