//! GPU derivation with wgpu compute passes (`derive.wgsl`): per-word successor lengths, a
//! hierarchical exclusive scan (blocks of 256, their totals scanned recursively, so there is no
//! ceiling such as 262,144 symbols), and a scatter. Dispatches larger than 65,535 workgroups are
//! laid out in two dimensions. Stochastic choices use the same hash as the CPU, so the result is
//! bit-identical to `derive::derive`.
//!
//! It handles grammars without parameters and conditions (context-free and stochastic); a
//! parametric grammar is refused with one line. This is the only file of `lsystem` that uses
//! wgpu; it opens its own device.

use wgpu::util::DeviceExt;

use super::derive::{LString, Limits, step_key};
use super::error::LsystemError;
use super::grammar::{Choice, Grammar};

const WG: u32 = 256;
const MAX_GROUPS: u32 = 65_535;

/// A wgpu device with the derivation pipelines.
pub struct GpuDeriver {
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: String,
    lengths: wgpu::ComputePipeline,
    scan_block: wgpu::ComputePipeline,
    add_offsets: wgpu::ComputePipeline,
    scatter: wgpu::ComputePipeline,
    max_binding: u64,
    max_groups: u32,
}

/// The packed tables of a grammar (see `derive.wgsl`) and the pool's word offset.
fn tables(g: &Grammar) -> (Vec<u32>, u32) {
    let mut head = vec![0u32; 256];
    let mut alts: Vec<u32> = Vec::new();
    let mut pool: Vec<u8> = Vec::new();
    let mut add = |thr: u32, r: u32, alts: &mut Vec<u32>| {
        let succ = &g.rules[r as usize].succ;
        alts.extend_from_slice(&[thr, pool.len() as u32, succ.len() as u32]);
        pool.extend_from_slice(succ);
    };
    for s in 0..128 {
        let first = (alts.len() / 3) as u32;
        let count = match &g.choice[s] {
            Choice::Identity | Choice::Conditional(_) => 0,
            Choice::Single(r) => {
                add(1 << 24, *r, &mut alts);
                1
            }
            Choice::Stochastic(t) => {
                for &(thr, r) in t {
                    add(thr, r, &mut alts);
                }
                t.len() as u32
            }
        };
        head[2 * s] = first;
        head[2 * s + 1] = count;
    }
    let mut words = head;
    words.extend_from_slice(&alts);
    let pool_base = words.len() as u32;
    words.extend(pack(&pool));
    (words, pool_base)
}

/// Bytes packed four to a little-endian u32 (at least one word).
fn pack(bytes: &[u8]) -> Vec<u32> {
    let mut w: Vec<u32> =
        bytes.chunks(4).map(|c| c.iter().enumerate().fold(0u32, |a, (i, &b)| a | (b as u32) << (8 * i))).collect();
    if w.is_empty() {
        w.push(0);
    }
    w
}

/// A two-dimensional workgroup count covering `groups` workgroups with at most `max` per
/// dimension, and the threads per row.
fn grid(groups: u32, max: u32) -> (u32, u32, u32) {
    let groups = groups.max(1);
    let x = groups.min(max);
    (x, groups.div_ceil(x), x * WG)
}

impl GpuDeriver {
    /// Opens a device on the first adapter wgpu offers (lavapipe is fine) and builds the
    /// pipelines. Fails with one line when there is none.
    pub fn new() -> Result<GpuDeriver, LsystemError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        }))
        .map_err(LsystemError::Adapter)?;
        let info = adapter.get_info();
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("lsystem derivation device"),
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(LsystemError::Device)?;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("lsystem derive.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("derive.wgsl").into()),
        });
        let pipe = |entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        Ok(GpuDeriver {
            lengths: pipe("lengths"),
            scan_block: pipe("scan_block"),
            add_offsets: pipe("add_offsets"),
            scatter: pipe("scatter"),
            max_binding: (limits.max_storage_buffer_binding_size as u64).min(limits.max_buffer_size),
            max_groups: MAX_GROUPS.min(limits.max_compute_workgroups_per_dimension),
            adapter: format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type),
            device,
            queue,
        })
    }

    /// Lowers the most workgroups per dispatch dimension (at least 1), so that tests can exercise
    /// the two-dimensional layout on small strings.
    pub fn set_max_workgroups(&mut self, max: u32) {
        self.max_groups = max.clamp(1, MAX_GROUPS);
    }

    /// A one-line description of the adapter.
    pub fn adapter(&self) -> &str {
        &self.adapter
    }

    fn buffer(&self, label: &str, bytes: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes.max(4).div_ceil(4) * 4,
            usage,
            mapped_at_creation: false,
        })
    }

    fn params(&self, n: u32, key: u32, row: u32, pool: u32) -> wgpu::Buffer {
        self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("lsystem params"),
            contents: bytemuck::cast_slice(&[n, key, row, pool]),
            usage: wgpu::BufferUsages::UNIFORM,
        })
    }

    /// One dispatch in its own compute pass (passes are ordered, so each sees the last's writes).
    fn dispatch(
        &self,
        enc: &mut wgpu::CommandEncoder,
        pipe: &wgpu::ComputePipeline,
        entries: &[(u32, &wgpu::Buffer)],
        groups: (u32, u32),
    ) {
        let bind = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipe.get_bind_group_layout(0),
            entries: &entries
                .iter()
                .map(|(b, buf)| wgpu::BindGroupEntry { binding: *b, resource: buf.as_entire_binding() })
                .collect::<Vec<_>>(),
        });
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes: None });
        pass.set_pipeline(pipe);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    }

    /// Scans `data` (n elements) in place, recursively; returns the one-element buffer that holds
    /// the total.
    fn scan(&self, enc: &mut wgpu::CommandEncoder, data: &wgpu::Buffer, n: u32) -> wgpu::Buffer {
        let blocks = n.div_ceil(WG).max(1);
        let sums = self.buffer(
            "lsystem block sums",
            blocks as u64 * 4,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        );
        let (x, y, _) = grid(blocks, self.max_groups);
        let prm = self.params(n, 0, 0, 0);
        self.dispatch(enc, &self.scan_block, &[(0, &prm), (3, data), (4, &sums)], (x, y));
        if blocks == 1 {
            return sums;
        }
        let total = self.scan(enc, &sums, blocks);
        self.dispatch(enc, &self.add_offsets, &[(0, &prm), (3, data), (4, &sums)], (x, y));
        total
    }

    fn read(&self, buf: &wgpu::Buffer, bytes: u64) -> Result<Vec<u8>, LsystemError> {
        let size = bytes.max(4).div_ceil(4) * 4;
        let staging =
            self.buffer("lsystem readback", size, wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(buf, 0, &staging, 0, size);
        self.queue.submit([enc.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(LsystemError::Poll)?;
        rx.recv().map_err(LsystemError::ReadbackDropped)?.map_err(LsystemError::Readback)?;
        let view = staging.get_mapped_range(..).map_err(LsystemError::ReadbackRange)?;
        Ok(view[..bytes as usize].to_vec())
    }

    /// Derives `n` steps of `g` from its axiom; the same string as the CPU gives.
    pub fn derive(&self, g: &Grammar, n: u32, seed: u64, limits: &Limits) -> Result<LString, LsystemError> {
        if g.is_parametric() || g.is_conditional() {
            return Err(LsystemError::GpuGrammar(g.name.clone()));
        }
        let (table, pool_base) = tables(g);
        let table = self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("lsystem tables"),
            contents: bytemuck::cast_slice(&table),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let mut len = g.axiom.len() as u64;
        limits.check(0, len, 0)?;
        let mut src = self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("lsystem symbols"),
            contents: bytemuck::cast_slice(&pack(&g.axiom)),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let max_succ = g.max_successor() as u64;
        for k in 1..=n {
            if len * max_succ > u32::MAX as u64 {
                return Err(LsystemError::GpuOffsets { step: k, symbols: len });
            }
            let key = step_key(seed, k);
            let words = len.div_ceil(4) as u32;
            let lens = self.buffer("lsystem lengths", words as u64 * 4, wgpu::BufferUsages::STORAGE);
            if words as u64 * 4 > self.max_binding {
                return Err(LsystemError::GpuBinding { step: k, symbols: len, limit: self.max_binding });
            }
            let (x, y, row) = grid(words.div_ceil(WG), self.max_groups);
            let prm = self.params(len as u32, key, row, pool_base);
            let mut enc = self.device.create_command_encoder(&Default::default());
            self.dispatch(&mut enc, &self.lengths, &[(0, &prm), (1, &src), (2, &table), (3, &lens)], (x, y));
            let total_buf = self.scan(&mut enc, &lens, words);
            self.queue.submit([enc.finish()]);
            let total = u32::from_le_bytes(self.read(&total_buf, 4)?[..4].try_into().expect("four bytes")) as u64;
            limits.check(k, total, 0)?;
            if total.div_ceil(4) * 4 > self.max_binding {
                return Err(LsystemError::GpuBinding { step: k, symbols: total, limit: self.max_binding });
            }
            let dst = self.buffer("lsystem symbols", total, wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
            let mut enc = self.device.create_command_encoder(&Default::default());
            self.dispatch(&mut enc, &self.scatter, &[(0, &prm), (1, &src), (2, &table), (3, &lens), (5, &dst)], (x, y));
            self.queue.submit([enc.finish()]);
            src = dst;
            len = total;
        }
        let syms = self.read(&src, len)?;
        Ok(LString { syms, params: Vec::new() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_stay_within_the_dispatch_limit() {
        assert_eq!(grid(0, MAX_GROUPS), (1, 1, 256));
        assert_eq!(grid(65_535, MAX_GROUPS), (65_535, 1, 65_535 * 256));
        assert_eq!(grid(65_536, MAX_GROUPS), (65_535, 2, 65_535 * 256));
        assert_eq!(grid(10, 3), (3, 4, 768));
    }
}
