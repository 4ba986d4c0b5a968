//! The WGSL wind functions (src/render/trees/wind.wgsl) agree with their CPU reference
//! (grove_systems::wind_model): both models run in a compute pass over a few thousand vertices
//! with mixed channels, times and parameters, and every displaced position must match the CPU to
//! within 1e-4 m.
//!
//! Needs a wgpu adapter; lavapipe (Debian's `mesa-vulkan-drivers`) is enough. Without one the
//! test fails with a message that says so.

use glam::{Vec2, Vec3, Vec4};
use grove_systems::wind_model::{self, WindParams, hash_u32};
use wgpu::util::DeviceExt;

const WIND_WGSL: &str = include_str!("../../src/render/trees/wind.wgsl");

/// The test's entry point, appended to the wind functions.
const TEST_WGSL: &str = r#"
struct Vertex {
    v0: vec4<f32>,
    ch: vec4<f32>,
    // x, y: bend; z: gain; w: tree phase.
    tree: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> vertices: array<Vertex>;
@group(0) @binding(1) var<storage, read> params: array<WindParams>;
@group(0) @binding(2) var<storage, read_write> out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&vertices) {
        return;
    }
    let v = vertices[i];
    let p = params[i];
    let moved = wind_displace(p.model, v.v0.xyz, v.ch, v.tree.xy, v.tree.z, v.tree.w, p);
    // The raw noise at the vertex, to tell a noise mismatch from a model mismatch.
    let n = wind_noise01(p.density * v.v0.xyz + vec3<f32>(0.1, 0.2, 0.3));
    out[i] = vec4<f32>(moved, n);
}
"#;

const N: usize = 4096;

/// A deterministic number in [lo, hi) for vertex `i` and field `salt`.
fn rnd(i: usize, salt: u32, lo: f32, hi: f32) -> f32 {
    let h = hash_u32((i as u32).wrapping_mul(0x9e37_79b9) ^ hash_u32(salt));
    lo + (hi - lo) * ((h >> 8) as f32 / (1u32 << 24) as f32)
}

struct Case {
    v0: Vec3,
    ch: Vec4,
    bend: Vec2,
    gain: f32,
    phase: f32,
    params: WindParams,
}

fn cases() -> Vec<Case> {
    (0..N)
        .map(|i| {
            let angle = rnd(i, 1, 0.0, std::f32::consts::TAU);
            let h = rnd(i, 2, 0.0, 12.0);
            let params = WindParams {
                direction: [angle.cos(), angle.sin()],
                strength: rnd(i, 3, 0.0, 2.5),
                gust: rnd(i, 4, 0.0, 1.3),
                density: rnd(i, 5, 0.02, 0.6),
                noise_speed: rnd(i, 6, 0.0, 6.0),
                noise_amplitude: rnd(i, 7, 0.01, 0.15),
                // Times up to ten minutes of simulation, some exactly zero.
                time: if i % 17 == 0 { 0.0 } else { rnd(i, 8, 0.0, 600.0) },
                trunk_stiffness: rnd(i, 9, 2.0, 15.0),
                branch_stiffness: rnd(i, 10, 8.0, 40.0),
                branch_frequency: rnd(i, 11, 0.2, 1.5),
                leaf_flutter: rnd(i, 12, 0.0, 0.15),
                leaf_frequency: rnd(i, 13, 1.0, 4.0),
                // Half the vertices use each model.
                model: (i % 2) as u32,
                pad: [0; 2],
            };
            Case {
                v0: Vec3::new(rnd(i, 14, -40.0, 40.0), h + rnd(i, 15, -0.5, 0.5), rnd(i, 16, -40.0, 40.0)),
                ch: Vec4::new(h, rnd(i, 17, 0.0, 4.0), rnd(i, 18, 0.0, 1.0), rnd(i, 19, 0.0, 1.0)),
                bend: Vec2::new(rnd(i, 20, -0.05, 0.05), rnd(i, 21, -0.05, 0.05)),
                gain: rnd(i, 22, 0.5, 1.5),
                phase: rnd(i, 23, 0.0, std::f32::consts::TAU),
                params,
            }
        })
        .collect()
}

fn f32_bytes(values: impl IntoIterator<Item = f32>) -> Vec<u8> {
    values.into_iter().flat_map(f32::to_le_bytes).collect()
}

/// Runs the WGSL functions on the GPU and returns one vec4 per case.
fn run_gpu(cases: &[Case]) -> Vec<[f32; 4]> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter =
        pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default())).unwrap_or_else(|e| {
            panic!(
                "no wgpu adapter ({e}); this test needs a GPU or a software Vulkan driver \
             (apt-get install mesa-vulkan-drivers libvulkan1 for lavapipe)"
            )
        });
    eprintln!("wind_gpu: adapter {:?}", adapter.get_info());
    let (device, queue) = pollster::block_on(
        adapter.request_device(&wgpu::DeviceDescriptor { label: Some("wind test device"), ..Default::default() }),
    )
    .expect("request a wgpu device");

    // wind.wgsl imports the uniform's declaration, which grove-systems writes.
    let source = format!("{}\n{WIND_WGSL}\n{TEST_WGSL}", WindParams::WGSL);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("wind test shader"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });

    let vertex_bytes = f32_bytes(cases.iter().flat_map(|c| {
        [c.v0.x, c.v0.y, c.v0.z, 1.0, c.ch.x, c.ch.y, c.ch.z, c.ch.w, c.bend.x, c.bend.y, c.gain, c.phase]
    }));
    let param_bytes: Vec<u8> = cases.iter().flat_map(|c| c.params.to_le_bytes()).collect();
    let out_size = (cases.len() * 16) as u64;

    let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("wind test vertices"),
        contents: &vertex_bytes,
        usage: wgpu::BufferUsages::STORAGE,
    });
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("wind test params"),
        contents: &param_bytes,
        usage: wgpu::BufferUsages::STORAGE,
    });
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("wind test output"),
        size: out_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("wind test readback"),
        size: out_size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });

    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("wind test pipeline"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("wind test bind group"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: vertices.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: params.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 2, resource: out.as_entire_binding() },
        ],
    });

    let mut encoder =
        device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("wind test encoder") });
    {
        let mut pass = encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("wind test pass"), timestamp_writes: None });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(cases.len().div_ceil(64) as u32, 1, 1);
    }
    encoder.copy_buffer_to_buffer(&out, 0, &readback, 0, out_size);
    queue.submit([encoder.finish()]);

    readback.map_async(wgpu::MapMode::Read, .., |r| r.expect("map the readback buffer"));
    device.poll(wgpu::PollType::wait_indefinitely()).expect("wait for the GPU");
    let view = readback.get_mapped_range(..).expect("read the mapped buffer");
    view.chunks_exact(16)
        .map(|c| {
            let f = |k: usize| f32::from_le_bytes(c[4 * k..4 * k + 4].try_into().unwrap());
            [f(0), f(1), f(2), f(3)]
        })
        .collect()
}

#[test]
fn wgsl_wind_matches_cpu_reference_within_a_tenth_of_a_millimetre() {
    let cases = cases();
    let gpu = run_gpu(&cases);
    assert_eq!(gpu.len(), cases.len());

    let mut worst = [0.0f32; 2];
    let mut worst_noise = 0.0f32;
    let mut largest_sway = [0.0f32; 2];
    for (i, (c, g)) in cases.iter().zip(&gpu).enumerate() {
        let model = c.params.model as usize;
        let cpu = wind_model::displace(c.params.model, c.v0, c.ch, c.bend, c.gain, c.phase, &c.params);
        let err = (cpu - Vec3::new(g[0], g[1], g[2])).length();
        assert!(err <= 1e-4, "vertex {i} (model {model}): GPU {:?} vs CPU {cpu}, error {err} m", &g[..3]);
        worst[model] = worst[model].max(err);
        largest_sway[model] = largest_sway[model].max((cpu - c.v0).length());

        let n = wind_model::noise01(c.params.density * c.v0 + Vec3::new(0.1, 0.2, 0.3));
        worst_noise = worst_noise.max((n - g[3]).abs());
    }
    eprintln!(
        "wind_gpu: max error noise model {:.2e} m, hierarchical {:.2e} m; raw noise {:.2e}",
        worst[0], worst[1], worst_noise
    );
    eprintln!(
        "wind_gpu: largest displacement noise model {:.3} m, hierarchical {:.3} m",
        largest_sway[0], largest_sway[1]
    );
    assert!(worst_noise <= 1e-5, "raw noise differs by {worst_noise}");
    // The cases must actually move vertices by a visible amount, or the comparison says little.
    assert!(largest_sway[0] > 0.05 && largest_sway[1] > 0.05, "displacements too small: {largest_sway:?}");
}
