//! Tiled mip pyramids of aerial photographs of any size (issue #22; format in
//! `docs/aerial-tiles.md`).
//!
//! A pyramid folder holds `pyramid.ron` (the [`PyramidMeta`]) and one PNG per tile at
//! `<mip>/<ty>/<tx>.png`. Mip 0 is the photograph itself; each mip above halves both sides
//! (rounding up), each texel the mean of the 2 × 2 texels below it that exist. Tiles are
//! `tile × tile` texels, except those on the right and bottom edges, which hold only the part
//! inside the image. The last mip is the first one that fits in a single tile.
//!
//! The parts:
//!
//! - [`source`]: PNG (row by row) and TIFF (strip by strip, or a row of tiles at a time) read
//!   as a stream of rows, 8-bit grey or RGB;
//! - [`write`]: the streaming writer behind `grove aerial tile`: memory O(width · tile) per mip,
//!   output into a temporary folder renamed into place at the end;
//! - [`read`]: [`Pyramid`], the reader: a tile as RGBA8 with alpha 0 outside the image, and one
//!   clear line for a missing, truncated or foreign tile.
//!
//! Texel coordinates: x to the right (east), y down (south); mip `m`'s texel `(u, v)` covers mip
//! 0's texels `[u · 2^m, (u + 1) · 2^m) × [v · 2^m, (v + 1) · 2^m)`.

pub mod read;
pub mod source;
pub mod write;

#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::AerialError;

pub use read::{Pyramid, TileReader};
pub use write::{TileOptions, tile_image};

/// The `format` field of every `pyramid.ron`.
pub const FORMAT: &str = "grove-pyramid";
/// The version of the pyramid format this code writes and reads.
pub const VERSION: u32 = 1;
/// The largest image side a pyramid holds, texels (texel coordinates fit an `i32` with room).
pub const MAX_SIDE: u32 = 1 << 20;
/// The smallest and largest tile side, texels (a power of two).
pub const TILE_RANGE: (u32, u32) = (16, 4096);
/// The name of the metadata file in a pyramid folder.
pub const META_FILE: &str = "pyramid.ron";

/// What `pyramid.ron` says about a pyramid.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PyramidMeta {
    /// Always [`FORMAT`].
    pub format: String,
    /// The format version, [`VERSION`].
    pub version: u32,
    /// Mip 0's width, texels.
    pub width: u32,
    /// Mip 0's height, texels.
    pub height: u32,
    /// Channels per texel in the tile files: 1 (grey) or 3 (RGB).
    pub channels: u8,
    /// Tile side, texels.
    pub tile: u32,
    /// The number of mips, mip 0 included.
    pub levels: u32,
    /// The source image's fingerprint ([`fingerprint`]): 16 hexadecimal digits.
    pub fingerprint: String,
    /// The tile files' format; `"png"` in version 1.
    pub tile_format: String,
}

impl PyramidMeta {
    /// The metadata of a pyramid of a `width × height` image with `channels` channels cut into
    /// tiles of `tile` texels.
    pub fn new(width: u32, height: u32, channels: u8, tile: u32, fingerprint: String) -> PyramidMeta {
        PyramidMeta {
            format: FORMAT.into(),
            version: VERSION,
            width,
            height,
            channels,
            tile,
            levels: levels_for(width, height, tile),
            fingerprint,
            tile_format: "png".into(),
        }
    }

    /// Checks every field against the format's rules; one line on failure.
    pub fn validate(&self) -> Result<(), AerialError> {
        if self.format != FORMAT {
            return Err(AerialError::PyramidFormat(self.format.clone()));
        }
        if self.version != VERSION {
            return Err(AerialError::PyramidVersion(self.version));
        }
        if !(1..=MAX_SIDE).contains(&self.width) || !(1..=MAX_SIDE).contains(&self.height) {
            return Err(AerialError::Sides { width: self.width, height: self.height });
        }
        check_tile(self.tile)?;
        if self.channels != 1 && self.channels != 3 {
            return Err(AerialError::Channels(self.channels));
        }
        let levels = levels_for(self.width, self.height, self.tile);
        if self.levels != levels {
            return Err(AerialError::Levels {
                levels: self.levels,
                width: self.width,
                height: self.height,
                tile: self.tile,
                expected: levels,
            });
        }
        if self.fingerprint.len() != 16 || !self.fingerprint.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(AerialError::Fingerprint(self.fingerprint.clone()));
        }
        if self.tile_format != "png" {
            return Err(AerialError::TileFormat(self.tile_format.clone()));
        }
        Ok(())
    }

    /// Mip `mip`'s width and height, texels.
    pub fn mip_size(&self, mip: u32) -> (u32, u32) {
        (shrink(self.width, mip), shrink(self.height, mip))
    }

    /// How many tiles mip `mip` has across and down.
    pub fn tiles(&self, mip: u32) -> (u32, u32) {
        let (w, h) = self.mip_size(mip);
        (w.div_ceil(self.tile), h.div_ceil(self.tile))
    }

    /// The width and height of the image part that tile `(tx, ty)` of mip `mip` holds, texels.
    pub fn tile_extent(&self, mip: u32, tx: u32, ty: u32) -> (u32, u32) {
        let (w, h) = self.mip_size(mip);
        (w.saturating_sub(tx * self.tile).min(self.tile), h.saturating_sub(ty * self.tile).min(self.tile))
    }
}

/// Refuses a tile side that is not a power of two inside [`TILE_RANGE`].
pub fn check_tile(tile: u32) -> Result<(), AerialError> {
    if !tile.is_power_of_two() || !(TILE_RANGE.0..=TILE_RANGE.1).contains(&tile) {
        return Err(AerialError::TileSide(tile));
    }
    Ok(())
}

/// A side of `side` texels at mip `mip`: halved `mip` times, rounding up.
pub fn shrink(side: u32, mip: u32) -> u32 {
    if mip >= 32 { 1 } else { side.div_ceil(1 << mip).max(1) }
}

/// The number of mips of a `width × height` image cut into tiles of `tile`: up to and including
/// the first mip that fits in one tile.
pub fn levels_for(width: u32, height: u32, tile: u32) -> u32 {
    let mut levels = 1;
    while shrink(width, levels - 1) > tile || shrink(height, levels - 1) > tile {
        levels += 1;
    }
    levels
}

/// The path of tile `(tx, ty)` of mip `mip` inside a pyramid folder.
pub fn tile_path(dir: &Path, mip: u32, tx: u32, ty: u32) -> PathBuf {
    dir.join(mip.to_string()).join(ty.to_string()).join(format!("{tx}.png"))
}

/// The fingerprint of a source image: XXH3 of its size, channel count, first row and last row,
/// as 16 hexadecimal digits. Two different photographs of the same size differ in it with near
/// certainty; it is cheap because a streaming reader sees both rows anyway.
pub fn fingerprint(width: u32, height: u32, channels: u8, first_row: &[u8], last_row: &[u8]) -> String {
    let mut bytes = Vec::with_capacity(first_row.len() + last_row.len() + 32);
    bytes.extend_from_slice(b"grove-pyramid-fingerprint-1");
    bytes.extend_from_slice(&width.to_le_bytes());
    bytes.extend_from_slice(&height.to_le_bytes());
    bytes.push(channels);
    bytes.extend_from_slice(first_row);
    bytes.extend_from_slice(last_row);
    format!("{:016x}", xxhash_rust::xxh3::xxh3_64(&bytes))
}

#[cfg(test)]
mod unit_tests {
    use super::*;

    #[test]
    fn levels_stop_at_the_first_mip_that_fits_one_tile() {
        // 1000 → 500 → 250: 250 fits a tile of 256, so three mips.
        assert_eq!(levels_for(1000, 10, 256), 3);
        assert_eq!(levels_for(256, 256, 256), 1);
        assert_eq!(levels_for(257, 1, 256), 2);
        assert_eq!(levels_for(32768, 32768, 256), 8);
    }

    #[test]
    fn mip_sizes_round_up_and_edge_tiles_are_partial() {
        let m = PyramidMeta::new(1000, 300, 3, 256, "0".repeat(16));
        assert_eq!(m.mip_size(1), (500, 150));
        assert_eq!(m.mip_size(2), (250, 75));
        assert_eq!(m.tiles(0), (4, 2));
        assert_eq!(m.tile_extent(0, 3, 1), (1000 - 768, 300 - 256));
        assert_eq!(m.tile_extent(0, 0, 0), (256, 256));
        assert!(m.validate().is_ok());
        let bad = PyramidMeta { levels: 2, ..m };
        assert!(bad.validate().unwrap_err().to_string().contains("levels"));
    }
}
