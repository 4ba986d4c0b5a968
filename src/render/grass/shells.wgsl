// Shell grass (Fukuda et al. 2007): the patch's ground drawn `shells` times in one instanced
// draw, layer `instance_index` raised along the normal by its share of the grass height. A
// noise texture gives every texel (one strand) a height; a layer keeps the texels whose strand
// reaches it, more transparent towards the tip. Layers are drawn bottom to top, blended.
// lighting.wgsl is prepended (src/render/gpu.rs).
//
// Units: metres; +Y up.

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
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // The strand texture's coordinates: the position before the layer's sway.
    @location(2) strand_uv: vec2<f32>,
    @location(3) irr: vec3<f32>,
    @location(4) @interpolate(flat) layer: u32,
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
    out.world_pos = p;
    out.normal = v.normal;
    out.strand_uv = v.position.xz * params.strands.x / 128.0;
    out.irr = textureSampleLevel(irradiance_map, env_sampler, v.normal, 0.0).rgb;
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
    let n = normalize(in.normal);
    let c = shade_lit(albedo, n, in.world_pos, 0.05, 0.8, 0.4, in.irr);
    // More transparent towards the tip of each strand.
    let alpha = select(1.0, clamp(1.0 - 0.7 * h / max(strand, 1e-3), 0.25, 1.0), in.layer > 0u);
    return vec4<f32>(tone(aerial(c, in.world_pos)), alpha);
}
