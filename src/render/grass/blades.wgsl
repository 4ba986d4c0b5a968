// Grass blades, drawn from the lists the cull pass wrote (cull.wgsl) in three non-instanced
// indirect draws (the near and middle ones indexed), nearest level first so that near blades hide far ones before they are
// shaded: 7 segments near the camera (13 triangles), 3 further away (5 triangles), and far away,
// where a blade is narrower than a pixel, a line from its root to its tip (a software
// rasteriser pays per primitive and per vertex; a line is one primitive of two vertices and,
// unlike a sub-pixel triangle, always covers its pixels). lighting.wgsl is prepended
// (src/render/gpu.rs).
//
// The cull pass has already evaluated the wind, the pushes and the gravity bend: a blade is a
// quadratic Bézier curve from its root to its tip, widened across and narrowing to the tip. The
// sun, the sky's irradiance and the specular highlight are evaluated per vertex; the fragment
// only looks up the shadow (the trees' shadows fall on the grass).
//
// Units: metres, radians; +Y up.

// A visible blade's shape (matches `Shape` in cull.wgsl).
struct Shape {
    root: vec3<f32>,
    width_patch: u32,
    curve0: u32,
    curve1: u32,
    curve2: u32,
    across: u32,
};

struct BladeParams {
    // Per patch: the root colour, then the tip colour (linear RGB).
    colours: array<vec4<f32>, 128>,
};

@group(2) @binding(0) var<uniform> params: BladeParams;
@group(2) @binding(1) var<storage, read> shapes: array<Shape>;
// The near, middle and far lists one after the other (cull.wgsl); each draw's first vertex
// makes `vertex_index / vertices a blade` the index into this buffer.
@group(2) @binding(2) var<storage, read> lists: array<u32>;

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
// (side −1), its right edge (+1) or its middle (0).
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
    // A line (side 0) covers whole pixels where the blade would cover a part of each: it is
    // darker, so that a far lawn keeps the tone of its near part.
    let albedo = mix(root_colour, tip_colour, t) * mix(0.55, 1.0, t) * (0.8 + 0.4 * variation) * select(1.0, 0.7, side == 0.0);

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
    return strip_vertex(shapes[lists[v / 15u]], v % 15u, 7u);
}

@vertex
fn vs_mid(@builtin(vertex_index) v: u32) -> VertexOut {
    return strip_vertex(shapes[lists[v / 7u]], v % 7u, 3u);
}

@vertex
fn vs_far(@builtin(vertex_index) v: u32) -> VertexOut {
    // A line: the root, then the tip.
    return blade_vertex(shapes[lists[v / 2u]], f32(v & 1u), 0.0);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let lit = shadow_factor(in.world_pos, normalize(in.normal));
    return vec4<f32>(tone(in.ambient + in.direct * lit), 1.0);
}
