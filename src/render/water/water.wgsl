// Water: the surface of each pond, drawn in the main pass before the ground. lighting.wgsl is
// prepended (group 0 the view, group 1 the lighting). What the surface shows comes from two
// textures the frame drew before the main pass (src/render/water/mod.rs): the reflection (the
// scene from the camera mirrored in the surface, clipped at it) and the refraction (what lies
// below the surface, seen from the camera, with its depth). Two normal maps scroll in different
// directions; the normal they make shifts both lookups, Schlick's Fresnel term mixes them, the
// sun leaves a glint, and where the water is shallow towards the shore it fades into the bed.
// Units: metres, seconds; +Y up.

// #import lighting

struct WaterParams {
    // World to the reflection texture's clip space (the matrix its pass drew with).
    reflection_view_proj: mat4x4<f32>,
    // The refraction texture's clip space back to the world (for the bed's depth).
    refraction_inv_view_proj: mat4x4<f32>,
    // x: what to show (0 the water, 1 the reflection alone, 2 the refraction alone);
    // y, z: the main target's size in pixels; w: unused.
    misc: vec4<f32>,
};

@group(2) @binding(0) var<uniform> water: WaterParams;
@group(2) @binding(1) var reflection_tex: texture_2d<f32>;
@group(2) @binding(2) var refraction_tex: texture_2d<f32>;
@group(2) @binding(3) var refraction_depth: texture_depth_2d;
@group(2) @binding(4) var normal_map: texture_2d<f32>;
@group(2) @binding(5) var clamp_sampler: sampler;
@group(2) @binding(6) var repeat_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) colour_depth: vec4<f32>,
    @location(2) ripple: vec2<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) colour_depth: vec4<f32>,
    @location(2) ripple: vec2<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.world_pos = v.position;
    out.colour_depth = v.colour_depth;
    out.ripple = v.ripple;
    return out;
}

// Clip space to texture coordinates (v down).
fn clip_uv(c: vec4<f32>) -> vec2<f32> {
    let ndc = c.xy / c.w;
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
}

// The length of the path through the water from the surface point `surface` to what the
// refraction texture shows at `uv`; 1000 m where it shows nothing.
fn water_path(uv: vec2<f32>, surface: vec3<f32>) -> f32 {
    let size = vec2<f32>(textureDimensions(refraction_depth));
    let texel = vec2<i32>(clamp(uv * size, vec2<f32>(0.0), size - 1.0));
    let d = textureLoad(refraction_depth, texel, 0);
    if (d >= 1.0) {
        return 1000.0;
    }
    let ndc = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, d, 1.0);
    let w = water.refraction_inv_view_proj * ndc;
    return length(w.xyz / w.w - surface);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let strength = in.ripple.x;
    let drift = in.ripple.y * frame.time;
    // Two normal maps (one texture at two scales) scrolling in different directions.
    let p = in.world_pos.xz;
    let a = textureSample(normal_map, repeat_sampler, (p + vec2<f32>(0.6, 0.8) * drift) / 3.1).xyz * 2.0 - 1.0;
    let b = textureSample(normal_map, repeat_sampler, (p + vec2<f32>(-0.9, 0.45) * drift) / 1.7).xyz * 2.0 - 1.0;
    // Tangent space: u along world X, v along world Z, the map's Z up. Strength 0 is a mirror.
    let s = 0.3 * strength;
    let n = normalize(vec3<f32>(s * (a.x + b.x), a.z + b.z, s * (a.y + b.y)));

    let v = normalize(frame.camera_pos - in.world_pos);
    let screen = in.clip.xy / water.misc.yz;
    // How much water lies under this point, straight along the view: the shore fades in where
    // it is shallow, and the ripples distort less there (so they do not pull the shore in).
    let path = water_path(screen, in.world_pos);
    let shore = smoothstep(0.0, 0.35, path);
    let shift = n.xz * 0.035 * shore;

    // Reflection: the surface point through the reflection camera, shifted by the ripples.
    let ruv = clamp(clip_uv(water.reflection_view_proj * vec4<f32>(in.world_pos, 1.0)) + shift, vec2<f32>(0.001), vec2<f32>(0.999));
    let reflected = textureSampleLevel(reflection_tex, clamp_sampler, ruv, 0.0).rgb;

    // Refraction: what lies below, shifted by the ripples, tinted and darkened with the length
    // of the path through the water (the unshifted one: a second depth lookup would cost a
    // software rasteriser much and change little).
    let t_path = path;
    let below = textureSampleLevel(refraction_tex, clamp_sampler, screen + shift, 0.0).rgb;
    let deep = in.colour_depth.rgb * (frame.ambient * frame.sky + frame.sun_color * 0.25);
    // Light fades to a tenth over the body's depth.
    let k = 2.3 / max(in.colour_depth.w, 0.1);
    let transmit = exp(-k * t_path);
    let tint = mix(in.colour_depth.rgb * 4.0, vec3<f32>(1.0), transmit);
    let refracted = mix(tone(deep), below * clamp(tint, vec3<f32>(0.0), vec3<f32>(1.0)), transmit);

    // Schlick's Fresnel term for water (F0 = 0.02), faded out at the shore.
    let f = (0.02 + 0.98 * pow(1.0 - max(dot(n, v), 0.0), 5.0)) * shore;
    // The sun's glint on the ripples.
    let r = reflect(-v, n);
    let glint = frame.sun_color * pow(max(dot(r, frame.sun_dir), 0.0), 600.0) * 4.0 * shore;
    var c = mix(refracted, reflected, f) + tone(glint);

    let mode = u32(water.misc.x + 0.5);
    if (mode == 1u) {
        c = reflected;
    } else if (mode == 2u) {
        c = below;
    }
    return vec4<f32>(c, 1.0);
}
