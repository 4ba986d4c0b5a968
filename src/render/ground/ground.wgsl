// Ground planes as a landscape: the Plane meshes, their sides (earth banks with a soil edge under
// their outlines, pits with sloping soil walls under their holes: banks.rs), the soil floor under
// them (seen through the holes, which are missing triangles) and the terrain around them, lit and
// shadowed, and faded into the sky's colour at the horizon with distance (aerial perspective).
// lighting.wgsl is prepended (src/render/ground/mod.rs; the kinds are those of
// src/render/ground/landscape.rs).
//
// Written for a software rasteriser, where a pixel's cost is its instructions and, above all,
// its filtered texture samples: a pixel takes one sample of the ground texture (its 2.5 m
// repeat), and the variation at larger scales that hides the repeat (about 12 m, 70 m and a hue
// over 150 m) comes per vertex as the tint, computed on the CPU (landscape.rs, `Tint`). The
// aerial perspective and the irradiance are also per vertex (the terrain is cut into cells small
// enough for them to vary linearly); the ground's light is diffuse and ambient only (its weak,
// broad highlight, specular strength 0.08, is left out). The far terrain has its own fragment
// entry, `fs_far`: no shadow lookups.

// #import lighting

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
    // 0 a plane, 1 a plane's soil side (a bank's cut, a pit's wall), 2 terrain, 3 the soil
    // floor, 4 a bank's grassed slope.
    @location(2) kind: f32,
    // The albedo's factor at scales above the texture's repeat (linear RGB); on soil, its shade.
    @location(3) tint: vec3<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // The texture coordinate, metres: along the ground, or along and up a side.
    @location(0) uv: vec2<f32>,
    // The position in the shadow map (`shadow_coord`), affine in the position.
    @location(1) shadow: vec3<f32>,
    // The albedo's factor times the sunlight on the front (before shadowing), and times the
    // sky's light on the front and on the back (seen from below: no sun there). The ground's
    // normals vary slowly, so per vertex is enough.
    @location(2) sun_front: vec3<f32>,
    @location(3) sky_front: vec3<f32>,
    @location(4) sky_back: vec3<f32>,
    // The aerial perspective's haze colour (rgb) and how much of it covers the ground (a).
    @location(5) haze: vec4<f32>,
    // 1 for soil (sides and floor), 0 for the ground.
    @location(6) @interpolate(flat) soil: f32,
};

// Soil's colour (linear RGB), times 0.25 plus the texture's brightness: cut soil takes twice
// this, the floor under the holes once.
const SOIL: vec3<f32> = vec3<f32>(0.2, 0.13, 0.08);

// The albedo's factor of a vertex of `kind` (landscape.rs) with the tint `tint`: the ground as
// textured and tinted, the terrain and the banks' grassed slopes a little greener; soil (see
// `SOIL`), whose tint is only its shade (darker towards a pit's foot), brighter on the sides.
fn albedo_factor(kind: u32, tint: vec3<f32>) -> vec3<f32> {
    switch kind {
        case 1u: { return 2.0 * tint; }
        case 2u, 4u: { return tint * vec3<f32>(0.85, 1.0, 0.75); }
        default: { return tint; }
    }
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    let kind = u32(v.kind + 0.5);
    // Sides take the texture along the wall, everything else in the horizontal plane.
    let along = v.position.x * v.normal.z - v.position.z * v.normal.x;
    out.uv = select(v.position.xz, vec2<f32>(along, v.position.y * 2.0), kind == 1u) / ground_params.metres_per_repeat;
    out.shadow = shadow_coord(v.position, v.normal);
    let f = albedo_factor(kind, v.tint);
    out.sun_front = f * frame.sun_color * max(dot(v.normal, frame.sun_dir), 0.0);
    out.sky_front = f * textureSampleLevel(irradiance_map, env_sampler, v.normal, 0.0).rgb * frame.ambient;
    out.sky_back = f * textureSampleLevel(irradiance_map, env_sampler, -v.normal, 0.0).rgb * frame.ambient;
    out.haze = haze_at(v.position);
    out.soil = select(0.0, 1.0, kind == 1u || kind == 3u);
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let tex = srgb_decode(textureSample(ground_tex, ground_sampler, in.uv).rgb);
    let t = select(tex, SOIL * (0.25 + dot(tex, vec3<f32>(0.3, 0.6, 0.1))), in.soil > 0.5);
    let light = select(in.sky_back, in.sun_front * shadow_at(in.shadow) + in.sky_front, front);
    return vec4<f32>(tone(mix(t * light, in.haze.rgb, in.haze.a)), 1.0);
}

// The far terrain (beyond the ring next to the planes): the same, without shadows (the shadow
// map does not reach that far); seen from above only.
@fragment
fn fs_far(in: VertexOut) -> @location(0) vec4<f32> {
    let t = srgb_decode(textureSample(ground_tex, ground_sampler, in.uv).rgb);
    return vec4<f32>(tone(mix(t * (in.sun_front + in.sky_front), in.haze.rgb, in.haze.a)), 1.0);
}
