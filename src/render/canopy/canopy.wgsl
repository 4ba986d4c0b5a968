// The canopy: each photographed crown drawn as `layer_count` horizontal layers stacked between
// its base and top height, each a square around the tree's current position, textured from the
// summer photograph around the crown's photographed centre where the layer's own mask bit says
// treetop (the masks' k grows with height, so upper layers are smaller and the crown rounds off),
// with a slight texture shift per layer. Alpha-tested, lit by the sun, casting shadows (from the
// lowest layer, whose outline holds the others).
// lighting.wgsl and clipmap.wgsl are prepended (src/render/canopy/mod.rs).

// #import lighting, clipmap

struct CanopyParams {
    // The number of layers and the photographs' ground sample distance, metres.
    layer_count: f32,
    gsd_m: f32,
    // The angle one pixel of the main view spans, radians (2 tan(fov / 2) / height).
    pixel_angle: f32,
    pad0: f32,
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
    // The half-side of the layer's quad, metres (as far as its mask bits reach around the
    // crown, src/render/canopy/extents.rs), and padding.
    @location(2) extent_pad: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    // The photograph's ground point at this vertex (world X, Z).
    @location(1) photo: vec2<f32>,
    // The layer's index, and the mask's and the summer photograph's clipmap levels for the
    // whole crown (chosen per vertex, the same at its six).
    @location(2) @interpolate(flat) layer_levels: vec3<u32>,
    // The offset from the crown's centre in radii.
    @location(3) local: vec2<f32>,
};

// A little wider than the crown: the mask decides the outline.
const SPREAD: f32 = 1.25;

// The finest level of `c`, not finer than `min_level`, whose window holds the square of
// half-side `half` metres around ground point `p` (with a texel of margin for bilinear
// footprints); the coarsest level when none does.
fn crown_level(c: Clipmap, p: vec2<f32>, half: f32, min_level: u32) -> u32 {
    var chosen = c.levels - 1u;
    for (var li = c.levels - 1u; li + 1u > min_level; li = li - 1u) {
        let margin = half / c.level[li].texel_m + 1.0;
        let w = clipmap_window_pos(c, li, p);
        if (all(w >= vec2<f32>(margin)) && all(w <= vec2<f32>(c.size - margin))) {
            chosen = li;
        }
        if (li == 0u) {
            break;
        }
    }
    return chosen;
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32, l: LayerIn) -> VertexOut {
    let corner = array<vec2<f32>, 6>(vec2<f32>(-1.0, -1.0), vec2<f32>(-1.0, 1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(-1.0, 1.0), vec2<f32>(1.0, 1.0));
    let r = l.foot_radius.w * SPREAD;
    let layer = u32(l.photo_height_layer.w + 0.5);
    // The slight texture shift of each layer: a fraction of a texel per layer, along a diagonal.
    let shift = vec2<f32>(0.35, 0.2) * params.gsd_m * f32(layer);
    let centre = vec3<f32>(l.foot_radius.x, l.foot_radius.y + l.photo_height_layer.z, l.foot_radius.z);
    // The ground a pixel spans at the crown's centre, stretched as the view grazes the layer
    // (as the screen derivatives of a fragment would give), picks the finest level worth
    // reading: for the whole crown, so each fragment reads one level.
    let to = centre - frame.camera_pos;
    let dist = length(to);
    let footprint = dist * params.pixel_angle / max(abs(to.y) / max(dist, 1e-6), 0.25);
    let photo_centre = l.photo_height_layer.xy + shift;
    let mask_min = min(u32(floor(log2(max(footprint / masks.level[0].texel_m, 1.0)))), masks.levels - 1u);
    let summer_min = min(u32(floor(log2(max(footprint / summer.level[0].texel_m, 1.0)))), summer.levels - 1u);
    let mask_level = crown_level(masks, photo_centre, r, mask_min);
    // The quad reaches as far as the layer's bits, and a texel of the level read further: a
    // coarser level's texel may reach beyond the finest texels' extent.
    let half = min(l.extent_pad.x + masks.level[mask_level].texel_m, r);
    let d = corner[i] * half;
    var out: VertexOut;
    out.world_pos = centre + vec3<f32>(d.x, 0.0, d.y);
    out.clip = frame.view_proj * vec4<f32>(out.world_pos, 1.0);
    out.photo = photo_centre + d;
    out.layer_levels = vec3<u32>(layer, mask_level, crown_level(summer, photo_centre, r, summer_min));
    out.local = d / max(l.foot_radius.w, 1e-6);
    return out;
}

// Whether this layer is treetop at the fragment: its bit in the layer mask at the crown's
// level (one nearest texel), within the crown's square (the photograph of a neighbouring crown
// is not drawn on a moved tree).
fn layer_mask(in: VertexOut) -> bool {
    let level = in.layer_levels.y;
    let uv = ((in.photo - masks.photo_origin) / masks.level[level].texel_m) / masks.size;
    let m = textureSampleLevel(masks_tex, masks_sampler, uv, i32(level), 0.0);
    let bits = u32(m.r * 255.0 + 0.5);
    let inside = max(abs(in.local.x), abs(in.local.y)) < 1.2;
    return m.a > 0.5 && ((bits >> in.layer_levels.x) & 1u) == 1u && inside;
}

// Alpha-tested shading where the layer is treetop. The layers come nearest crown first and
// each crown's top layer first, so fragments behind or below fail the depth test before this
// runs. Where the summer photograph has not arrived yet at the crown's level, a coarser level
// shows.
@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    if (!layer_mask(in)) {
        discard;
    }
    let t = clipmap_sample(summer_tex, summer_sampler, summer, in.photo, in.layer_levels.z);
    // Lower layers a little darker (less sky reaches inside the crown), and a normal leaning
    // outwards from the centre so the crown reads as rounded.
    let depth = (f32(in.layer_levels.x) + 1.0) / max(params.layer_count, 1.0);
    let albedo = pow(t.rgb, vec3<f32>(2.2)) * (0.7 + 0.3 * depth);
    let n = normalize(vec3<f32>(in.local.x * 0.5, 1.0, in.local.y * 0.5));
    let irr = textureSampleLevel(irradiance_map, env_sampler, n, 0.0).rgb;
    let c = shade_lit(albedo, n, in.world_pos, 0.05, 0.9, 0.35, irr);
    return vec4<f32>(tone(aerial(c, in.world_pos)), 1.0);
}

// The shadow pass (the lowest layer only, src/render/canopy/mod.rs): depth where it is treetop.
@fragment
fn fs_depth(in: VertexOut) {
    if (!layer_mask(in)) {
        discard;
    }
}
