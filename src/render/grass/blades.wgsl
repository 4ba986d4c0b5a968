// Grass blades, drawn from the lists the cull pass wrote (cull.wgsl), one instance per visible
// blade, as a triangle strip: 15 vertices near the camera (7 segments and the tip), 7 further
// away (3 segments and the tip). lighting.wgsl is prepended (src/render/gpu.rs).
//
// A blade is built in its own frame: it grows up from its root, each segment leaning further in
// its facing direction by the blade's gravity bend. The wind is a rotation per segment towards
// the wind's direction, its angle read from a world-space noise texture scrolled along the
// wind, so neighbouring blades move together; the angle grows along the blade. Near the eye and
// near the controller's hit point, the blade is also turned away from that point.
//
// Units: metres, radians; +Y up.

struct Blade {
    position: vec3<f32>,
    height: f32,
    yaw: f32,
    bend: f32,
    width: f32,
    packed: u32,
};

struct BladeParams {
    // The wind: direction (x, z), the bend it gives (radians at the tip), the time, seconds.
    wind: vec4<f32>,
    // The scroll speed of the wind noise (m/s), its scale (per metre), unused, unused.
    wind_noise: vec4<f32>,
    // The eye, metres, and the radius within which blades bend away from it.
    eye: vec4<f32>,
    // The controller's hit point, metres, and its radius (0: no hit point).
    hit: vec4<f32>,
    // Per patch: the root colour, then the tip colour (linear RGB).
    colours: array<vec4<f32>, 128>,
};

@group(2) @binding(0) var<uniform> params: BladeParams;
@group(2) @binding(1) var<storage, read> blades: array<Blade>;
@group(2) @binding(2) var<storage, read> near_list: array<u32>;
@group(2) @binding(3) var<storage, read> far_list: array<u32>;
@group(2) @binding(4) var wind_tex: texture_2d<f32>;
@group(2) @binding(5) var wind_sampler: sampler;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
    // The irradiance for the normal, looked up per vertex.
    @location(3) irr: vec3<f32>,
};

// The horizontal push away from `centre` within `radius` (zero outside), as an angle times a
// direction.
fn push(root: vec3<f32>, centre: vec3<f32>, radius: f32, strength: f32) -> vec2<f32> {
    let d = root.xz - centre.xz;
    let dist = length(d);
    if (radius <= 0.0 || dist >= radius || dist < 1e-4) {
        return vec2<f32>(0.0);
    }
    let f = 1.0 - dist / radius;
    return d / dist * strength * f * f;
}

// One vertex of blade `b`, with `segments` segments; vertex `v` of the strip.
fn blade_vertex(b: Blade, v: u32, segments: u32) -> VertexOut {
    let patch_index = b.packed & 255u;
    let variation = f32(b.packed >> 8u) / 16777216.0;
    // The blade's width direction and the direction it leans, both horizontal.
    let across = vec3<f32>(cos(b.yaw), 0.0, -sin(b.yaw));
    let lean = vec3<f32>(sin(b.yaw), 0.0, cos(b.yaw));
    // The wind at the root: an angle towards the wind's direction from the scrolled noise.
    let wdir = vec2<f32>(params.wind.x, params.wind.y);
    let uv = b.position.xz * params.wind_noise.y - wdir * params.wind.w * params.wind_noise.x * params.wind_noise.y;
    let n = textureSampleLevel(wind_tex, wind_sampler, uv, 0.0).r;
    let sway = params.wind.z * (0.35 + 0.65 * n) * (0.85 + 0.3 * variation);
    // The total tilt at the tip: the wind plus the pushes away from the eye and the hit point.
    var tilt = wdir * sway;
    // The eye pushes only when it is within 2 m above the blade.
    let eye_near = clamp(2.0 - (params.eye.y - b.position.y), 0.0, 1.0);
    tilt = tilt + push(b.position, params.eye.xyz, params.eye.w, 1.2 * eye_near);
    tilt = tilt + push(b.position, params.hit.xyz, params.hit.w, 1.3);
    let tilt_angle = min(length(tilt), 1.45);
    let tilt_axis = normalize(cross(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(tilt.x, 0.0, tilt.y) + vec3<f32>(1e-6, 0.0, 0.0)));

    // Walk up the segments below this vertex. Segment k's direction is the vertical turned
    // towards `lean` by the gravity bend and then about the tilt axis by its share of the tilt,
    // both at (k + 1/2) / segments of the full angle. The cosines and sines of those angles are
    // advanced by the angle-addition formulas, so a vertex costs eight trigonometric calls
    // rather than four per segment.
    let seg = min(v / 2u, segments);
    let n_seg = f32(segments);
    let segment_length = b.height / n_seg;
    let step_bend = b.bend / n_seg;
    let step_tilt = tilt_angle / n_seg;
    let bend_step = vec2<f32>(cos(step_bend), sin(step_bend));
    let tilt_step = vec2<f32>(cos(step_tilt), sin(step_tilt));
    var bend_cs = vec2<f32>(cos(0.5 * step_bend), sin(0.5 * step_bend));
    var tilt_cs = vec2<f32>(cos(0.5 * step_tilt), sin(0.5 * step_tilt));
    let up = vec3<f32>(0.0, 1.0, 0.0);
    var p = b.position;
    var dir = up;
    for (var k = 0u; k < seg; k = k + 1u) {
        let g = up * bend_cs.x - lean * bend_cs.y;
        dir = g * tilt_cs.x + cross(tilt_axis, g) * tilt_cs.y + tilt_axis * dot(tilt_axis, g) * (1.0 - tilt_cs.x);
        p = p + dir * segment_length;
        bend_cs = vec2<f32>(bend_cs.x * bend_step.x - bend_cs.y * bend_step.y, bend_cs.y * bend_step.x + bend_cs.x * bend_step.y);
        tilt_cs = vec2<f32>(tilt_cs.x * tilt_step.x - tilt_cs.y * tilt_step.y, tilt_cs.y * tilt_step.x + tilt_cs.x * tilt_step.y);
    }
    let t = f32(seg) / f32(segments);
    // The width narrows to a point at the tip (the last vertex is the tip alone).
    let half_width = 0.5 * b.width * (1.0 - t * t);
    let side = select(-1.0, 1.0, (v & 1u) == 1u);
    let is_tip = v >= 2u * segments;
    if (!is_tip) {
        p = p + across * side * half_width;
    }
    // The face's normal, rounded a little across the blade so it does not look flat.
    let face = normalize(cross(across, dir));
    var normal = normalize(face + across * side * 0.35);
    // Both faces are lit: the normal is turned towards the eye.
    if (dot(normal, frame.camera_pos - p) < 0.0) {
        normal = -normal;
    }

    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(p, 1.0);
    out.world_pos = p;
    out.normal = normal;
    out.irr = textureSampleLevel(irradiance_map, env_sampler, normal, 0.0).rgb;
    let root = params.colours[2u * patch_index].rgb;
    let tip = params.colours[2u * patch_index + 1u].rgb;
    // Darker near the root (the lawn shades itself), and each blade a little different.
    out.albedo = mix(root, tip, t) * mix(0.55, 1.0, t) * (0.8 + 0.4 * variation);
    return out;
}

@vertex
fn vs_near(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> VertexOut {
    return blade_vertex(blades[near_list[i]], v, 7u);
}

@vertex
fn vs_far(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> VertexOut {
    return blade_vertex(blades[far_list[i]], v, 3u);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let c = shade_lit(in.albedo, normalize(in.normal), in.world_pos, 0.15, 0.55, 0.6, in.irr);
    return vec4<f32>(tone(c), 1.0);
}
