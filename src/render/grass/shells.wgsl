// Shell grass (Fukuda et al. 2007): the patch's ground drawn `shells` times in one instanced
// draw, layer `instance_index` raised along the normal by its share of the grass height. A
// noise texture gives every texel (one strand) a height; a layer keeps the texels whose strand
// reaches it, more transparent towards the tip. Layers are drawn bottom to top, blended.
// lighting.wgsl is prepended (src/render/gpu.rs).
//
// The light is evaluated per vertex (a patch's normal is its triangle's; the aerial
// perspective changes slowly), and few values cross to the fragment, which adds the strand's
// colour and, with shadows on, the trees' shadow. (Thinning the layers by the pixels each
// covers, per triangle or per fragment, was tried: it darkened distant lawns, whose colour
// builds up over all their layers, and a discarded fragment still costs lavapipe its
// rasterisation.)
//
// Units: metres; +Y up.

// #import lighting

struct ShellParams {
    // The root colour (rgb) and the number of layers (w).
    root: vec4<f32>,
    // The tip colour (rgb) and the grass height, metres (w).
    tip: vec4<f32>,
    // The wind: direction (x, z), the sway at the tip (metres), the time (seconds).
    wind: vec4<f32>,
    // Strands per metre along each axis, the wind noise's scale (per metre) and scroll speed
    // (m/s), and the shortest strand as a share of the height.
    strands: vec4<f32>,
};

@group(2) @binding(0) var<uniform> params: ShellParams;
@group(2) @binding(1) var strand_tex: texture_2d<f32>;
@group(2) @binding(2) var wind_tex: texture_2d<f32>;
@group(2) @binding(3) var nearest_sampler: sampler;
@group(2) @binding(4) var wind_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // The triangle's centre (xyz) and radius (w), metres: the same for its three corners.
    @location(2) triangle: vec4<f32>,
};

// Shell layers fade out of sight with distance as the strands shrink below a pixel: all layers
// up to 25 m from the camera, then fewer, down to a quarter of them from 150 m on. A whole
// triangle keeps or drops a layer (by its nearest possible point), so no triangle is torn.
fn layers_at(d: f32, layers: f32) -> f32 {
    return layers * mix(1.0, 0.25, smoothstep(25.0, 150.0, d));
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // The point where the shadow map is looked up (pushed along the normal, lighting.wgsl's
    // `shadow_factor`), metres.
    @location(0) shadow_pos: vec3<f32>,
    // The strand texture's coordinates (the position before the layer's sway).
    @location(1) strand_uv: vec2<f32>,
    // The sky's light and the sun's (without its shadow) for an albedo of one, each already
    // faded by the aerial perspective, and what the fragment adds to them: the haze and the
    // sun's highlight. Linear RGB. Few values cross to the fragment, as each costs an
    // interpolation per pixel and per layer.
    @location(2) ambient: vec3<f32>,
    @location(3) direct: vec3<f32>,
    @location(4) add: vec3<f32>,
    @location(5) @interpolate(flat) layer: u32,
};

@vertex
fn vs_main(v: VertexIn, @builtin(instance_index) layer: u32) -> VertexOut {
    let layers = params.root.w;
    let h = (f32(layer) + 0.5) / layers;
    let wdir = params.wind.xy;
    let uv = v.position.xz * params.strands.y - wdir * params.wind.w * params.strands.z * params.strands.y;
    let n = textureSampleLevel(wind_tex, wind_sampler, uv, 0.0).r;
    // Higher layers sway further with the wind (quadratically, as a bending strand).
    let sway = params.wind.z * (0.35 + 0.65 * n) * h * h;
    let p = v.position + v.normal * (params.tip.w * h) + vec3<f32>(wdir.x, 0.0, wdir.y) * sway;
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(p, 1.0);
    let nearest = max(distance(v.triangle.xyz, frame.camera_pos) - v.triangle.w, 0.0);
    if (layer > 0u && f32(layer) >= layers_at(nearest, layers)) {
        // A layer this triangle does not need at its distance: all three corners collapse
        // onto one point outside the view, so the triangle is dropped.
        out.clip = vec4<f32>(0.0, 0.0, -1.0, 1.0);
    }
    let to_eye = frame.camera_pos - p;
    let dist = length(to_eye);
    out.shadow_pos = p + v.normal * frame.shadow_normal_offset;
    out.strand_uv = v.position.xz * params.strands.x / 128.0;
    // `shade_lit` (lighting.wgsl) with specular 0.05, roughness 0.8 and translucency 0.4, for
    // an albedo of one, without the shadow; no reflection (too rough to show one).
    let l = frame.sun_dir;
    let ndl = dot(v.normal, l);
    let hv = normalize(l + to_eye / max(dist, 1e-4));
    let irr = textureSampleLevel(irradiance_map, env_sampler, v.normal, 0.0).rgb;
    let spec = frame.sun_color * (0.05 * 0.25 * pow(max(dot(v.normal, hv), 0.0), 30.4) * select(0.0, 1.0, ndl > 0.0));
    // lighting.wgsl's `aerial`, per vertex: the haze and its share `f`.
    let hz = haze_at(p);
    let haze = hz.rgb;
    let f = hz.a;
    out.ambient = irr * frame.ambient * (1.0 - f);
    out.direct = frame.sun_color * (max(ndl, 0.0) + 0.4 * max(-ndl, 0.0)) * (1.0 - f);
    out.add = haze * f + spec * (1.0 - f);
    out.layer = layer;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let layers = params.root.w;
    let h = f32(in.layer) / layers;
    // The strand's height as a share of the grass height.
    let s = textureSample(strand_tex, nearest_sampler, in.strand_uv).r;
    let strand = mix(params.strands.w, 1.0, s);
    // The bottom layer is the lawn's floor; above it only the strands that reach the layer.
    if (in.layer > 0u && strand < h) {
        discard;
    }
    // A dense lawn shades itself: darker towards the floor, and less bright than a bare
    // surface even at the top (the strands shade each other).
    let albedo = mix(params.root.rgb, params.tip.rgb, h) * mix(0.3, 0.7, h) * (0.8 + 0.4 * s);
    // The shadow map, looked up where the vertex shader already pushed the point along the
    // normal.
    let lit = shadow_factor(in.shadow_pos, vec3<f32>(0.0));
    let c = albedo * (in.ambient + in.direct * lit) + in.add;
    // More transparent towards the tip of each strand.
    let alpha = select(1.0, clamp(1.0 - 0.7 * h / max(strand, 1e-3), 0.25, 1.0), in.layer > 0u);
    return vec4<f32>(tone(c), alpha);
}
