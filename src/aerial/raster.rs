//! 8-bit RGB images in memory: reading PNG and TIFF, writing PNG through a temporary file.
//!
//! Every error is one line that names the file. Outputs are written to a temporary file in the
//! same folder and renamed into place, so a failed run never leaves a partial file, and an
//! existing file is only replaced when the caller says so.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use image::{ColorType, ImageDecoder, ImageReader, Limits};

use super::AerialError;

/// The largest image this module reads: 1 GiB of RGB texels (for example 18,000 × 18,000).
/// A larger image, or a file whose header claims one, is refused before anything is allocated.
pub const MAX_BYTES: u64 = 1 << 30;

/// An 8-bit RGB image, row-major from the top-left corner, three bytes per texel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbImage {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width * height * 3` bytes: R, G, B of each texel, rows from the top.
    pub data: Vec<u8>,
}

impl RgbImage {
    /// An image from its texels; `None` if `data` does not hold `width * height` RGB texels.
    pub fn new(width: u32, height: u32, data: Vec<u8>) -> Option<RgbImage> {
        (data.len() as u64 == width as u64 * height as u64 * 3).then_some(RgbImage { width, height, data })
    }

    /// An image from a list of texels given row by row.
    pub fn from_texels(width: u32, height: u32, texels: &[[u8; 3]]) -> Option<RgbImage> {
        RgbImage::new(width, height, texels.iter().flatten().copied().collect())
    }

    /// The number of texels.
    pub fn texels(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The texel at column `x`, row `y`.
    pub fn get(&self, x: u32, y: u32) -> [u8; 3] {
        let i = (y as usize * self.width as usize + x as usize) * 3;
        [self.data[i], self.data[i + 1], self.data[i + 2]]
    }

    /// Reads an 8-bit RGB PNG or TIFF (the format is guessed from the content). `what` names the
    /// image in errors ("summer image"). Any other colour type, a missing or unreadable file, or
    /// an image over [`MAX_BYTES`] is an error of one line.
    pub fn load(path: &Path, what: &str) -> Result<RgbImage, AerialError> {
        let name = format!("{what} {}", path.display());
        let (mut file, _) = grove_systems::files::open(path, grove_systems::files::Kind::Image)
            .map_err(|error| AerialError::OpenImage { what: what.to_string(), error })?;
        // The format comes from the content alone: a PNG or TIFF signature, whatever the file is called.
        let mut head = [0u8; 8];
        let io = |e: std::io::Error| AerialError::Access(e).named(&name);
        let n = std::io::Read::read(&mut file, &mut head).map_err(io)?;
        std::io::Seek::rewind(&mut file).map_err(io)?;
        let format = match &head[..n] {
            [0x89, b'P', b'N', b'G', ..] => image::ImageFormat::Png,
            [b'I', b'I', 42, 0, ..] | [b'M', b'M', 0, 42, ..] => image::ImageFormat::Tiff,
            _ => return Err(AerialError::NotPngOrTiff.named(&name)),
        };
        let mut reader = ImageReader::with_format(std::io::BufReader::new(file), format);
        let mut limits = Limits::default();
        limits.max_alloc = Some(MAX_BYTES + (64 << 20));
        reader.limits(limits);
        let decode = |e: image::ImageError| AerialError::Decode(one_line(&e.to_string())).named(&name);
        let decoder = reader.into_decoder().map_err(decode)?;
        let (width, height) = decoder.dimensions();
        let colour = decoder.color_type();
        if colour != ColorType::Rgb8 {
            return Err(AerialError::NotRgb8(colour_name(colour)).named(&name));
        }
        let bytes = width as u64 * height as u64 * 3;
        if bytes > MAX_BYTES || width == 0 || height == 0 {
            return Err(AerialError::ImageSize { width, height }.named(&name));
        }
        let mut data = vec![0u8; bytes as usize];
        decoder.read_image(&mut data).map_err(decode)?;
        Ok(RgbImage { width, height, data })
    }
}

fn one_line(s: &str) -> String {
    s.replace('\n', " ")
}

fn colour_name(c: ColorType) -> String {
    match c {
        ColorType::L8 => "8-bit grey".into(),
        ColorType::La8 => "8-bit grey with alpha".into(),
        ColorType::Rgba8 => "8-bit RGBA".into(),
        ColorType::L16 => "16-bit grey".into(),
        ColorType::La16 => "16-bit grey with alpha".into(),
        ColorType::Rgb16 => "16-bit RGB".into(),
        ColorType::Rgba16 => "16-bit RGBA".into(),
        other => format!("{other:?}"),
    }
}

/// Refuses to go on when any of `paths` exists and `force` is not set: one line naming the first.
pub fn check_writable(paths: &[PathBuf], force: bool) -> Result<(), AerialError> {
    for p in paths {
        if p.is_dir() {
            return Err(AerialError::IsFolder(p.clone()));
        }
        if p.exists() && !force {
            return Err(AerialError::Exists(p.clone()));
        }
    }
    Ok(())
}

/// Writes a file through a temporary file in the same folder, renamed into place when `body`
/// succeeded; on failure the temporary file is removed and nothing at `path` changes.
pub fn write_atomic(
    path: &Path,
    body: impl FnOnce(&mut BufWriter<File>) -> Result<(), AerialError>,
) -> Result<(), AerialError> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let file_name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_else(|| "out".into());
    let tmp = dir.join(format!(".{file_name}.tmp-{}", std::process::id()));
    let result = (|| {
        let file = File::create(&tmp).map_err(|e| AerialError::Access(e).named(tmp.display()))?;
        let mut w = BufWriter::with_capacity(1 << 20, file);
        body(&mut w)?;
        let io = |e: std::io::Error| AerialError::Io(e).named(path.display());
        let file = w.into_inner().map_err(|e| io(e.into_error()))?;
        file.sync_all().map_err(io)?;
        std::fs::rename(&tmp, path).map_err(io)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Writes an 8-bit PNG (`channels` 1 grey, 3 RGB) of `width × height` to `w`, row by row:
/// `body` gets the pixel stream and must write exactly all rows, top first. The whole image is
/// never held in memory.
pub fn png_stream<W: Write>(
    w: W,
    width: u32,
    height: u32,
    channels: u8,
    body: impl FnOnce(&mut dyn Write) -> Result<(), AerialError>,
) -> Result<(), AerialError> {
    let mut enc = png::Encoder::new(w, width, height);
    enc.set_color(if channels == 1 { png::ColorType::Grayscale } else { png::ColorType::Rgb });
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    let mut writer = enc.write_header().map_err(AerialError::Png)?;
    {
        let mut stream = writer.stream_writer().map_err(AerialError::Png)?;
        body(&mut stream)?;
        stream.finish().map_err(AerialError::Png)?;
    }
    writer.finish().map_err(AerialError::Png)
}

/// Writes an 8-bit PNG (`channels` 1 or 3) atomically.
pub fn write_png(path: &Path, width: u32, height: u32, channels: u8, data: &[u8]) -> Result<(), AerialError> {
    write_atomic(path, |w| {
        png_stream(w, width, height, channels, |rows| rows.write_all(data).map_err(AerialError::Io))
            .map_err(|e| e.named(path.display()))
    })
}
