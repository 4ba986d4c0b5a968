//! The impostor atlases cached on disk, so a model is baked once and not at every start.
//!
//! A cache file holds both atlases of one model, every mip level, as raw RGBA8 texels. Its name
//! is the model's name and a key ([`model_key`]): the XXH3 hash of the model's content (vertices,
//! indices, materials, images), of the bake's parameters ([`BAKE_VERSION`], the view grid, the
//! cell size, the mip levels) and of the bake shader's source, so a changed model, bake or shader
//! never reads an old atlas. Bank models are cached like the shipped ones.
//!
//! Layout (little-endian): the magic `GROVEIMP`, the version `u32`, the key `u64`, `GRID`,
//! `CELL` and `MIP_LEVELS` as `u32`, the albedo atlas's levels then the normal atlas's (each
//! level `side² × 4` bytes, `side = GRID × CELL >> level`), and the XXH3 hash of everything
//! before it as a `u64`. A file that does not match in every point is refused with a reason;
//! the caller bakes the model again and replaces the file. Files are written through a temporary
//! file and a rename (`crate::atomic_write`).
//!
//! The folder is `$GROVE_CACHE_DIR` if set (empty: no cache), else `$XDG_CACHE_HOME/grove`,
//! else `~/.cache/grove`; the atlases go into its `impostors/` folder.

use std::path::{Path, PathBuf};

use xxhash_rust::xxh3::Xxh3;

use super::MIP_LEVELS;
use super::{CELL, GRID};
use crate::models::ModelData;

/// Why a cache file could not be read, used or written: one line, printed as a warning (the
/// model is then baked again, or its atlas not kept).
#[derive(Debug, thiserror::Error)]
pub enum AtlasError {
    /// The file could not be read (`grove_systems::files`' reason, without the path).
    #[error("{}", .0.reason())]
    Read(grove_systems::files::FileError),
    /// The file's length is not the layout's.
    #[error("{found} bytes where {expected} were expected")]
    Length {
        /// The file's bytes.
        found: usize,
        /// The layout's bytes.
        expected: usize,
    },
    /// The file does not start with the magic.
    #[error("not an impostor atlas file")]
    NotAtlas,
    /// Another bake version, key or layout.
    #[error("made by another bake or for another model")]
    OtherBake,
    /// The checksum does not match.
    #[error("damaged (its checksum does not match)")]
    Damaged,
    /// Waiting for the GPU failed.
    #[error("GPU poll failed ({0})")]
    Poll(wgpu::PollError),
    /// A read-back buffer could not be mapped.
    #[error("cannot read the atlas back ({0})")]
    ReadBack(wgpu::MapRangeError),
    /// A read-back buffer shorter than its level.
    #[error("short read-back")]
    ShortReadBack,
    /// The cache folder could not be created.
    #[error("{}: cannot create ({error})", dir.display())]
    CreateDir {
        /// The folder.
        dir: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// The file could not be written (the writer's message with its causes).
    #[error("{0:#}")]
    Write(anyhow::Error),
}

/// The bake's version: raise it when the bake changes in a way the shader's source does not
/// show (the atlas layout, the formats, the view fitting).
pub const BAKE_VERSION: u32 = 1;

/// The file's magic bytes.
const MAGIC: &[u8; 8] = b"GROVEIMP";

/// The header's length in bytes: magic, version, key, grid, cell, levels.
const HEADER: usize = 8 + 4 + 8 + 4 + 4 + 4;

/// The cache folder from the environment (see the module's docs); `None` when there is none.
pub fn default_dir() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("GROVE_CACHE_DIR") {
        return (!dir.is_empty()).then(|| PathBuf::from(dir));
    }
    if let Some(xdg) = std::env::var_os("XDG_CACHE_HOME").filter(|d| !d.is_empty()) {
        return Some(PathBuf::from(xdg).join("grove"));
    }
    std::env::var_os("HOME").filter(|d| !d.is_empty()).map(|h| PathBuf::from(h).join(".cache").join("grove"))
}

/// The key of `data`'s atlases: its content, the bake's parameters and `shader` (the bake
/// shader's source).
pub fn model_key(data: &ModelData, shader: &str) -> u64 {
    let mut h = Xxh3::new();
    for v in [BAKE_VERSION, GRID, CELL, MIP_LEVELS] {
        h.update(&v.to_le_bytes());
    }
    h.update(shader.as_bytes());
    for p in &data.primitives {
        h.update(&(p.vertices.len() as u64).to_le_bytes());
        h.update(bytemuck::cast_slice(&p.vertices));
        h.update(&(p.indices.len() as u64).to_le_bytes());
        h.update(bytemuck::cast_slice(&p.indices));
        h.update(&(p.material as u64).to_le_bytes());
    }
    // Materials by their debug text, which prints every field (floats exactly).
    for m in &data.materials {
        h.update(format!("{m:?}").as_bytes());
    }
    for img in &data.images {
        h.update(&img.width.to_le_bytes());
        h.update(&img.height.to_le_bytes());
        h.update(&img.rgba);
    }
    h.digest()
}

/// The cache file of the model `name` with `key` in the folder `dir`.
pub fn file_path(dir: &Path, name: &str, key: u64) -> PathBuf {
    let safe: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' })
        .take(64)
        .collect();
    dir.join("impostors").join(format!("{safe}-{key:016x}.atlas"))
}

/// The edge of mip level `level` of an atlas, texels.
pub fn level_side(level: u32) -> u32 {
    (GRID * CELL) >> level
}

/// The bytes of one atlas's mip level.
fn level_len(level: u32) -> usize {
    let s = level_side(level) as usize;
    s * s * 4
}

/// The file's bytes: the header, `levels` (albedo levels, then normal levels) and the checksum.
pub fn encode(key: u64, levels: &[Vec<u8>]) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER + levels.iter().map(Vec::len).sum::<usize>() + 8);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&BAKE_VERSION.to_le_bytes());
    out.extend_from_slice(&key.to_le_bytes());
    for v in [GRID, CELL, MIP_LEVELS] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for l in levels {
        out.extend_from_slice(l);
    }
    let sum = xxhash_rust::xxh3::xxh3_64(&out);
    out.extend_from_slice(&sum.to_le_bytes());
    out
}

/// The levels of a file written by [`encode`] with `key`: `2 × MIP_LEVELS` texel arrays, the
/// albedo atlas's first. An error names what does not match.
pub fn decode(bytes: &[u8], key: u64) -> Result<Vec<Vec<u8>>, AtlasError> {
    let body: usize = 2 * (0..MIP_LEVELS).map(level_len).sum::<usize>();
    if bytes.len() != HEADER + body + 8 {
        return Err(AtlasError::Length { found: bytes.len(), expected: HEADER + body + 8 });
    }
    if &bytes[..8] != MAGIC {
        return Err(AtlasError::NotAtlas);
    }
    let u32_at = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap_or_default());
    let u64_at = |i: usize| u64::from_le_bytes(bytes[i..i + 8].try_into().unwrap_or_default());
    if u32_at(8) != BAKE_VERSION
        || u64_at(12) != key
        || [u32_at(20), u32_at(24), u32_at(28)] != [GRID, CELL, MIP_LEVELS]
    {
        return Err(AtlasError::OtherBake);
    }
    let end = HEADER + body;
    if xxhash_rust::xxh3::xxh3_64(&bytes[..end]) != u64_at(end) {
        return Err(AtlasError::Damaged);
    }
    let mut at = HEADER;
    let mut levels = Vec::with_capacity(2 * MIP_LEVELS as usize);
    for _ in 0..2 {
        for level in 0..MIP_LEVELS {
            let n = level_len(level);
            levels.push(bytes[at..at + n].to_vec());
            at += n;
        }
    }
    Ok(levels)
}

/// Reads every mip level of `textures` back from the GPU (waiting for it), in order.
pub fn read_back(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    textures: [&wgpu::Texture; 2],
) -> Result<Vec<Vec<u8>>, AtlasError> {
    let mut encoder =
        device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("impostor read-back") });
    let mut buffers = Vec::new();
    for t in textures {
        for level in 0..MIP_LEVELS {
            let side = level_side(level);
            // Rows padded to the copy alignment.
            let row = (side * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("impostor read-back"),
                size: u64::from(row) * u64::from(side),
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture: t,
                    mip_level: level,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(side),
                    },
                },
                wgpu::Extent3d { width: side, height: side, depth_or_array_layers: 1 },
            );
            buffers.push((buffer, row, side));
        }
    }
    queue.submit([encoder.finish()]);
    for (b, _, _) in &buffers {
        b.slice(..).map_async(wgpu::MapMode::Read, |_| {});
    }
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(AtlasError::Poll)?;
    let mut levels = Vec::with_capacity(buffers.len());
    for (b, row, side) in &buffers {
        let mapped = b.slice(..).get_mapped_range().map_err(AtlasError::ReadBack)?;
        let mut texels = Vec::with_capacity((side * side * 4) as usize);
        for r in 0..*side as usize {
            let start = r * *row as usize;
            texels.extend_from_slice(mapped.get(start..start + *side as usize * 4).ok_or(AtlasError::ShortReadBack)?);
        }
        drop(mapped);
        b.unmap();
        levels.push(texels);
    }
    Ok(levels)
}

/// Writes the levels of `textures` into the cache file `path` (through a temporary file).
pub fn store(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    textures: [&wgpu::Texture; 2],
    path: &Path,
    key: u64,
) -> Result<(), AtlasError> {
    let levels = read_back(device, queue, textures)?;
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|error| AtlasError::CreateDir { dir: dir.to_path_buf(), error })?;
    }
    crate::atomic_write::write_atomic(path, &encode(key, &levels)).map_err(AtlasError::Write)
}

/// Uploads `levels` (from [`decode`]) into `textures`, every mip level.
pub fn upload(queue: &wgpu::Queue, textures: [&wgpu::Texture; 2], levels: &[Vec<u8>]) {
    for (i, t) in textures.into_iter().enumerate() {
        for level in 0..MIP_LEVELS {
            let side = level_side(level);
            let Some(texels) = levels.get(i * MIP_LEVELS as usize + level as usize) else { continue };
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: t,
                    mip_level: level,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                texels,
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(side * 4), rows_per_image: Some(side) },
                wgpu::Extent3d { width: side, height: side, depth_or_array_layers: 1 },
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn levels(seed: u8) -> Vec<Vec<u8>> {
        (0..2 * MIP_LEVELS).map(|i| vec![seed.wrapping_add(i as u8); level_len(i % MIP_LEVELS)]).collect()
    }

    #[test]
    fn a_file_reads_back_as_written_and_only_with_its_key() {
        let l = levels(3);
        let bytes = encode(42, &l);
        assert_eq!(decode(&bytes, 42).unwrap(), l);
        assert!(decode(&bytes, 43).is_err(), "another model's key");
    }

    #[test]
    fn damaged_or_short_files_are_refused() {
        let bytes = encode(7, &levels(1));
        let mut flipped = bytes.clone();
        flipped[HEADER + 1000] ^= 0x10;
        assert!(decode(&flipped, 7).unwrap_err().to_string().contains("checksum"));
        assert!(decode(&bytes[..bytes.len() - 1], 7).is_err());
        assert!(decode(&[], 7).is_err());
        let mut magic = bytes;
        magic[0] = b'X';
        assert!(decode(&magic, 7).is_err());
    }

    #[test]
    fn names_are_kept_inside_the_folder() {
        let p = file_path(Path::new("/c"), "../x y", 0xab);
        assert_eq!(p, Path::new("/c/impostors/___x_y-00000000000000ab.atlas"));
    }
}
