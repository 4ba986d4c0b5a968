// Ground planes as a landscape: the Plane meshes, their sides, the soil floor under them (seen
// through the holes, which are missing triangles) and the terrain around them, textured in world
// space at three scales so the texture does not visibly repeat, lit and shadowed, and faded into
// the sky's colour at the horizon with distance (aerial perspective). lighting.wgsl is prepended
// (src/render/ground/mod.rs; the kinds are those of src/render/ground/landscape.rs).
//
// The aerial perspective is computed per vertex (the terrain is cut into cells small enough for
// it to vary linearly), and the far terrain has its own fragment entry, `fs_far`: one texture
// scale and no shadow lookups. On a software rasteriser these per-pixel savings are most of the
// landscape's cost.

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
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.world_pos = v.position;
    out.normal = v.normal;
    out.irr_front = textureSampleLevel(irradiance_map, env_sampler, v.normal, 0.0).rgb;
    out.irr_back = textureSampleLevel(irradiance_map, env_sampler, -v.normal, 0.0).rgb;
    out.kind = u32(v.kind + 0.5);
    out.haze = haze_at(v.position);
    return out;
}

// The ground texture at three scales: the base repeat, a second sample rotated and at about
// 3.9 times the size, and a broad brightness variation at about 17 times, so no repeat shows.
fn ground_albedo(p: vec2<f32>) -> vec3<f32> {
    let m = ground_params.metres_per_repeat;
    let a = textureSample(ground_tex, ground_sampler, p / m).rgb;
    let q = vec2<f32>(0.8 * p.x - 0.6 * p.y, 0.6 * p.x + 0.8 * p.y);
    let b = textureSample(ground_tex, ground_sampler, q / (3.9 * m) + vec2<f32>(0.37, 0.11)).rgb;
    let c = textureSample(ground_tex, ground_sampler, p / (17.3 * m) + vec2<f32>(0.71, 0.53)).rgb;
    // The broad sample's brightness against the base sample's: about 0.5 on average.
    let w = vec3<f32>(0.3, 0.6, 0.1);
    let share = dot(c, w) / max(dot(c, w) + dot(a, w), 0.01);
    let broad = 0.6 + 0.8 * share;
    return mix(a, b, 0.4) * broad;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // One texture lookup set for every kind (no divergent branches around the samples): sides
    // take the texture along the wall, everything else in the horizontal plane.
    let along = in.world_pos.x * in.normal.z - in.world_pos.z * in.normal.x;
    let uv = select(in.world_pos.xz, vec2<f32>(along, in.world_pos.y * 2.0), in.kind == 1u);
    let t = ground_albedo(uv);
    let lum = dot(t, vec3<f32>(0.3, 0.6, 0.1));
    // Soil (the sides and the floor under the holes): brown, with the texture's brightness; the
    // sides as cut soil, the floor darker; the terrain the same ground, a little greener.
    let soil = vec3<f32>(0.2, 0.13, 0.08);
    var albedo = t;
    albedo = select(albedo, soil * (0.5 + 2.0 * lum), in.kind == 1u);
    albedo = select(albedo, soil * (0.25 + 1.0 * lum), in.kind == 3u);
    albedo = select(albedo, t * vec3<f32>(0.85, 1.0, 0.75), in.kind == 2u);
    let n = normalize(in.normal) * select(-1.0, 1.0, front);
    let irr = select(in.irr_back, in.irr_front, front);
    let c = shade_lit(albedo, n, in.world_pos, 0.08, 0.95, 0.0, irr);
    return vec4<f32>(tone(mix(c, in.haze.rgb, in.haze.a)), 1.0);
}

// The far terrain (beyond the ring next to the planes): the ground texture at one scale, the
// sun and the sky's light without shadows or highlights, and the haze. Its normal is +Y.
@fragment
fn fs_far(in: VertexOut) -> @location(0) vec4<f32> {
    let m = ground_params.metres_per_repeat;
    let p = in.world_pos.xz;
    let q = vec2<f32>(0.8 * p.x - 0.6 * p.y, 0.6 * p.x + 0.8 * p.y);
    let t = textureSample(ground_tex, ground_sampler, q / (3.9 * m) + vec2<f32>(0.37, 0.11)).rgb;
    let albedo = t * vec3<f32>(0.85, 1.0, 0.75);
    let c = albedo * (frame.sun_color * max(frame.sun_dir.y, 0.0) + in.irr_front * frame.ambient);
    return vec4<f32>(tone(mix(c, in.haze.rgb, in.haze.a)), 1.0);
}
