// The impostor bake: draws a model once per atlas cell (one instance per cell), each with an
// orthographic view from the cell's direction fitted to the model's bounding sphere, into the
// albedo (sRGB, alpha = coverage) and normal (model space, encoded 0..1; alpha = depth across
// the sphere, 0 nearest) atlases. srgb.wgsl and octa.wgsl are prepended. No wind, no lighting.

// #import srgb, octa, material

// The model's bounding sphere, model-space metres (mirrors `BakeParams` in bake.rs).
struct BakeParams {
    centre: vec3<f32>,
    radius: f32,
};

@group(0) @binding(0) var<uniform> bake: BakeParams;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var albedo_tex: texture_2d<f32>;
@group(2) @binding(2) var normal_tex: texture_2d<f32>;
@group(2) @binding(3) var specular_tex: texture_2d<f32>;
@group(2) @binding(4) var material_sampler: sampler;

struct BakeIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    // The vertex colour (COLOR_0, linear; white where the model has none).
    @location(14) color: vec4<f32>,
};

struct BakeVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) depth: f32,
    @location(3) color: vec4<f32>,
};

@vertex
fn vs_bake(v: BakeIn, @builtin(instance_index) cell_index: u32) -> BakeVarying {
    let n = u32(IMPOSTOR_GRID);
    let cell = vec2<f32>(f32(cell_index % n), f32(cell_index / n));
    let d = impostor_cell_dir(cell);
    let right = impostor_basis_right(d);
    let up = cross(d, right);
    let rel = v.position - bake.centre;
    let ndc = vec2<f32>(dot(rel, right), dot(rel, up)) / bake.radius;
    // Depth across the sphere: 0 at the side facing the viewer, 1 at the far side.
    let depth = clamp(0.5 - dot(rel, d) / (2.0 * bake.radius), 0.0, 1.0);
    var out: BakeVarying;
    out.clip = vec4<f32>(
        -1.0 + (2.0 * cell.x + 1.0 + ndc.x) / IMPOSTOR_GRID,
        1.0 - (2.0 * cell.y + 1.0 - ndc.y) / IMPOSTOR_GRID,
        depth,
        1.0,
    );
    out.normal = v.normal;
    out.uv = v.uv;
    out.depth = depth;
    out.color = v.color;
    return out;
}

struct BakeOut {
    @location(0) albedo: vec4<f32>,
    @location(1) normal: vec4<f32>,
};

@fragment
fn fs_bake(in: BakeVarying, @builtin(front_facing) front: bool) -> BakeOut {
    // The albedo's texels are sRGB-encoded bytes in a linear format, decoded after filtering.
    let texel = textureSample(albedo_tex, material_sampler, in.uv);
    let base = vec4<f32>(srgb_decode(texel.rgb), texel.a) * material.base_color * in.color;
    if (material.alpha_cutoff >= 0.0 && base.a < material.alpha_cutoff) {
        discard;
    }
    var n = in.normal * inverseSqrt(max(dot(in.normal, in.normal), 1e-12));
    if (!front) {
        n = -n;
    }
    var out: BakeOut;
    out.albedo = vec4<f32>(base.rgb, 1.0);
    out.normal = vec4<f32>(n * 0.5 + 0.5, in.depth);
    return out;
}
