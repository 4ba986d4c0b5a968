// Shell grass (Fukuda et al. 2007): the patch's ground seen through `shells` layers, layer `l`
// raised along the normal by its share of the grass height and swayed by the wind. A noise
// texture gives every texel (one strand) a height; a layer keeps the texels whose strand
// reaches it, more transparent towards the tip; the layers are blended bottom to top.
//
// The layers are not drawn one by one: each ground triangle is drawn once, where the bottom
// layer lies, and the fragment finds every layer along its view ray (see `fs_main`). A software
// rasteriser pays per fragment far more than per texture read, so one fragment that walks the
// layers costs a fraction of one fragment per layer.
//
// The light is evaluated per vertex (a patch's normal is its triangle's; the aerial
// perspective changes slowly), and few values cross to the fragment, which adds the strand's
// colour and, with shadows on, the trees' shadow, looked up once where the visible strands are. (Thinning
// the layers by the pixels each covers, per triangle or per fragment, was tried with layered
// draws: it darkened distant lawns, whose colour builds up over all their layers.)
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
    // The corner's distance to the lawn's edge over the fade band (grass/edges.rs), at most 1.
    @location(3) edge: f32,
};

// Shell layers fade out of sight with distance as the strands shrink below a pixel: all layers
// up to 25 m from the camera, then fewer, down to a quarter of them from 150 m on. A whole
// triangle keeps or drops a layer (by its nearest possible point), so no triangle is torn.
fn layers_at(d: f32, layers: f32) -> f32 {
    return layers * mix(1.0, 0.25, smoothstep(25.0, 150.0, d));
}

// What a ground triangle's corner passes to the fragment. Layer `l`'s surface is the triangle's
// plane moved by `layer_offset(l)`; the view ray through the bottom layer's point `q` meets it
// at `t = 1 + n·(offset(l) − offset(0)) / n·(q − eye)` of the way to `q`, and the strand there is
// the one under that point before the offset.
struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // The floor point (h = 0), metres.
    @location(0) floor_pos: vec3<f32>,
    // The triangle's normal (the same at its three corners).
    @location(1) normal: vec3<f32>,
    @location(2) ambient: vec3<f32>,
    @location(3) direct: vec3<f32>,
    @location(4) add: vec3<f32>,
    // The wind noise (as `vs_main` reads it per corner) and the triangle's nearest distance to
    // the eye (the same at its corners; it decides the layers kept, as in `vs_main`).
    @location(5) wind_noise: f32,
    @location(6) nearest: f32,
    @location(7) edge: f32,
};

// Layer `layer`'s displacement of the floor (vs_main's): along the normal by its share of the
// grass height, and along the wind by its sway (quadratic in the height).
fn layer_offset(n: vec3<f32>, sway_tip: f32, layer: u32) -> vec3<f32> {
    let hv = (f32(layer) + 0.5) / params.root.w;
    return n * (params.tip.w * hv) + vec3<f32>(params.wind.x, 0.0, params.wind.y) * (sway_tip * hv * hv);
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let wdir = params.wind.xy;
    let uv = v.position.xz * params.strands.y - wdir * params.wind.w * params.strands.z * params.strands.y;
    var out: VertexOut;
    out.floor_pos = v.position;
    out.normal = v.normal;
    out.edge = v.edge;
    out.wind_noise = textureSampleLevel(wind_tex, wind_sampler, uv, 0.0).r;
    // Drawn where the bottom layer lies, so that it has the layered draw's depth.
    let sway_tip = params.wind.z * (0.35 + 0.65 * out.wind_noise);
    out.clip = frame.view_proj * vec4<f32>(v.position + layer_offset(v.normal, sway_tip, 0u), 1.0);
    out.nearest = max(distance(v.triangle.xyz, frame.camera_pos) - v.triangle.w, 0.0);
    // The light as `vs_main` has it, at the floor.
    let p = v.position;
    let to_eye = frame.camera_pos - p;
    let dist = length(to_eye);
    let l = frame.sun_dir;
    let ndl = dot(v.normal, l);
    let hv = normalize(l + to_eye / max(dist, 1e-4));
    let irr = textureSampleLevel(irradiance_map, env_sampler, v.normal, 0.0).rgb;
    let spec = frame.sun_color * (0.05 * 0.25 * pow(max(dot(v.normal, hv), 0.0), 30.4) * select(0.0, 1.0, ndl > 0.0));
    let hz = haze_at(p);
    let f = hz.a;
    out.ambient = irr * frame.ambient * (1.0 - f);
    out.direct = frame.sun_color * (max(ndl, 0.0) + 0.4 * max(-ndl, 0.0)) * (1.0 - f);
    out.add = hz.rgb * f + spec * (1.0 - f);
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let layers = params.root.w;
    let kept = layers_at(in.nearest, layers);
    let n = in.normal;
    let sway_tip = params.wind.z * (0.35 + 0.65 * in.wind_noise);
    // The ray from the eye through the bottom layer's point.
    let bottom = layer_offset(n, sway_tip, 0u);
    let d = in.floor_pos + bottom - frame.camera_pos;
    let nd = dot(n, d);
    let scale = params.strands.x / 128.0;
    // The strand texture's footprint, from the floor's (the layers' differ little from it).
    let uv0 = in.floor_pos.xz * scale;
    let gx = dpdx(uv0);
    let gy = dpdy(uv0);
    // Front to back, from the highest layer kept: each layer adds its albedo times its alpha
    // times what the layers above it let through, which is the bottom-to-top blend's sum; the
    // bottom layer is opaque. Once less than 1/1024 gets through, the rest cannot change the
    // 8-bit result by more than a quarter of a step. The points where the ray meets the layers
    // are summed with the same weights: the trees' shadow is looked up once, at their mean,
    // where the visible strands are (a lookup at the floor would move the shadows of a low sun
    // by the grass height over its tangent). The layers are lit and toned after the sum, not
    // each (the tone curve is nearly straight over a lawn's colours).
    // Along the lawn's edge it turns transparent over the ground (border blend) and its
    // strands shorten to nothing (height falloff, more slowly: the short lawn's dark floor
    // would read as a dark rim).
    let cover = smoothstep(0.0, 1.0, in.edge);
    let grow = sqrt(cover);
    var albedo_sum = vec3<f32>(0.0);
    var at = vec3<f32>(0.0);
    var through = 1.0;
    let top = min(u32(layers) - 1u, u32(max(ceil(kept), 1.0)) - 1u);
    for (var layer = i32(top); layer >= 0; layer = layer - 1) {
        let l = u32(layer);
        let offset = layer_offset(n, sway_tip, l);
        // Where the ray meets the layer, and the floor point under it.
        let t = 1.0 + dot(n, offset - bottom) / min(nd, -1e-6);
        let hit = frame.camera_pos + d * t;
        let s = textureSampleGrad(strand_tex, nearest_sampler, (hit - offset).xz * scale, gx, gy).r;
        let strand = mix(params.strands.w, 1.0, s) * grow;
        let h = f32(l) / layers;
        let albedo = mix(params.root.rgb, params.tip.rgb, h) * mix(0.3, 0.7, h) * (0.8 + 0.4 * s);
        let alpha = select(clamp(1.0 - 0.7 * h / max(strand, 1e-3), 0.25, 1.0), 1.0, l == 0u);
        let w = select(0.0, alpha, l == 0u || strand >= h) * through;
        albedo_sum = albedo_sum + albedo * w;
        at = at + hit * w;
        through = through - w;
        if (through < 1.0 / 1024.0) {
            break;
        }
    }
    at = at / max(1.0 - through, 1e-6);
    let lit = shadow_factor(at + n * frame.shadow_normal_offset, vec3<f32>(0.0));
    let c = tone(albedo_sum * (in.ambient + in.direct * lit) + in.add);
    return vec4<f32>(c, cover);
}
