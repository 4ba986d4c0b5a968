// Ground planes as a landscape: the Plane meshes, their sides, the soil floor under them (seen
// through the holes, which are missing triangles) and the terrain around them, lit and shadowed,
// and faded into the sky's colour at the horizon with distance (aerial perspective).
// lighting.wgsl is prepended (src/render/ground/mod.rs; the kinds are those of
// src/render/ground/landscape.rs).
//
// Written for a software rasteriser, where a pixel's cost is its instructions and, above all,
// its filtered texture samples: a pixel takes one sample of the ground texture (its 2.5 m
// repeat), and the variation at larger scales that hides the repeat (about 12 m, 70 m and a hue
// over 150 m) comes per vertex as the tint, computed on the CPU (landscape.rs, `Tint`). The
// aerial perspective and the irradiance are also per vertex (the terrain is cut into cells small
// enough for them to vary linearly); the ground's light is diffuse and ambient only (its
// highlight was below one level in 255). The far terrain has its own fragment entry, `fs_far`:
// no shadow lookups.

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
    // 0 a plane, 1 a plane's side, 2 terrain, 3 the soil floor.
    @location(2) kind: f32,
    // The albedo's factor at scales above the texture's repeat (linear RGB).
    @location(3) tint: vec3<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // The irradiance for the normal and for its opposite (seen from below, through a hole):
    // the ground's normals vary slowly, so per vertex is enough.
    @location(2) irr_front: vec3<f32>,
    @location(3) irr_back: vec3<f32>,
    @location(4) @interpolate(flat) kind: u32,
    // The aerial perspective's haze colour (rgb) and how much of it covers the ground (a).
    @location(5) haze: vec4<f32>,
    // The tint, with the terrain's greener shade already in it.
    @location(6) tint: vec3<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.world_pos = v.position;
    out.normal = v.normal;
    out.irr_front = textureSampleLevel(irradiance_map, env_sampler, v.normal, 0.0).rgb * frame.ambient;
    out.irr_back = textureSampleLevel(irradiance_map, env_sampler, -v.normal, 0.0).rgb * frame.ambient;
    out.kind = u32(v.kind + 0.5);
    out.haze = haze_at(v.position);
    // The terrain: the same ground, a little greener.
    out.tint = v.tint * select(vec3<f32>(1.0), vec3<f32>(0.85, 1.0, 0.75), out.kind == 2u);
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // One texture sample for every kind (no divergent branches around it): sides take the
    // texture along the wall, everything else in the horizontal plane.
    let along = in.world_pos.x * in.normal.z - in.world_pos.z * in.normal.x;
    let uv = select(in.world_pos.xz, vec2<f32>(along, in.world_pos.y * 2.0), in.kind == 1u);
    let t = textureSample(ground_tex, ground_sampler, uv / ground_params.metres_per_repeat).rgb;
    // Soil (the sides and the floor under the holes): brown, with the texture's brightness; the
    // sides as cut soil, the floor darker.
    let lum = dot(t, vec3<f32>(0.3, 0.6, 0.1));
    let soil = vec3<f32>(0.2, 0.13, 0.08);
    var albedo = t * in.tint;
    albedo = select(albedo, soil * (0.5 + 2.0 * lum), in.kind == 1u);
    albedo = select(albedo, soil * (0.25 + 1.0 * lum), in.kind == 3u);
    let n = normalize(in.normal) * select(-1.0, 1.0, front);
    let irr = select(in.irr_back, in.irr_front, front);
    let lit = shadow_factor(in.world_pos, n);
    let c = albedo * (frame.sun_color * (max(dot(n, frame.sun_dir), 0.0) * lit) + irr);
    return vec4<f32>(tone(mix(c, in.haze.rgb, in.haze.a)), 1.0);
}

// The far terrain (beyond the ring next to the planes): the same texture and tint, the sun and
// the sky's light without shadows. Its normal is +Y.
@fragment
fn fs_far(in: VertexOut) -> @location(0) vec4<f32> {
    let t = textureSample(ground_tex, ground_sampler, in.world_pos.xz / ground_params.metres_per_repeat).rgb;
    let c = t * in.tint * (frame.sun_color * max(frame.sun_dir.y, 0.0) + in.irr_front);
    return vec4<f32>(tone(mix(c, in.haze.rgb, in.haze.a)), 1.0);
}
