//! Frames to H.264 in MP4: OpenH264 (the `openh264` crate, built from source) encodes each RGBA
//! frame as constrained-baseline H.264 (no B-frames, so presentation order is decoding order),
//! and the `mp4` crate muxes the access units into an `avc1` track. The colours are converted
//! with BT.601 limited-range coefficients, which the stream's VUI names, so players and
//! ffmpeg decode them back the same way.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use image::RgbaImage;
use openh264::OpenH264API;
use openh264::encoder::{
    BitRate, Encoder, EncoderConfig, FrameRate, IntraFramePeriod, QpRange, RateControlMode, UsageType, VuiConfig,
};
use openh264::formats::{RgbaSliceU8, YUVBuffer};

/// Why a video could not be written.
#[derive(Debug, thiserror::Error)]
pub enum VideoError {
    /// The encoder refused its settings or a frame.
    #[error("H.264 encoder: {0}")]
    Encoder(String),
    /// The MP4 file could not be written.
    #[error("{path}: cannot write the video ({reason})")]
    Write {
        /// The file.
        path: String,
        /// What failed.
        reason: String,
    },
    /// The renderer failed to draw or read back a frame.
    #[error("rendering a frame: {0}")]
    Render(crate::render::RenderError),
    /// A frame of another size than the video's.
    #[error("frame of {got:?} pixels in a video of {want:?}")]
    FrameSize {
        /// The frame's size.
        got: (u32, u32),
        /// The video's size.
        want: (u32, u32),
    },
}

/// The MP4 track's ticks per frame (its timescale is `fps` times this).
const TICKS_PER_FRAME: u32 = 1000;

/// An MP4 file being written, one frame at a time.
pub struct VideoWriter {
    encoder: Encoder,
    yuv: YUVBuffer,
    mp4: mp4::Mp4Writer<BufWriter<File>>,
    path: String,
    size: (u32, u32),
    track: bool,
    frames: u64,
    bytes: u64,
    fps: u32,
}

/// The bits per second asked of the encoder for a `w`×`h` video at `fps`: about 0.12 bits a
/// pixel a frame (5.5 Mbit/s at 1280 × 720 and 30 fps), enough that foliage and text stay sharp.
pub fn bitrate(w: u32, h: u32, fps: u32) -> u32 {
    ((w as f64 * h as f64 * fps as f64 * 0.2) as u64).clamp(200_000, 50_000_000) as u32
}

impl VideoWriter {
    /// Starts a video of `width`×`height` (both even) at `fps` frames per second in `path`.
    pub fn create(path: &Path, width: u32, height: u32, fps: u32) -> Result<VideoWriter, VideoError> {
        let name = path.display().to_string();
        let write_err = |e: &dyn std::fmt::Display| VideoError::Write { path: name.clone(), reason: e.to_string() };
        let config = EncoderConfig::new()
            .usage_type(UsageType::CameraVideoRealTime)
            .rate_control_mode(RateControlMode::Off)
            .qp(QpRange::new(18, 26))
            .bitrate(BitRate::from_bps(bitrate(width, height, fps)))
            .max_frame_rate(FrameRate::from_hz(fps as f32))
            .skip_frames(false)
            // A key frame every two seconds, so that players can seek.
            .intra_frame_period(IntraFramePeriod::from_num_frames(2 * fps))
            .vui(VuiConfig::bt601())
            .num_threads(1)
            .debug(false);
        let encoder = Encoder::with_api_config(OpenH264API::from_source(), config)
            .map_err(|e| VideoError::Encoder(e.to_string()))?;
        let file = File::create(path).map_err(|e| write_err(&e))?;
        let config = mp4::Mp4Config {
            major_brand: str::parse("isom").map_err(|e| write_err(&e))?,
            minor_version: 512,
            compatible_brands: ["isom", "iso2", "avc1", "mp41"].iter().filter_map(|b| str::parse(b).ok()).collect(),
            timescale: 1000,
        };
        let mp4 = mp4::Mp4Writer::write_start(BufWriter::new(file), &config).map_err(|e| write_err(&e))?;
        Ok(VideoWriter {
            encoder,
            yuv: YUVBuffer::new(width as usize, height as usize),
            mp4,
            path: name,
            size: (width, height),
            track: false,
            frames: 0,
            bytes: 0,
            fps,
        })
    }

    /// Encodes and writes one frame.
    pub fn push(&mut self, frame: &RgbaImage) -> Result<(), VideoError> {
        if frame.dimensions() != self.size {
            return Err(VideoError::FrameSize { got: frame.dimensions(), want: self.size });
        }
        let (w, h) = self.size;
        self.yuv.read_rgba8(RgbaSliceU8::new(frame.as_raw(), (w as usize, h as usize)));
        let stream = self.encoder.encode(&self.yuv).map_err(|e| VideoError::Encoder(e.to_string()))?.to_vec();
        let mut sample = Vec::with_capacity(stream.len() + 16);
        let (mut sps, mut pps, mut sync) = (None, None, false);
        for nal in openh264::nal_units(&stream).map(strip_start_code).filter(|n| !n.is_empty()) {
            match nal[0] & 0x1f {
                7 => sps = Some(nal.to_vec()),
                8 => pps = Some(nal.to_vec()),
                t => {
                    sync |= t == 5;
                    sample.extend_from_slice(&(nal.len() as u32).to_be_bytes());
                    sample.extend_from_slice(nal);
                }
            }
        }
        if !self.track {
            let (Some(seq_param_set), Some(pic_param_set)) = (sps, pps) else {
                return Err(VideoError::Encoder("the first frame carries no parameter sets".into()));
            };
            let track = mp4::TrackConfig {
                track_type: mp4::TrackType::Video,
                timescale: self.fps * TICKS_PER_FRAME,
                language: "und".into(),
                media_conf: mp4::MediaConfig::AvcConfig(mp4::AvcConfig {
                    width: w as u16,
                    height: h as u16,
                    seq_param_set,
                    pic_param_set,
                }),
            };
            self.mp4
                .add_track(&track)
                .map_err(|e| VideoError::Write { path: self.path.clone(), reason: e.to_string() })?;
            self.track = true;
        }
        if sample.is_empty() {
            return Err(VideoError::Encoder(format!("frame {} was skipped by the encoder", self.frames)));
        }
        self.bytes += sample.len() as u64;
        let s = mp4::Mp4Sample {
            start_time: self.frames * TICKS_PER_FRAME as u64,
            duration: TICKS_PER_FRAME,
            rendering_offset: 0,
            is_sync: sync,
            bytes: bytes::Bytes::from(sample),
        };
        self.mp4
            .write_sample(1, &s)
            .map_err(|e| VideoError::Write { path: self.path.clone(), reason: e.to_string() })?;
        self.frames += 1;
        Ok(())
    }

    /// Frames written so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Bytes of video data written so far.
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    /// Writes the index (`moov`) and closes the file.
    pub fn finish(mut self) -> Result<u64, VideoError> {
        let err = |e: &dyn std::fmt::Display| VideoError::Write { path: self.path.clone(), reason: e.to_string() };
        self.mp4.write_end().map_err(|e| err(&e))?;
        let mut w = self.mp4.into_writer();
        std::io::Write::flush(&mut w).map_err(|e| err(&e))?;
        w.get_ref().sync_all().map_err(|e| err(&e))?;
        Ok(self.frames)
    }
}

/// A NAL unit without its Annex B start code (`00 00 01` or `00 00 00 01`).
fn strip_start_code(nal: &[u8]) -> &[u8] {
    let zeros = nal.iter().take_while(|&&b| b == 0).count();
    if zeros >= 2 && nal.get(zeros) == Some(&1) { &nal[zeros + 1..] } else { nal }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn start_codes_of_both_lengths_are_removed() {
        assert_eq!(strip_start_code(&[0, 0, 1, 0x67, 5]), &[0x67, 5]);
        assert_eq!(strip_start_code(&[0, 0, 0, 1, 0x68]), &[0x68]);
        assert_eq!(strip_start_code(&[0x65, 0, 0, 1]), &[0x65, 0, 0, 1]);
    }

    #[test]
    fn the_bitrate_grows_with_the_pixels_and_is_bounded() {
        assert!(bitrate(1280, 720, 30) > bitrate(640, 360, 30));
        assert_eq!(bitrate(2, 2, 1), 200_000);
        assert_eq!(bitrate(8192, 8192, 120), 50_000_000);
    }
}
