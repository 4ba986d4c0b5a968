//! Images read as a stream of rows: PNG row by row (the `png` crate), TIFF strip by strip or one
//! row of tiles at a time (the `tiff` crate). Only 8-bit grey or RGB; memory stays O(width ·
//! strip or tile height) whatever the image's size.

use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;

use super::MAX_SIDE;
use crate::aerial::AerialError;

/// A source of image rows, read once from the top.
pub trait RowSource {
    /// Width, texels.
    fn width(&self) -> u32;
    /// Height, texels.
    fn height(&self) -> u32;
    /// Channels per texel: 1 (grey) or 3 (RGB).
    fn channels(&self) -> u8;
    /// Reads the next `rows` rows into `out` (`rows · width · channels` bytes).
    fn read_rows(&mut self, out: &mut [u8], rows: u32) -> Result<(), String>;
}

/// Opens a PNG or TIFF (the format is read from the first bytes, not the name) as a row source.
/// Every error is one line naming the file.
pub fn open(path: &Path) -> Result<Box<dyn RowSource>, AerialError> {
    let name = path.display().to_string();
    // Only a regular file, opened without blocking; the size is bounded by the dimensions
    // checked below, not by the file's length (a pyramid's source may be tens of gigabytes).
    let (mut file, _) =
        grove_systems::files::open(path, grove_systems::files::Kind::ImageRows).map_err(AerialError::File)?;
    let mut head = [0u8; 8];
    let io = |e: std::io::Error| AerialError::Access(e).named(&name);
    let refused = |e: String| AerialError::RowReader(e).named(&name);
    let n = file.read(&mut head).map_err(io)?;
    std::io::Seek::rewind(&mut file).map_err(io)?;
    let reader = BufReader::with_capacity(1 << 20, file);
    let source: Box<dyn RowSource> = match &head[..n] {
        [0x89, b'P', b'N', b'G', ..] => Box::new(PngRows::new(reader).map_err(refused)?),
        [b'I', b'I', 42, 0, ..] | [b'M', b'M', 0, 42, ..] | [b'I', b'I', 43, 0, ..] | [b'M', b'M', 0, 43, ..] => {
            Box::new(TiffRows::new(reader).map_err(refused)?)
        }
        _ => return Err(AerialError::NotPngOrTiff.named(&name)),
    };
    let (w, h) = (source.width(), source.height());
    if !(1..=MAX_SIDE).contains(&w) || !(1..=MAX_SIDE).contains(&h) {
        return Err(AerialError::Sides { width: w, height: h }.named(&name));
    }
    Ok(Box::new(Named { name, inner: source }))
}

/// Adds the file name to every read error.
struct Named {
    name: String,
    inner: Box<dyn RowSource>,
}

impl RowSource for Named {
    fn width(&self) -> u32 {
        self.inner.width()
    }
    fn height(&self) -> u32 {
        self.inner.height()
    }
    fn channels(&self) -> u8 {
        self.inner.channels()
    }
    fn read_rows(&mut self, out: &mut [u8], rows: u32) -> Result<(), String> {
        self.inner.read_rows(out, rows).map_err(|e| format!("{}: {e}", self.name))
    }
}

fn one_line(s: impl ToString) -> String {
    s.to_string().replace('\n', " ")
}

/// A PNG read row by row.
struct PngRows {
    reader: png::Reader<BufReader<File>>,
    width: u32,
    height: u32,
    channels: u8,
}

impl PngRows {
    fn new(r: BufReader<File>) -> Result<PngRows, String> {
        let mut dec = png::Decoder::new(r);
        // Palettes become RGB and grey of 1, 2 or 4 bits becomes 8-bit grey.
        dec.set_transformations(png::Transformations::EXPAND);
        let reader = dec.read_info().map_err(one_line)?;
        let info = reader.info();
        let (width, height) = (info.width, info.height);
        if info.interlaced {
            return Err("is an interlaced PNG, which cannot be read row by row; write it without interlacing".into());
        }
        let channels = match reader.output_color_type() {
            (png::ColorType::Grayscale, png::BitDepth::Eight) => 1,
            (png::ColorType::Rgb, png::BitDepth::Eight) => 3,
            (c, d) => {
                return Err(format!("is {c:?} of {} bits per sample; a pyramid needs 8-bit grey or RGB", d as u8));
            }
        };
        Ok(PngRows { reader, width, height, channels })
    }
}

impl RowSource for PngRows {
    fn width(&self) -> u32 {
        self.width
    }
    fn height(&self) -> u32 {
        self.height
    }
    fn channels(&self) -> u8 {
        self.channels
    }
    fn read_rows(&mut self, out: &mut [u8], rows: u32) -> Result<(), String> {
        let line = self.width as usize * self.channels as usize;
        for chunk in out[..rows as usize * line].chunks_exact_mut(line) {
            match self.reader.next_row().map_err(one_line)? {
                Some(row) if row.data().len() == line => chunk.copy_from_slice(row.data()),
                Some(row) => return Err(format!("a row of {} bytes, expected {line}", row.data().len())),
                None => return Err("the image data ends early (truncated file)".into()),
            }
        }
        Ok(())
    }
}

/// A TIFF read one chunk row at a time: a strip, or a row of tiles across the image.
struct TiffRows {
    dec: tiff::decoder::Decoder<BufReader<File>>,
    width: u32,
    height: u32,
    channels: u8,
    /// Chunk width and height (a strip is as wide as the image).
    chunk: (u32, u32),
    tiled: bool,
    /// The rows decoded and not yet handed out: `band_rows` rows of the image's width.
    band: Vec<u8>,
    band_rows: u32,
    /// The first row of `band` not handed out yet.
    band_pos: u32,
    /// The next chunk row (strip index, or row of tiles) to decode.
    next_chunk_row: u32,
}

impl TiffRows {
    fn new(r: BufReader<File>) -> Result<TiffRows, String> {
        let mut dec = tiff::decoder::Decoder::new(r).map_err(one_line)?;
        let (width, height) = dec.dimensions().map_err(one_line)?;
        let channels = match dec.colortype().map_err(one_line)? {
            tiff::ColorType::Gray(8) => 1,
            tiff::ColorType::RGB(8) => 3,
            other => return Err(format!("is a TIFF of {other:?}; a pyramid needs 8-bit grey or RGB")),
        };
        let planar = dec.find_tag_unsigned::<u16>(tiff::tags::Tag::PlanarConfiguration).map_err(one_line)?.unwrap_or(1);
        if planar != 1 {
            return Err("is a planar TIFF (one plane per channel); write it with interleaved channels".into());
        }
        let tiled = matches!(dec.get_chunk_type(), tiff::decoder::ChunkType::Tile);
        let chunk = dec.chunk_dimensions();
        if chunk.0 == 0 || chunk.1 == 0 || chunk.1 > MAX_SIDE || chunk.0 > MAX_SIDE {
            return Err(format!("chunks of {} x {} texels", chunk.0, chunk.1));
        }
        Ok(TiffRows {
            dec,
            width,
            height,
            channels,
            chunk,
            tiled,
            band: Vec::new(),
            band_rows: 0,
            band_pos: 0,
            next_chunk_row: 0,
        })
    }

    /// Decodes the next strip, or the next row of tiles, into `band`.
    fn fill(&mut self) -> Result<(), String> {
        let (cw, ch) = self.chunk;
        let row0 = self.next_chunk_row * ch;
        if row0 >= self.height {
            return Err("the image data ends early".into());
        }
        let rows = ch.min(self.height - row0);
        let c = self.channels as usize;
        let line = self.width as usize * c;
        self.band.clear();
        self.band.resize(rows as usize * line, 0);
        let across = if self.tiled { self.width.div_ceil(cw) } else { 1 };
        for i in 0..across {
            let index = self.next_chunk_row * across + i;
            let data = match self.dec.read_chunk(index).map_err(one_line)? {
                tiff::decoder::DecodingResult::U8(v) => v,
                _ => return Err("samples are not 8-bit".into()),
            };
            let x0 = i * cw;
            let w = if self.tiled { cw.min(self.width - x0) } else { self.width };
            let src_line = w as usize * c;
            if data.len() < rows as usize * src_line {
                return Err(format!("chunk {index} holds {} bytes, expected {}", data.len(), rows as usize * src_line));
            }
            for y in 0..rows as usize {
                let dst = y * line + x0 as usize * c;
                self.band[dst..dst + src_line].copy_from_slice(&data[y * src_line..(y + 1) * src_line]);
            }
        }
        self.band_rows = rows;
        self.band_pos = 0;
        self.next_chunk_row += 1;
        Ok(())
    }
}

impl RowSource for TiffRows {
    fn width(&self) -> u32 {
        self.width
    }
    fn height(&self) -> u32 {
        self.height
    }
    fn channels(&self) -> u8 {
        self.channels
    }
    fn read_rows(&mut self, out: &mut [u8], rows: u32) -> Result<(), String> {
        let line = self.width as usize * self.channels as usize;
        let mut done = 0;
        while done < rows {
            if self.band_pos == self.band_rows {
                self.fill()?;
            }
            let take = (rows - done).min(self.band_rows - self.band_pos);
            let src = self.band_pos as usize * line;
            let dst = done as usize * line;
            out[dst..dst + take as usize * line].copy_from_slice(&self.band[src..src + take as usize * line]);
            self.band_pos += take;
            done += take;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_striped_tiff_reads_as_the_same_rows_as_its_texels() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.tif");
        let (w, h) = (37u32, 29u32);
        let data: Vec<u8> = (0..w * h * 3).map(|i| (i * 7 % 251) as u8).collect();
        {
            let f = File::create(&path).unwrap();
            let mut enc = tiff::encoder::TiffEncoder::new(f).unwrap();
            let mut img = enc.new_image::<tiff::encoder::colortype::RGB8>(w, h).unwrap();
            img.rows_per_strip(4).unwrap();
            img.write_data(&data).unwrap();
        }
        let mut src = open(&path).unwrap();
        assert_eq!((src.width(), src.height(), src.channels()), (w, h, 3));
        let mut out = vec![0u8; data.len()];
        // Read in uneven bands across the strips' edges.
        let line = (w * 3) as usize;
        let mut y = 0;
        for n in [3u32, 5, 1, 20] {
            src.read_rows(&mut out[y * line..], n).unwrap();
            y += n as usize;
        }
        assert_eq!(out, data);
        assert!(src.read_rows(&mut out, 1).is_err(), "past the end is an error");
    }

    #[test]
    fn rgba_and_sixteen_bit_pngs_are_refused_in_one_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        let f = File::create(&path).unwrap();
        let mut enc = png::Encoder::new(f, 2, 2);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.write_header().unwrap().write_image_data(&[0; 16]).unwrap();
        let e = open(&path).err().unwrap().to_string();
        assert!(e.contains("8-bit grey or RGB") && !e.contains('\n'), "{e}");
        std::fs::write(&path, b"not an image at all").unwrap();
        assert!(open(&path).err().unwrap().to_string().contains("not a PNG or TIFF"));
    }
}
