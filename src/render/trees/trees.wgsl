// Trees: instanced, textured (albedo, normal, specular), alpha-clipped leaves, two-sided leaves
// with the normal's component along the face normal flipped on back faces. Every vertex, in the
// main pass and the shadow pass alike, is displaced by wind.wgsl's `wind_displace` (the global
// model `WIND_MODEL`) from its `_WIND` channels and the instance's WindState. lighting.wgsl and
// wind.wgsl are prepended. The main pass fades each vertex into the aerial perspective's haze.

// #import lighting, wind, octa, material

// The wind for all trees, written every frame from the world's Wind component and the sim time.
@group(0) @binding(1) var<uniform> wind: WindParams;

// The global wind model (0 noise, 1 hierarchical), equal to `wind.model`: set per pipeline from
// its `PipelineKey` (src/render/gpu.rs), so that only the chosen model's code runs per vertex.
override WIND_MODEL: u32 = 1u;

@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var albedo_tex: texture_2d<f32>;
// The normal map (RGB) with the specular map's strength in A (src/render/trees/model.rs packs
// them, so one sample reads both).
@group(2) @binding(2) var normal_spec_tex: texture_2d<f32>;
@group(2) @binding(4) var material_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    @location(4) wind: vec4<f32>,
    // The instance (src/render/trees/instances.rs): the tree's origin (metres) and uniform scale,
    @location(5) origin: vec3<f32>,
    @location(6) scale: f32,
    // its yaw (radians), the trunk's lean (WindState.bend, metres per metre of height, world X
    // and Z) and the wind's gain at the tree (WindState.gain),
    @location(7) yaw: f32,
    @location(8) bend: vec2<f32>,
    @location(9) gain: f32,
    // its wind phase (WindState.phase, radians) and the share of its leaves kept (lod.rs).
    @location(10) phase: f32,
    @location(11) keep: f32,
    // xyz: the centre of the vertex's leaf (model space); w: the leaf's rank in 0..1, or -1 where
    // the primitive is not simplified.
    @location(12) leaf: vec4<f32>,
    // The share of the tree drawn as an impostor (impostor/mod.rs `fade`): alpha-clipped
    // fragments give up the dithered share `fade` of their pixels to the impostor, and opaque
    // parts (the trunk) give way at half the band.
    @location(13) fade: f32,
    // The vertex colour (COLOR_0, linear; white where the model has none), multiplying the base
    // colour.
    @location(14) color: vec4<f32>,
    // The share of the tree handed to its far model (instances.rs `far_share`): fragments whose
    // dither is at least 1 - handoff go to the far model, and opaque parts give way above half.
    @location(15) handoff: f32,
};

// The linear size of a leaf of rank `rank` on a tree that keeps the share `keep` of its leaves:
// the twin of lod::leaf_scale (see src/render/trees/lod.rs for the derivation).
fn leaf_scale(rank: f32, keep: f32) -> f32 {
    if (rank < 0.0 || keep >= 1.0) {
        return 1.0;
    }
    let weight = clamp((2.0 * keep - rank) / keep, 0.0, 1.0);
    let over = max(2.0 * keep - 1.0, 0.0);
    let kept = keep + (keep * keep - over * over) / (2.0 * keep);
    return sqrt(weight / kept);
}

struct VertexOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    @location(4) color: vec4<f32>,
    // The aerial perspective's haze colour (rgb) and its share (a) at the vertex (lighting.wgsl
    // `haze_at`), as the ground fades: a tree fades into the distance with the ground it stands on.
    @location(5) haze: vec4<f32>,
};

fn rotate_y(v: vec3<f32>, yaw: f32) -> vec3<f32> {
    let c = cos(yaw);
    let s = sin(yaw);
    return vec3<f32>(c * v.x + s * v.z, v.y, -s * v.x + c * v.z);
}

// The swayed world position: the rest position (scaled, turned by the yaw, moved to the tree's
// origin) displaced by the wind. The _WIND distances are model-space metres, so x, y and z are
// scaled with the tree; w (the branch phase) is not.
fn world_position(v: VertexIn) -> vec3<f32> {
    if (material.alpha_cutoff < 0.0 && (v.fade >= 0.5 || v.handoff > 0.5)) {
        // Every vertex at one point: the triangles have no area and draw nothing.
        return v.origin;
    }
    let scale = v.scale;
    let p = v.leaf.xyz + (v.position - v.leaf.xyz) * leaf_scale(v.leaf.w, v.keep);
    let v0 = v.origin + rotate_y(p * scale, v.yaw);
    let ch = vec4<f32>(v.wind.xyz * scale, v.wind.w);
    return wind_displace(WIND_MODEL, v0, ch, v.bend, v.gain, v.phase, wind);
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    let wp = world_position(v);
    out.clip = frame.view_proj * vec4<f32>(wp, 1.0);
    out.world_pos = wp;
    out.normal = rotate_y(v.normal, v.yaw);
    out.tangent = vec4<f32>(rotate_y(v.tangent.xyz, v.yaw), v.tangent.w);
    out.uv = v.uv;
    out.color = v.color;
    // Within HAZE_START (40 m) of the camera there is no haze, so the near trees, the most
    // vertices, skip its sky lookup.
    out.haze = vec4<f32>(0.0);
    let to = wp - frame.camera_pos;
    if (dot(to, to) > HAZE_START * HAZE_START) {
        out.haze = haze_at(wp);
    }
    return out;
}

// Shades a tree fragment. It never discards: alpha-clipped materials reach it only where their
// depth pre-pass (fs_alpha_test) kept the fragment, through an equal depth test.
@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Derivatives and texture samples first, in uniform control flow.
    let dpx = dpdx(in.world_pos);
    let dpy = dpdy(in.world_pos);
    // The albedo's texels are sRGB-encoded bytes in a linear format, decoded after filtering.
    let texel = textureSample(albedo_tex, material_sampler, in.uv);
    let base = vec4<f32>(srgb_decode(texel.rgb), texel.a) * material.base_color * in.color;
    let normal_spec = textureSample(normal_spec_tex, material_sampler, in.uv);
    let nt = normal_spec.xyz * 2.0 - 1.0;
    let spec_tex = normal_spec.a;
    let v = normalize(frame.camera_pos - in.world_pos);
    var n = normalize(in.normal);
    // The face normal from screen-space derivatives; tiny (sub-pixel) triangles can give a zero
    // cross product, in which case the vertex normal stands in, so no NaN reaches the shading.
    let cr = cross(dpx, dpy);
    var ng = select(n, cr * inverseSqrt(max(dot(cr, cr), 1e-30)), dot(cr, cr) > 1e-30);
    if (dot(ng, v) < 0.0) {
        ng = -ng;
    }
    let t0 = in.tangent.xyz - n * dot(n, in.tangent.xyz);
    let alt = cross(n, select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), abs(n.y) > 0.9));
    let t = select(normalize(alt), t0 * inverseSqrt(max(dot(t0, t0), 1e-30)), dot(t0, t0) > 1e-12);
    let b = cross(n, t) * in.tangent.w;
    let ns = vec3<f32>(nt.xy * material.normal_scale, max(nt.z, 0.05));
    n = normalize(t * ns.x + b * ns.y + n * ns.z);
    if (!front) {
        // Back face of a two-sided leaf: flip the component along the face normal (ng faces
        // the viewer), keeping the tangential part, so a leaf card shades like a leaf from
        // both sides.
        n = normalize(n - 2.0 * dot(n, ng) * ng);
    }
    let spec = spec_tex * material.specular_factor;
    let c = shade(base.rgb, n, in.world_pos, spec, material.roughness, material.translucency);
    return vec4<f32>(tone(mix(c, in.haze.rgb, in.haze.a)), 1.0);
}

struct DepthOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) fade: f32,
    @location(2) alpha: f32,
    @location(3) @interpolate(flat) handoff: f32,
};

// Depth only, for the shadow map (with the light's frame) and the alpha-clipped materials'
// depth pre-pass (with the camera's). The clip position is computed exactly as in vs_main.
@vertex
fn vs_depth(v: VertexIn) -> DepthOut {
    var out: DepthOut;
    out.clip = frame.view_proj * vec4<f32>(world_position(v), 1.0);
    out.uv = v.uv;
    out.fade = v.fade;
    out.handoff = v.handoff;
    out.alpha = v.color.a;
    return out;
}

// Alpha-tested leaves write no depth where they are clipped: in the shadow map this gives
// dappled shadows, in the pre-pass the holes through which farther leaves are seen.
@fragment
fn fs_alpha_test(in: DepthOut) {
    let a = textureSample(albedo_tex, material_sampler, in.uv).a * material.base_color.a * in.alpha;
    if (material.alpha_cutoff >= 0.0 && a < material.alpha_cutoff) {
        discard;
    }
    // The coarser levels' shares of the cross-fades: the impostor's (or, on a far model, the
    // model's) below `fade`, the far model's from 1 - handoff; each keeps the complementary
    // pixels.
    let d = impostor_dither(in.clip.xy);
    if (d < in.fade || d >= 1.0 - in.handoff) {
        discard;
    }
}
