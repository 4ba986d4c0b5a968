// The GPU half of a clipmap (src/render/clipmap/gpu.rs): sampling a texture array of `levels`
// toroidal layers at a ground point. Prepended, after lighting.wgsl, to the shaders that read
// aerial photographs (the aerial ground, the canopy). Textures and samplers are passed as
// arguments, so one shader can read several clipmaps (the summer photograph and the layer masks).

struct ClipLevel {
    // The window's top-left texel in its mip's texel coordinates (x, y), the mip's texel size
    // in metres, and the mip number.
    origin_x: f32,
    origin_y: f32,
    texel_m: f32,
    mip: f32,
};

struct Clipmap {
    // World (X, Z) of the photograph's top-left corner, metres.
    photo_origin: vec2<f32>,
    // Texels per level side, and the number of levels.
    size: f32,
    levels: u32,
    // 1 colours the levels (`--debug-lod`), 0 shows the photograph.
    debug_lod: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    level: array<ClipLevel, 16>,
};

// The colours of the levels in `--debug-lod` (after the source's Fig. 2: one hue per level,
// finest red through yellow, green, cyan, blue and magenta, then again darker).
fn clipmap_level_colour(i: u32) -> vec3<f32> {
    let hues = array<vec3<f32>, 8>(
        vec3<f32>(1.0, 0.1, 0.1), vec3<f32>(1.0, 0.85, 0.1), vec3<f32>(0.2, 0.9, 0.2), vec3<f32>(0.1, 0.9, 0.9),
        vec3<f32>(0.15, 0.3, 1.0), vec3<f32>(0.9, 0.2, 0.9), vec3<f32>(1.0, 0.55, 0.1), vec3<f32>(0.6, 0.6, 0.6));
    return hues[i % 8u] * select(1.0, 0.6, i >= 8u);
}

// The position of ground point `p` (world X, Z) in level `i`'s window, texels from its corner.
fn clipmap_window_pos(c: Clipmap, i: u32, p: vec2<f32>) -> vec2<f32> {
    let l = c.level[i];
    return (p - c.photo_origin) / l.texel_m - vec2<f32>(l.origin_x, l.origin_y);
}

// The photograph at ground point `p`: the finest level, not finer than `min_level`, whose window
// holds `p` (with a texel of margin for the bilinear footprint) and whose texel there is loaded
// (alpha 1), else the next coarser one; transparent where no level has it. The repeating sampler
// does the toroidal addressing: the texel of mip coordinates (u, v) lies at (u mod n, v mod n).
// With `debug_lod` the result is tinted with the level's colour.
fn clipmap_sample(t: texture_2d_array<f32>, s: sampler, c: Clipmap, p: vec2<f32>, min_level: u32) -> vec4<f32> {
    var out = vec4<f32>(0.0);
    var chosen = 99u;
    // Finest first, stopping at the first loaded texel: usually one sample.
    for (var li = min_level; li < c.levels; li = li + 1u) {
        let w = clipmap_window_pos(c, li, p);
        if (all(w >= vec2<f32>(1.0)) && all(w <= vec2<f32>(c.size - 1.0))) {
            let l = c.level[li];
            let uv = ((p - c.photo_origin) / l.texel_m) / c.size;
            let v = textureSampleLevel(t, s, uv, i32(li), 0.0);
            if (v.a > 0.995) {
                out = v;
                chosen = li;
                break;
            }
        }
    }
    if (c.debug_lod != 0u && chosen < 99u) {
        let lum = dot(out.rgb, vec3<f32>(0.3, 0.6, 0.1));
        out = vec4<f32>(clipmap_level_colour(chosen) * (0.35 + 0.65 * lum), out.a);
    }
    return out;
}

// The texel at ground point `p` through `s`, a nearest (unfiltered) repeating sampler, from the
// finest level not finer than `min_level` that holds it loaded: for data that must not be
// blended, such as the canopy's layer masks. Transparent where no level has it.
fn clipmap_load(t: texture_2d_array<f32>, s: sampler, c: Clipmap, p: vec2<f32>, min_level: u32) -> vec4<f32> {
    var out = vec4<f32>(0.0);
    for (var li = min_level; li < c.levels; li = li + 1u) {
        let w = clipmap_window_pos(c, li, p);
        if (all(w >= vec2<f32>(0.0)) && all(w < vec2<f32>(c.size))) {
            let l = c.level[li];
            let uv = ((p - c.photo_origin) / l.texel_m) / c.size;
            let v = textureSampleLevel(t, s, uv, i32(li), 0.0);
            if (v.a > 0.5) {
                out = v;
                break;
            }
        }
    }
    return out;
}

// The finest level worth sampling at a fragment whose ground point is `p`: the level whose
// texels are about as large as the fragment's footprint on the ground (from the screen-space
// derivatives; call it in uniform control flow).
fn clipmap_min_level(c: Clipmap, p: vec2<f32>) -> u32 {
    let footprint = max(length(dpdx(p)), length(dpdy(p)));
    let lod = log2(max(footprint / c.level[0].texel_m, 1.0));
    return min(u32(floor(lod)), c.levels - 1u);
}
