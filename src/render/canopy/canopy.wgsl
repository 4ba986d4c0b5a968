// The canopy: each photographed crown drawn as `layer_count` horizontal layers stacked between
// its base and top height, each a square around the tree's current position, textured from the
// summer photograph around the crown's photographed centre where the layer's own mask bit says
// treetop (the masks' k grows with height, so upper layers are smaller and the crown rounds off),
// with a slight texture shift per layer. Alpha-tested, lit by the sun, casting shadows (from the
// lowest layer, whose outline holds the others).
// lighting.wgsl and clipmap.wgsl are prepended (src/render/canopy/mod.rs).

struct CanopyParams {
    // The number of layers and the photographs' ground sample distance, metres.
    layer_count: f32,
    gsd_m: f32,
    pad0: f32,
    pad1: f32,
};

@group(2) @binding(0) var<uniform> summer: Clipmap;
@group(2) @binding(1) var summer_tex: texture_2d_array<f32>;
@group(2) @binding(2) var summer_sampler: sampler;
@group(2) @binding(3) var<uniform> params: CanopyParams;
// The layer masks in a group of their own: lavapipe (Mesa 22/23) crashed sampling a second
// texture array of the same group.
@group(3) @binding(0) var<uniform> masks: Clipmap;
@group(3) @binding(1) var masks_tex: texture_2d_array<f32>;
@group(3) @binding(2) var masks_sampler: sampler;

struct LayerIn {
    // The tree's foot (world, metres) and the crown's radius.
    @location(0) foot_radius: vec4<f32>,
    // The crown's photographed centre (world X, Z), the layer's height over the foot and the
    // layer's index.
    @location(1) photo_height_layer: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    // The photograph's ground point at this vertex (world X, Z).
    @location(1) photo: vec2<f32>,
    // The offset from the crown's centre in radii, and the layer's index.
    @location(2) @interpolate(flat) layer: u32,
    @location(3) local: vec2<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) i: u32, l: LayerIn) -> VertexOut {
    let corner = array<vec2<f32>, 6>(vec2<f32>(-1.0, -1.0), vec2<f32>(-1.0, 1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(-1.0, 1.0), vec2<f32>(1.0, 1.0));
    // A little wider than the crown: the mask decides the outline.
    let r = l.foot_radius.w * 1.25;
    let d = corner[i] * r;
    let layer = u32(l.photo_height_layer.w + 0.5);
    // The slight texture shift of each layer: a fraction of a texel per layer, along a diagonal.
    let shift = vec2<f32>(0.35, 0.2) * params.gsd_m * f32(layer);
    var out: VertexOut;
    out.world_pos = vec3<f32>(l.foot_radius.x + d.x, l.foot_radius.y + l.photo_height_layer.z, l.foot_radius.z + d.y);
    out.clip = frame.view_proj * vec4<f32>(out.world_pos, 1.0);
    out.photo = l.photo_height_layer.xy + d + shift;
    out.layer = layer;
    out.local = corner[i] * 1.25;
    return out;
}

// Whether this layer is treetop at the fragment: its bit in the layer mask, within the crown's
// square (the photograph of a neighbouring crown is not drawn on a moved tree).
fn layer_mask(in: VertexOut, min_level: u32) -> bool {
    let m = clipmap_load(masks_tex, masks_sampler, masks, in.photo, min_level);
    let bits = u32(m.r * 255.0 + 0.5);
    let inside = max(abs(in.local.x), abs(in.local.y)) < 1.2;
    return m.a > 0.5 && ((bits >> in.layer) & 1u) == 1u && inside;
}

// The main view's depth pre-pass: depth where the layer is treetop and the photograph loaded,
// so the shading below runs once per pixel however many layers overlap there.
@fragment
fn fs_prepass(in: VertexOut) {
    let min_level = clipmap_min_level(masks, in.photo);
    if (!layer_mask(in, min_level)) {
        discard;
    }
    let t = clipmap_sample(summer_tex, summer_sampler, summer, in.photo, min_level);
    if (t.a < 0.5) {
        discard;
    }
}

// Shading at equal depth after the pre-pass: only the nearest treetop layer of each pixel.
@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let min_level = clipmap_min_level(masks, in.photo);
    let t = clipmap_sample(summer_tex, summer_sampler, summer, in.photo, min_level);
    // Lower layers a little darker (less sky reaches inside the crown), and a normal leaning
    // outwards from the centre so the crown reads as rounded.
    let depth = (f32(in.layer) + 1.0) / max(params.layer_count, 1.0);
    let albedo = pow(t.rgb, vec3<f32>(2.2)) * (0.7 + 0.3 * depth);
    let n = normalize(vec3<f32>(in.local.x * 0.5, 1.0, in.local.y * 0.5));
    let irr = textureSampleLevel(irradiance_map, env_sampler, n, 0.0).rgb;
    let c = shade_lit(albedo, n, in.world_pos, 0.05, 0.9, 0.35, irr);
    return vec4<f32>(tone(aerial(c, in.world_pos)), 1.0);
}

// The shadow pass (the lowest layer only, src/render/canopy/mod.rs): depth where it is treetop.
@fragment
fn fs_depth(in: VertexOut) {
    if (!layer_mask(in, 0u)) {
        discard;
    }
}
