// Shared by every lit pass: the frame uniforms, the lighting resources and the shading model.
// Imported by every lit shader (`// #import lighting`, src/render/shader.rs).

// #import srgb, haze

struct Frame {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    light_view_proj: mat4x4<f32>,
    // The camera's position, metres, and the simulated time, seconds (modulo an hour).
    camera_pos: vec3<f32>,
    time: f32,
    // Unit vector towards the sun.
    sun_dir: vec3<f32>,
    pad0: f32,
    // Sun colour times intensity, linear RGB (zero below the horizon).
    sun_color: vec3<f32>,
    pad1: f32,
    // Ambient tint times strength, linear RGB, and the sky's brightness (0..1).
    ambient: vec3<f32>,
    sky: f32,
    // The shadow map's texel in uv, the normal offset of lookups in metres and their depth bias.
    shadow_texel: f32,
    shadow_normal_offset: f32,
    shadow_depth_bias: f32,
    pad2: f32,
};

@group(0) @binding(0) var<uniform> frame: Frame;

// Whether lit shaders look up the shadow map, set per pipeline from its `PipelineKey`
// (src/render/gpu.rs); the frame decides it in one place (src/render/frame.rs). A constant, not
// a uniform: lavapipe pays for both sides of a branch, so only a pipeline built without the
// lookups is spared their cost.
override SHADOWS: bool = true;

@group(1) @binding(0) var shadow_map: texture_depth_2d;
@group(1) @binding(1) var shadow_sampler: sampler_comparison;
@group(1) @binding(2) var env_map: texture_cube<f32>;
@group(1) @binding(3) var irradiance_map: texture_cube<f32>;
@group(1) @binding(4) var env_sampler: sampler;

// Fraction of sunlight reaching `world_pos` (1 = lit): four bilinear taps on the comparison
// sampler, half a texel from the centre on each diagonal. Each tap filters 2x2 texels, so
// together they weigh 3x3 texels with a tent (1 2 1 by 1 2 1), and shadow edges, including the
// dapples of leaves, are soft.
fn shadow_factor(world_pos: vec3<f32>, n: vec3<f32>) -> f32 {
    if (!SHADOWS) {
        return 1.0;
    }
    return shadow_at(shadow_coord(world_pos, n));
}

// Where `world_pos`, moved along the normal `n` by the normal offset, lies in the shadow map:
// uv and depth. The sun's projection is orthographic, so this is an affine function of the
// position and shaders may compute it per vertex and interpolate it.
fn shadow_coord(world_pos: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let p = frame.light_view_proj * vec4<f32>(world_pos + n * frame.shadow_normal_offset, 1.0);
    let ndc = p.xyz / p.w;
    return vec3<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5, ndc.z);
}

// `shadow_factor` at a shadow-map coordinate from `shadow_coord`.
fn shadow_at(coord: vec3<f32>) -> f32 {
    if (!SHADOWS) {
        return 1.0;
    }
    let uv = coord.xy;
    if (uv.x < 0.0 || uv.x > 1.0 || uv.y < 0.0 || uv.y > 1.0 || coord.z > 1.0) {
        return 1.0;
    }
    let h = 0.5 * frame.shadow_texel;
    let z = coord.z - frame.shadow_depth_bias;
    var sum = textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(-h, -h), z);
    sum = sum + textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(h, -h), z);
    sum = sum + textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(-h, h), z);
    sum = sum + textureSampleCompareLevel(shadow_map, shadow_sampler, uv + vec2<f32>(h, h), z);
    return sum * 0.25;
}

// Diffuse sun (with some translucency for leaves), Blinn-Phong specular scaled by the specular
// map, ambient from the irradiance cubemap and a Fresnel-weighted reflection of the environment.
fn shade(albedo: vec3<f32>, n: vec3<f32>, world_pos: vec3<f32>, spec_strength: f32, roughness: f32, translucency: f32) -> vec3<f32> {
    let irr = textureSampleLevel(irradiance_map, env_sampler, n, 0.0).rgb;
    return shade_lit(albedo, n, world_pos, spec_strength, roughness, translucency, irr);
}

// `shade` with the irradiance for the normal `n` given: for surfaces whose normal varies so
// slowly that the irradiance can be looked up per vertex (the ground).
fn shade_lit(albedo: vec3<f32>, n: vec3<f32>, world_pos: vec3<f32>, spec_strength: f32, roughness: f32, translucency: f32, irr: vec3<f32>) -> vec3<f32> {
    let l = frame.sun_dir;
    let v = normalize(frame.camera_pos - world_pos);
    let ndl = dot(n, l);
    let lit = shadow_factor(world_pos, n);
    let diffuse = max(ndl, 0.0) + translucency * max(-ndl, 0.0);
    let h = normalize(l + v);
    let shininess = mix(128.0, 6.0, clamp(roughness, 0.0, 1.0));
    let spec = spec_strength * 0.25 * pow(max(dot(n, h), 0.0), shininess) * select(0.0, 1.0, ndl > 0.0);
    let direct = frame.sun_color * lit * (albedo * diffuse + vec3<f32>(spec));
    let ambient = irr * frame.ambient * albedo;
    // Reflections of the sky, skipped (one cube lookup less) where they would be invisible.
    var refl = vec3<f32>(0.0);
    let glossy = spec_strength * (1.0 - roughness) * (1.0 - roughness);
    if (glossy > 0.02) {
        let r = reflect(-v, n);
        let fres = 0.04 + 0.96 * pow(1.0 - max(dot(n, v), 0.0), 5.0);
        refl = srgb_decode(textureSampleLevel(env_map, env_sampler, r, roughness * 6.0).rgb) * frame.sky * fres * glossy;
    }
    return direct + ambient + refl;
}

// A gentle tone curve so that bright sun on light bark does not clip hard.
fn tone(c: vec3<f32>) -> vec3<f32> {
    return c / (1.0 + 0.15 * c);
}

// Aerial perspective: beyond 40 m, the colour faded towards the sky's colour at the horizon in
// the view direction with distance, entirely so at the far plane (600 m), where the terrain ends.
fn aerial(c: vec3<f32>, world_pos: vec3<f32>) -> vec3<f32> {
    let h = haze_at(world_pos);
    return mix(c, h.rgb, h.a);
}

// The haze colour (rgb) and its share (a) at `world_pos`, as `aerial` mixes them (the share by
// distance from the HAZE_* constants of the piece `haze`, src/render/haze.rs, whose
// `haze_share` is its CPU twin): shaders that
// fade per vertex interpolate this and mix in the fragment. The colour is the sky's along the
// view ray (`sky_lit`), so terrain that has faded entirely (at the far plane, where it ends) is
// the colour the sky draws beyond it, from any height: no edge at the horizon.
fn haze_at(world_pos: vec3<f32>) -> vec4<f32> {
    let to = world_pos - frame.camera_pos;
    let d = max(length(to), 1e-6);
    let f = max(1.0 - exp(-max(d - HAZE_START, 0.0) / HAZE_DEPTH), smoothstep(HAZE_FULL_FROM, HAZE_FULL_AT, d));
    let u = to / d;
    return vec4<f32>(sky_lit(u, log2(max(dot(u, frame.sun_dir), 1e-6))), f);
}

// The sky's colour seen along the unit view direction `u`, without the sun's disc: the
// environment cubemap, tinted like the ambient light (warmer when the sun is low) and dimmed
// with the sun's elevation, plus the sun's halo and its wide glow near the horizon (s^40 and
// s^4 of the cosine to the sun, from `ls`, the logarithm (base 2) of that cosine). The cubemap
// is read along the ray with its height raised to at least 0.02 (about 1.1° above the horizon
// for a level ray), so that a ray below the horizon, which meets the ground, takes the colour
// of the sky just above the horizon in its direction: the cubemap's own lower half (its ground) is never seen, the
// sky meets the faded terrain without a band, and a surface above the horizon fades into the
// very sky behind it. The sky shader draws this wherever nothing else was drawn.
fn sky_lit(u: vec3<f32>, ls: f32) -> vec3<f32> {
    // A cube is read along any non-zero vector: no need to normalise the raised one.
    let dir = vec3<f32>(u.x, max(u.y, 0.02), u.z);
    let tint = frame.ambient / max(frame.ambient.r, 0.001);
    let env = srgb_decode(textureSampleLevel(env_map, env_sampler, dir, 0.0).rgb) * frame.sky * tint;
    let low = 1.0 - clamp(frame.sun_dir.y * 2.0, 0.0, 1.0);
    return env + frame.sun_color * (exp2(40.0 * ls) * 0.12 + exp2(4.0 * ls) * 0.25 * low);
}
