//! GPU timestamp queries with named scopes: each pass of a frame asks for the timestamp writes
//! of a scope by name ([`Timer::scope`]) and the times come back by name
//! ([`PassTimes::ms`]), so a frame may have any number of passes (up to [`MAX_SCOPES`]).

use super::error::RenderError;

/// The most scopes one frame can time.
pub const MAX_SCOPES: u32 = 32;

/// GPU time of each timed scope (pass) of the last frame, in milliseconds, in frame order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassTimes {
    /// The scopes' names and times, milliseconds.
    pub scopes: Vec<(&'static str, f64)>,
}

impl PassTimes {
    /// The time of the scope `name`, milliseconds; 0 when the frame had no such scope.
    pub fn ms(&self, name: &str) -> f64 {
        self.scopes.iter().find(|(n, _)| *n == name).map_or(0.0, |(_, ms)| *ms)
    }
}

/// Timestamp queries at the start and end of each scope (indices 2i and 2i + 1), resolved into
/// a buffer and copied to a mappable one at the end of every frame.
pub(crate) struct Timer {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    period_ns: f64,
    /// The scopes of the frame being recorded, in order.
    scopes: Vec<&'static str>,
    /// The scopes of the last resolved frame.
    resolved: Vec<&'static str>,
}

impl Timer {
    /// A timer on `device`; fails when the device was opened without
    /// `Features::TIMESTAMP_QUERY`.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Timer, RenderError> {
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return Err(RenderError::NoTimestamps);
        }
        let size = u64::from(2 * MAX_SCOPES) * wgpu::QUERY_SIZE as u64;
        let buffer = |label: &str, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false })
        };
        Ok(Timer {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * MAX_SCOPES,
            }),
            resolve: buffer(
                "pass timestamps resolve",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: buffer("pass timestamps readback", wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ),
            period_ns: f64::from(queue.get_timestamp_period()),
            scopes: Vec::new(),
            resolved: Vec::new(),
        })
    }

    /// Starts a frame: no scopes yet.
    pub fn begin_frame(&mut self) {
        self.scopes.clear();
    }

    /// The timestamp writes of a new scope `name`; `None` once [`MAX_SCOPES`] are in use.
    pub fn scope(&mut self, name: &'static str) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let index = self.scopes.len() as u32;
        if index >= MAX_SCOPES {
            return None;
        }
        self.scopes.push(name);
        Some(wgpu::RenderPassTimestampWrites {
            query_set: &self.set,
            beginning_of_pass_write_index: Some(2 * index),
            end_of_pass_write_index: Some(2 * index + 1),
        })
    }

    /// Resolves this frame's timestamps and copies them where [`Timer::read`] maps them.
    pub fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder) {
        let count = 2 * self.scopes.len() as u32;
        if count > 0 {
            encoder.resolve_query_set(&self.set, 0..count, &self.resolve, 0);
            encoder.copy_buffer_to_buffer(
                &self.resolve,
                0,
                &self.readback,
                0,
                u64::from(count) * wgpu::QUERY_SIZE as u64,
            );
        }
        self.resolved = std::mem::take(&mut self.scopes);
    }

    /// The times of the last resolved frame. Waits for the GPU.
    pub fn read(&self, device: &wgpu::Device) -> Result<PassTimes, RenderError> {
        if self.resolved.is_empty() {
            return Ok(PassTimes::default());
        }
        let bytes = self.resolved.len() as u64 * 2 * wgpu::QUERY_SIZE as u64;
        let slice = self.readback.slice(..bytes);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        device.poll(wgpu::PollType::wait_indefinitely()).map_err(RenderError::Poll)?;
        rx.recv().map_err(|_| RenderError::TimestampsDropped)?.map_err(RenderError::Timestamps)?;
        let ticks: Vec<u64> = {
            let data = slice.get_mapped_range().map_err(RenderError::TimestampsRange)?;
            data.chunks_exact(8).map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8]))).collect()
        };
        self.readback.unmap();
        let scopes = self
            .resolved
            .iter()
            .enumerate()
            .map(|(i, name)| (*name, ticks[2 * i + 1].saturating_sub(ticks[2 * i]) as f64 * self.period_ns * 1e-6))
            .collect();
        Ok(PassTimes { scopes })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_are_found_by_scope_name() {
        let t = PassTimes { scopes: vec![("shadow", 1.5), ("grass", 0.25), ("main", 9.0)] };
        assert_eq!((t.ms("shadow"), t.ms("grass"), t.ms("main")), (1.5, 0.25, 9.0));
        assert_eq!(t.ms("water"), 0.0);
    }
}
