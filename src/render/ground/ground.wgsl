// Ground planes: the Plane meshes, textured in world space, lit and shadowed. Holes are simply
// missing triangles. lighting.wgsl is prepended (src/render/ground/mod.rs).

struct GroundParams {
    // Metres per repeat of the ground texture.
    metres_per_repeat: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
};

@group(2) @binding(0) var<uniform> ground_params: GroundParams;
@group(2) @binding(1) var ground_tex: texture_2d<f32>;
@group(2) @binding(2) var ground_normal_tex: texture_2d<f32>;
@group(2) @binding(3) var ground_specular_tex: texture_2d<f32>;
@group(2) @binding(4) var ground_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // The irradiance for the normal and for its opposite (seen from below, through a hole):
    // the ground's normals vary slowly, so per vertex is enough.
    @location(2) irr_front: vec3<f32>,
    @location(3) irr_back: vec3<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.world_pos = v.position;
    out.normal = v.normal;
    out.irr_front = textureSampleLevel(irradiance_map, env_sampler, v.normal, 0.0).rgb;
    out.irr_back = textureSampleLevel(irradiance_map, env_sampler, -v.normal, 0.0).rgb;
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let albedo = textureSample(ground_tex, ground_sampler, in.world_pos.xz / ground_params.metres_per_repeat).rgb;
    let n = normalize(in.normal) * select(-1.0, 1.0, front);
    let irr = select(in.irr_back, in.irr_front, front);
    let c = shade_lit(albedo, n, in.world_pos, 0.08, 0.95, 0.0, irr);
    return vec4<f32>(tone(c), 1.0);
}
