// The aerial ground: the winter photograph draped over the photographed rectangle at the
// ground's height, read from its clipmap, lit by the sun and shadowed. Where no level has the
// photograph loaded the fragment is discarded and the ordinary ground, drawn after it, shows.
// lighting.wgsl and clipmap.wgsl are prepended (src/render/aerial_ground/mod.rs).

// #import lighting, clipmap

struct AerialGroundParams {
    // The rectangle's corners, world (X, Z) metres, and its height.
    lo: vec2<f32>,
    hi: vec2<f32>,
    height: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
};

@group(2) @binding(0) var<uniform> winter: Clipmap;
@group(2) @binding(1) var winter_tex: texture_2d_array<f32>;
@group(2) @binding(2) var winter_sampler: sampler;
@group(2) @binding(3) var<uniform> params: AerialGroundParams;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) irr: vec3<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> VertexOut {
    // Two triangles: corners 0 1 2, 2 1 3 of the rectangle.
    let corner = array<vec2<f32>, 6>(vec2<f32>(0.0, 0.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0), vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 1.0));
    let xz = mix(params.lo, params.hi, corner[i]);
    var out: VertexOut;
    out.world_pos = vec3<f32>(xz.x, params.height, xz.y);
    out.clip = frame.view_proj * vec4<f32>(out.world_pos, 1.0);
    out.irr = textureSampleLevel(irradiance_map, env_sampler, vec3<f32>(0.0, 1.0, 0.0), 0.0).rgb;
    return out;
}

// sRGB-encoded photograph texels to linear.
fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    return pow(c, vec3<f32>(2.2));
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let p = in.world_pos.xz;
    let min_level = clipmap_min_level(winter, p);
    let t = clipmap_sample(winter_tex, winter_sampler, winter, p, min_level);
    if (t.a < 0.5) {
        discard;
    }
    let c = shade_lit(srgb_to_linear(t.rgb), vec3<f32>(0.0, 1.0, 0.0), in.world_pos, 0.04, 0.95, 0.0, in.irr);
    return vec4<f32>(tone(aerial(c, in.world_pos)), 1.0);
}
