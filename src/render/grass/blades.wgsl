// Grass blades, drawn from what the cull pass wrote (cull.wgsl), nearest level first so that
// near blades hide far ones before they are shaded: two non-instanced indexed indirect draws,
// 7 segments near the camera (13 triangles) and 3 further away (5 triangles), then the far
// blades, narrower than a pixel, which the cull pass rasterised into an image of their depth
// and lit colour: a rectangle around them (`vs_far`, `fs_far`) puts each pixel a far blade
// covers on the target and writes its depth, so the far blades hide and are hidden like the
// rest of the scene. lighting.wgsl (src/render/gpu.rs) and shapes.wgsl (the blade's `Shape` and
// the draw's `BladeParams`, shared with cull.wgsl) are prepended.
//
// The cull pass has already evaluated the wind, the pushes and the gravity bend: a blade is a
// quadratic Bézier curve from its root to its tip, widened across and narrowing to the tip. The
// sun, the sky's irradiance and the specular highlight are evaluated per vertex; a near blade's
// fragment only looks up the shadow (the trees' shadows fall on the grass), a middle blade's
// vertices look it up themselves.
//
// Units: metres, radians; +Y up.

// #import lighting, grass_constants, grass_shapes



@group(2) @binding(0) var<uniform> params: BladeParams;
@group(2) @binding(1) var<storage, read> shapes: array<Shape>;
// The near and middle lists one after the other (cull.wgsl); each draw's base vertex makes
// `vertex_index / vertices a blade` the index into this buffer.
@group(2) @binding(2) var<storage, read> lists: array<u32>;
// The cull pass's draw counts, then from word RASTER_OFFSET (written from Rust) the far
// blades' image (`pack_far`): per pixel 0, or a depth code (nearer is larger) in the top 11
// bits above the lit colour's square roots in 7 bits each (of 0 … 1 / 0.85, which `tone` maps
// to white).
@group(2) @binding(3) var<storage, read> raster: array<u32>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // The light that does not depend on the shadow (the sky's) and the sun's, linear RGB.
    @location(2) ambient: vec3<f32>,
    @location(3) direct: vec3<f32>,
};

// Vertex `corner` of a blade with `segments` segments: the left (even) and right (odd)
// corners of rows 0 … segments − 1, then the tip (2 × segments). The index buffers
// (src/render/grass/data.rs, `blade_indices`) join them into segments − 1 quads and the tip
// triangle; each vertex is shaded once.
fn strip_vertex(s: Shape, corner: u32, segments: u32) -> VertexOut {
    let is_tip = corner >= 2u * segments;
    let t = select(f32(corner / 2u) / f32(segments), 1.0, is_tip);
    return blade_vertex(s, t, select(-1.0, 1.0, (corner & 1u) == 1u));
}

// The point of blade `s` at `t` along it (0 at the root, 1 at the tip), on its left edge
// (side −1) or its right edge (+1).
fn blade_vertex(s: Shape, t: f32, side: f32) -> VertexOut {
    let c01 = unpack2x16float(s.curve0);
    let c23 = unpack2x16float(s.curve1);
    let c45 = unpack2x16float(s.curve2);
    let ctrl = vec3<f32>(c01, c23.x);
    let tip = vec3<f32>(c23.y, c45);
    let a = unpack2x16float(s.across);
    let across = vec3<f32>(a.x, 0.0, a.y);
    let half_width = unpack2x16float(s.width_patch & 0xffffu).x;
    let patch_index = (s.width_patch >> 16u) & 255u;
    let variation = f32(s.width_patch >> 24u) / 255.0;

    // The point and the tangent of the curve at t.
    let u = 1.0 - t;
    var p = s.root + ctrl * (2.0 * t * u) + tip * (t * t);
    let dir = ctrl * (2.0 * u) + (tip - ctrl) * (2.0 * t);
    // The width narrows to a point at the tip.
    p = p + across * (side * half_width * (1.0 - t * t));
    // The face's normal, rounded a little across the blade so it does not look flat, and
    // turned towards the eye: both faces are lit.
    let to_eye = frame.camera_pos - p;
    var normal = normalize(normalize(cross(across, dir)) + across * (side * 0.35));
    if (dot(normal, to_eye) < 0.0) {
        normal = -normal;
    }

    let root_colour = params.colours[2u * patch_index].rgb;
    let tip_colour = params.colours[2u * patch_index + 1u].rgb;
    // Darker near the root (the lawn shades itself), and each blade a little different.
    let albedo = mix(root_colour, tip_colour, t) * mix(0.55, 1.0, t) * (0.8 + 0.4 * variation);

    // The shading model of `shade_lit` (lighting.wgsl) for grass (specular 0.15, roughness
    // 0.55, translucency 0.6) without the shadow, which the fragment adds.
    let l = frame.sun_dir;
    let v = normalize(to_eye);
    let ndl = dot(normal, l);
    let diffuse = max(ndl, 0.0) + 0.6 * max(-ndl, 0.0);
    let h = normalize(l + v);
    let spec = 0.15 * 0.25 * pow(max(dot(normal, h), 0.0), 60.9) * select(0.0, 1.0, ndl > 0.0);
    let irr = textureSampleLevel(irradiance_map, env_sampler, normal, 0.0).rgb;

    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(p, 1.0);
    out.world_pos = p;
    out.normal = normal;
    out.ambient = irr * frame.ambient * albedo;
    out.direct = frame.sun_color * (albedo * diffuse + vec3<f32>(spec));
    return out;
}

@vertex
fn vs_near(@builtin(vertex_index) v: u32) -> VertexOut {
    return strip_vertex(shapes[lists[v / NEAR_VERTICES]], v % NEAR_VERTICES, NEAR_SEGMENTS);
}

// A middle blade is a few pixels wide: its shadow is looked up per vertex (7 lookups a blade
// instead of one for each of its pixels) and `fs_lit` only adds the light up.
@vertex
fn vs_mid(@builtin(vertex_index) v: u32) -> VertexOut {
    var out = strip_vertex(shapes[lists[v / MID_VERTICES]], v % MID_VERTICES, MID_SEGMENTS);
    out.direct = out.direct * shadow_factor(out.world_pos, out.normal);
    return out;
}

// The far blades' rectangle: two triangles over the box of pixels the cull pass found them to
// cover (words 11 to 14 of `raster`), empty when there are none.
@vertex
fn vs_far(@builtin(vertex_index) v: u32) -> @builtin(position) vec4<f32> {
    let size = params.viewport.xy;
    let lo = min(vec2<f32>(f32(raster[11u]), f32(raster[12u])), size);
    let hi = max(min(vec2<f32>(f32(raster[13u]), f32(raster[14u])) + 1.0, size), lo);
    // Corners (0, 0), (1, 0), (0, 1), then (0, 1), (1, 0), (1, 1).
    let k = select(v, 6u - v, v > 2u);
    let corner = vec2<f32>(f32(k & 1u), f32(k >> 1u));
    let px = mix(lo, hi, corner);
    return vec4<f32>(px.x / size.x * 2.0 - 1.0, 1.0 - px.y / size.y * 2.0, 0.0, 1.0);
}

struct FarOut {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

// A pixel of the far blades' image: its colour, lit by the cull pass, toned; with shadows, the
// sun's share of it dimmed by the trees' shadow there. Pixels no far blade covers are
// discarded. The depth written is the depth code's (its nearer edge, so that a blade's root
// is not hidden by the ground it stands on).
@fragment
fn fs_far(@builtin(position) pos: vec4<f32>) -> FarOut {
    let size = params.viewport.xy;
    let word = raster[RASTER_OFFSET + u32(pos.y) * u32(size.x) + u32(pos.x)];
    if (word == 0u) {
        discard;
    }
    let w = max(f32(2047u - (word >> 21u)) / 2047.0 * params.viewport.z, 0.1);
    let z = params.depth.x + params.depth.y / w;
    let e = vec3<f32>(f32((word >> 14u) & 127u), f32((word >> 7u) & 127u), f32(word & 127u)) / 127.0;
    var c = e * e / 0.85;
    if (SHADOWS) {
        // The world position, a face turned to the eye and tilted up (as `far_sky` in cull.wgsl
        // takes it), and the sun's share of the light on it.
        let ndc = vec2<f32>(pos.x / size.x * 2.0 - 1.0, 1.0 - pos.y / size.y * 2.0);
        let h = frame.inv_view_proj * vec4<f32>(ndc, z, 1.0);
        let p = h.xyz / h.w;
        let v = normalize(frame.camera_pos - p);
        let n = normalize(vec3<f32>(v.x, 0.0, v.z) + vec3<f32>(1e-4, 0.4, 0.0));
        let ndl = dot(n, frame.sun_dir);
        let sun = dot(frame.sun_color, vec3<f32>(0.2126, 0.7152, 0.0722)) * (max(ndl, 0.0) + 0.6 * max(-ndl, 0.0));
        let sky = dot(textureSampleLevel(irradiance_map, env_sampler, n, 0.0).rgb * frame.ambient, vec3<f32>(0.2126, 0.7152, 0.0722));
        c = c * (1.0 - sun / max(sun + sky, 1e-4) * (1.0 - shadow_factor(p, n)));
    }
    var out: FarOut;
    out.colour = vec4<f32>(tone(c), 1.0);
    out.depth = z;
    return out;
}

// A middle blade's pixel: its light, shadowed per vertex (`vs_mid`).
@fragment
fn fs_lit(in: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(tone(in.ambient + in.direct), 1.0);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let lit = shadow_factor(in.world_pos, normalize(in.normal));
    return vec4<f32>(tone(in.ambient + in.direct * lit), 1.0);
}
