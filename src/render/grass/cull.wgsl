// Grass blades, compute stage: one invocation per blade of the scene. A blade whose bounding
// sphere lies outside the view frustum or beyond the far distance is dropped. For every other
// blade this pass does all the per-blade work of the frame once: the wind (a rotation towards
// the wind's direction whose angle comes from a world-space noise texture scrolled along the
// wind, so neighbouring blades move together), the pushes away from the eye and the controller's
// hit point, and the gravity bend, giving the blade's final shape (a quadratic Bézier curve
// through its root, middle and tip). By the level of detail its distance calls for, a near
// (7 segments) or middle (3) blade writes its shape into `shapes` and its index into its
// block's near or middle list; a second stage (`cs_order`) joins the blocks' lists in the
// frame's order of the blocks, so that the blades are drawn in the same order every frame
// whatever order the invocations ran in (two blades at the same depth in a pixel leave the
// one drawn first), and writes the index counts of two indexed indirect draws (blades.wgsl).
// A far blade, narrower than a pixel, is rasterised here: its curve is walked one pixel at a time
// and each pixel it covers keeps, in an image after the draw counts in `args`, the nearest blade's depth and colour (an atomic
// maximum, so the result does not depend on the order the invocations run in); the main pass
// puts that image over the ground with a rectangle around the far blades' pixels that tests
// and writes depth (blades.wgsl, `fs_far`). A workgroup culls a block of blades that the CPU
// found in view; blocks whose every blade is far go to a pipeline without the near and middle
// code (`FAR_ONLY`, src/render/grass/blocks.rs). A software rasteriser such as lavapipe pays a
// fixed price per primitive it sets up, which thousands of sub-pixel blades made the frame's
// largest cost.
// No lighting is prepended: this module has its own group 0 (src/render/grass/mod.rs).
//
// Reads: the blades, the wind noise, the patch colours, the view. Writes: `shapes`, `lists`,
// `args` (the draw counts, the far blades' count, box and image).
//
// Units: metres, radians, seconds; +Y up; pixels from the image's top left corner.

// #import grass_constants, grass_shapes

struct Blade {
    // The root, metres.
    position: vec3<f32>,
    // The blade's length, metres.
    height: f32,
    // Facing, radians about +Y; gravity bend, radians; root width, metres.
    yaw: f32,
    bend: f32,
    width: f32,
    // Bits 0..7 the patch index, bits 8..31 a random fraction.
    packed: u32,
};


struct Cull {
    // The six frustum planes (xyz normal pointing inwards, w offset), normalised.
    planes: array<vec4<f32>, 6>,
    // The camera's position, metres, and the far distance beyond which no blade is drawn.
    camera: vec4<f32>,
    // Blades nearer than `lod_near` metres get 7 segments, nearer than `lod_mid` 3, the others
    // a line.
    lod_near: f32,
    lod_mid: f32,
    // The number of blades; where the far pipeline's blocks begin in the list of blocks.
    count: u32,
    far_base: u32,
    // The wind: direction (x, z), the bend it gives (radians at the tip), the time, seconds.
    wind: vec4<f32>,
    // The scroll speed of the wind noise (m/s), its scale (per metre), unused, unused.
    wind_noise: vec4<f32>,
    // The eye, metres, and the radius within which blades bend away from it.
    eye: vec4<f32>,
    // The controller's hit point, metres, and its radius (0: no hit point).
    hit: vec4<f32>,
    // World to clip space of the main view (wgpu's depth 0..1).
    view_proj: mat4x4<f32>,
};


@group(0) @binding(0) var<uniform> cull: Cull;
@group(0) @binding(1) var<storage, read> blades: array<Blade>;
@group(0) @binding(2) var<storage, read_write> shapes: array<Shape>;
// The near and middle lists of blade indices, `count` entries each, then this frame's blocks
// (src/render/grass/blocks.rs): those of the general pipeline, then from `far_base` on those of
// the far pipeline, one block of BLOCK_BLADES (BLADES_PER_INVOCATION × CULL_WORKGROUP) blades a
// workgroup, `blocks()` words in all. Then, for the general pipeline's blocks in the frame's
// order: each block's numbers of near and middle blades (`counts_at()`, one word a block: near
// in the low half, middle in the high half), and each block's own lists (`own_at()`,
// BLOCK_BLADES words a block: its near blades from the front, its middle blades from the back,
// each in the order of their indices), which `cs_order` joins.
@group(0) @binding(3) var<storage, read_write> lists: array<u32>;
// Two indexed indirect draws (index count, instance count 1, first index, base vertex, first
// instance) for the near and middle blades, then the number of far blades rasterised here and
// the box of pixels they cover (smallest x, y, then largest x, y, whole pixels). The
// frame resets the counts before this pass; `cs_order` writes the draws' index counts, and each
// far blade adds one to theirs. The base vertex of the middle draw points at its list (`count` times its vertices a
// blade), so that vertex / vertices a blade is the index into `lists`.
//
// From word RASTER_OFFSET on, the same buffer holds the far blades' image, one word a pixel,
// row by row from the top: 0 where no far blade covers the pixel, else `pack_far` of the
// nearest one's depth and colour. The frame clears it before this pass. (One buffer for both:
// a compute stage may bind only four storage buffers on downlevel devices.)
@group(0) @binding(4) var<storage, read_write> args: array<atomic<u32>>;
@group(0) @binding(5) var wind_tex: texture_2d<f32>;
@group(0) @binding(6) var wind_sampler: sampler;
@group(0) @binding(7) var<uniform> params: BladeParams;
// The sky's irradiance (lighting.wgsl's `irradiance_map`), sampled with `wind_sampler`.
@group(0) @binding(8) var irradiance_map: texture_cube<f32>;

// NEAR_INDICES, MID_INDICES (the indices of a blade at the near and middle levels of detail),
// NEAR_CAP and MID_CAP (the most blades their index buffers hold; blades beyond them drop a
// level), RASTER_OFFSET, CULL_WORKGROUP and BLADES_PER_INVOCATION are written from Rust's
// constants ahead of this file (`shader_constants` in src/render/grass/data.rs).
// The segments a near or middle blade's curve is integrated over before it is fitted, and a
// far blade's, whose curve is under ten pixels long (even).
const STEPS: u32 = 8u;
const FAR_STEPS: u32 = 2u;
// The most pixels a far blade's curve is walked in (a far blade is under ten pixels long).
const MAX_FAR_PIXELS: u32 = 64u;
// The box of pixels of no far blade (x, y of its smallest, then of its largest corner).
const NO_BOX: vec4<f32> = vec4<f32>(1e9, 1e9, -1e9, -1e9);
// A word of `args` that no one reads, for the far blades' samples outside the image.
const SCRATCH_WORD: u32 = 15u;
// The far blades' image begins at word RASTER_OFFSET of `args` (from Rust, see above).
// The depth codes of an image word (its top 11 bits; the colour takes the 21 below them, 7 a
// channel).
const DEPTH_LEVELS: u32 = 2047u;
// The linear colour that `tone` (lighting.wgsl) maps to white: an image word's colours span
// 0 … TONE_WHITE.
const TONE_WHITE: f32 = 1.0 / 0.85;
// The blades of a block, one workgroup of `cs_cull`.
const BLOCK_BLADES: u32 = CULL_WORKGROUP * BLADES_PER_INVOCATION;

// The number of blocks of the scene's blades (the last may be shorter), and where the blocks'
// counts and own lists begin in `lists` (see its declaration).
fn blocks() -> u32 {
    return (cull.count + BLOCK_BLADES - 1u) / BLOCK_BLADES;
}
fn counts_at() -> u32 {
    return 2u * cull.count + blocks();
}
fn own_at() -> u32 {
    return 2u * cull.count + 2u * blocks();
}

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

// A far blade's albedo at `t` along it (0 at the root, 1 at the tip) as blades.wgsl's
// `blade_vertex` gives a blade's: the patch's root and tip colours, darker near the root, and
// the blade's variation; 0.7 of it, since a far blade covers whole pixels where its width
// would cover a part of each, so that a far lawn keeps the tone of its near part.
fn far_albedo(patch_index: u32, variation: f32, t: f32) -> vec3<f32> {
    let c = mix(params.colours[2u * patch_index].rgb, params.colours[2u * patch_index + 1u].rgb, t);
    return c * mix(0.55, 1.0, t) * (0.8 + 0.4 * variation) * 0.7;
}

// The sky's light on far blades near `p` (metres): the irradiance of the sky, times the ambient
// strength, on a face turned to the eye and tilted up as a bent blade's face is on average
// (`fs_far` in blades.wgsl takes the same face for the trees' shadows). It changes slowly
// across a lawn, so an invocation looks it up once for all its blades.
fn far_sky(p: vec3<f32>) -> vec3<f32> {
    let v = normalize(cull.camera.xyz - p);
    let n = normalize(vec3<f32>(v.x, 0.0, v.z) + vec3<f32>(1e-4, 0.4, 0.0));
    return textureSampleLevel(irradiance_map, wind_sampler, n, 0.0).rgb * params.ambient.rgb;
}

// The light on a far blade: its colour is `albedo * gain + highlight` (linear RGB).
struct FarLight {
    gain: vec3<f32>,
    highlight: vec3<f32>,
};

// The light on a far blade under the sky's light `sky` and the sun, by the shading model of
// blades.wgsl (specular 0.15, roughness 0.55, translucency 0.6) on its own face: the normal of
// its root-to-tip chord across its width (`across`), turned to the eye at `p`, its middle.
fn far_light(p: vec3<f32>, chord: vec3<f32>, across: vec3<f32>, sky: vec3<f32>) -> FarLight {
    let v = normalize(cull.camera.xyz - p);
    var n = normalize(cross(across, chord) + vec3<f32>(0.0, 1e-6, 0.0));
    n = select(n, -n, dot(n, v) < 0.0);
    let l = params.sun_dir.xyz;
    let ndl = dot(n, l);
    let diffuse = max(ndl, 0.0) + 0.6 * max(-ndl, 0.0);
    let h = normalize(l + v);
    // The highlight's power 60.9 taken as 64, six squarings (a power is an exponential and a
    // logarithm in lavapipe).
    var s = max(dot(n, h), 0.0);
    s = s * s;
    s = s * s;
    s = s * s;
    s = s * s;
    s = s * s;
    s = s * s;
    let spec = 0.15 * 0.25 * s * select(0.0, 1.0, ndl > 0.0);
    var out: FarLight;
    out.gain = sky + params.sun_color.rgb * diffuse;
    out.highlight = params.sun_color.rgb * spec;
    return out;
}

// A lit colour (linear RGB) as an image word stores it: each channel's square root of its share
// of TONE_WHITE, 0 … 127 (the eye sees dark greens in finer steps than bright ones; a square
// root is one instruction, where a cube root is a power, which costs lavapipe an exponential
// and a logarithm a channel).
fn encode_far(colour: vec3<f32>) -> vec3<f32> {
    return sqrt(clamp(colour / TONE_WHITE, vec3<f32>(0.0), vec3<f32>(1.0))) * 127.0;
}

// A word of the far blades' image: the depth code of view depth `w` (metres; nearer is larger,
// never 0) above the encoded colour `e` (`encode_far`), seven bits a channel.
fn pack_far(w: f32, e: vec3<f32>) -> u32 {
    let d = min(u32(max(w, 0.0) / params.viewport.z * f32(DEPTH_LEVELS)), DEPTH_LEVELS - 1u);
    let c = vec3<u32>(round(e));
    return ((DEPTH_LEVELS - d) << 21u) | (c.r << 14u) | (c.g << 7u) | c.b;
}

// Rasterises a far blade, the quadratic Bézier curve through `p0`, `p1`, `p2` (world metres;
// the root, the control point and the tip) with its width along `across`, under the sky's
// light `sky`: the curve is projected (a projective map keeps a Bézier curve one, with the
// projected control points) and sampled about once a pixel, and every sample inside the
// image keeps the nearer of its blade and what its pixel holds. The colour is lit and encoded
// at the root and the tip and interpolated between them. Returns the box of pixels the blade
// may cover (its control polygon's), or `NO_BOX` for a blade too near to draw or not to be
// drawn (`draw` false).
//
// lavapipe pays dearly for control flow (every assignment under a condition becomes a masked
// store), so the blade's work is straight-line code; only the walk is a loop, of no pass for a
// blade not drawn.
fn rasterise_far(draw: bool, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, across: vec3<f32>, patch_index: u32, variation: f32, sky: vec3<f32>) -> vec4<f32> {
    let light = far_light(0.5 * (p0 + p2), p2 - p0, across, sky);
    let e0 = encode_far(far_albedo(patch_index, variation, 0.0) * light.gain + light.highlight);
    let e1 = encode_far(far_albedo(patch_index, variation, 1.0) * light.gain + light.highlight);
    let c0 = cull.view_proj * vec4<f32>(p0, 1.0);
    let c1 = cull.view_proj * vec4<f32>(p1, 1.0);
    let c2 = cull.view_proj * vec4<f32>(p2, 1.0);
    // A far blade lies well in front of the near plane; one that does not is left out.
    let ok = draw && min(c0.w, min(c1.w, c2.w)) >= 0.1;
    let size = params.viewport.xy;
    let half = vec2<f32>(0.5 * size.x, -0.5 * size.y);
    let s0 = c0.xy / c0.w * half;
    let s1 = c1.xy / c1.w * half;
    let s2 = c2.xy / c2.w * half;
    // The curve's length lies between its chord's and its control polygon's; their mean is
    // within a few per cent of it for a blade's gentle bend: samples about a pixel apart.
    let n = clamp(u32(ceil(0.5 * (distance(s0, s1) + distance(s1, s2) + distance(s0, s2)))), 1u, MAX_FAR_PIXELS);
    let samples = select(0u, n + 1u, ok);
    let width = u32(size.x);
    for (var k = 0u; k < samples; k = k + 1u) {
        let t = f32(k) / f32(n);
        let u = 1.0 - t;
        let c = c0 * (u * u) + c1 * (2.0 * t * u) + c2 * (t * t);
        let px = (c.xy / c.w * vec2<f32>(0.5, -0.5) + 0.5) * size;
        // A sample outside the image goes to a word nobody reads.
        let in_image = all(px >= vec2<f32>(0.0)) && all(px < size);
        let q = vec2<u32>(clamp(px, vec2<f32>(0.0), size - 1.0));
        let index = select(SCRATCH_WORD, RASTER_OFFSET + q.y * width + q.x, in_image);
        atomicMax(&args[index], pack_far(c.w, mix(e0, e1, t)));
    }
    return select(NO_BOX, vec4<f32>(min(s0, min(s1, s2)) + 0.5 * size, max(s0, max(s1, s2)) + 0.5 * size), ok);
}

// An invocation culls BLADES_PER_INVOCATION consecutive blades, which lie close together, and
// lights the far ones among them with the sky's light at the first (`far_sky`); fewer, longer
// invocations also spare lavapipe its fixed cost per invocation. The workgroup's size and the
// blades an invocation takes are CULL_WORKGROUP and BLADES_PER_INVOCATION (from Rust, see above).

// True in the pipeline for blocks whose every blade is far (src/render/grass/blocks.rs): the
// near and middle blades' code is left out, which lavapipe would otherwise run, masked, for
// every blade.
override FAR_ONLY: bool = false;

// Each invocation's numbers of near and middle blades (near in the low half), so that the
// workgroup lists its block's blades in the order of their indices.
var<workgroup> invocation_counts: array<u32, CULL_WORKGROUP>;

// Adds an invocation's `far` far blades to their count, and their box of pixels (clamped to the
// image, whole pixels), which the main pass covers (`vs_far`), to the frame's: one atomic for the
// count and four for the box, only where there are far blades.
fn add_far(far: u32, far_box: vec4<f32>) {
    if (far > 0u) {
        atomicAdd(&args[10], far);
        let size = params.viewport.xy;
        let lo = vec2<u32>(clamp(floor(far_box.xy), vec2<f32>(0.0), size));
        let hi = vec2<u32>(clamp(ceil(far_box.zw), vec2<f32>(0.0), size));
        atomicMin(&args[11], lo.x);
        atomicMin(&args[12], lo.y);
        atomicMax(&args[13], hi.x);
        atomicMax(&args[14], hi.y);
    }
}

@compute @workgroup_size(CULL_WORKGROUP)
fn cs_cull(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) local: u32) {
    // A 2D dispatch when there are more than 65,535 workgroups.
    let slot = group.x + group.y * 65535u + select(0u, cull.far_base, FAR_ONLY);
    let block = lists[2u * cull.count + slot];
    let first = (block * CULL_WORKGROUP + local) * BLADES_PER_INVOCATION;
    let sky = far_sky(blades[min(first, cull.count - 1u)].position);
    var far = 0u;
    var far_box = NO_BOX;
    // Bit k: blade first + k is near (in `near`) or middle (in `mid`).
    var near = 0u;
    var mid = 0u;
    for (var k = 0u; k < BLADES_PER_INVOCATION; k = k + 1u) {
        let c = cull_blade(first + k, sky, false);
        far = far + select(0u, 1u, c.far_box.x <= c.far_box.z);
        far_box = vec4<f32>(min(far_box.xy, c.far_box.xy), max(far_box.zw, c.far_box.zw));
        near = near | select(0u, 1u << k, c.level == 0u);
        mid = mid | select(0u, 1u << k, c.level == 1u);
    }
    add_far(far, far_box);
    // The block's own lists, in the order of the blades' indices: each invocation's blades go
    // after those of the invocations before it (a block's counts fit 16 bits each). A block of
    // far blades lists none (FAR_ONLY is the same for the whole dispatch, so the barrier is
    // reached by all of the workgroup or by none of it).
    if (!FAR_ONLY) {
        invocation_counts[local] = countOneBits(near) | (countOneBits(mid) << 16u);
        workgroupBarrier();
        var before = 0u;
        var total = 0u;
        for (var j = 0u; j < CULL_WORKGROUP; j = j + 1u) {
            let c = invocation_counts[j];
            before = before + select(0u, c, j < local);
            total = total + c;
        }
        let own = own_at() + slot * BLOCK_BLADES;
        var n = before & 0xffffu;
        var m = before >> 16u;
        for (var k = 0u; k < BLADES_PER_INVOCATION; k = k + 1u) {
            if ((near & (1u << k)) != 0u) {
                lists[own + n] = first + k;
                n = n + 1u;
            }
            if ((mid & (1u << k)) != 0u) {
                lists[own + BLOCK_BLADES - 1u - m] = first + k;
                m = m + 1u;
            }
        }
        if (local == 0u) {
            lists[counts_at() + slot] = total;
        }
    }
}

// The blocks' near and middle blades, in the order of the frame's blocks and of their indices
// within a block, into the near and middle lists, with the two draws' index counts: one
// workgroup per block of the general pipeline, after `cs_cull`. A list that is full passes its
// later blades on to the next level: the near list's to the middle list after its own blades,
// the middle list's to the far blades, rasterised here.
var<workgroup> block_sums: array<vec4<u32>, CULL_WORKGROUP>;

@compute @workgroup_size(CULL_WORKGROUP)
fn cs_order(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) local: u32) {
    let slot = group.x + group.y * 65535u;
    // The near and middle blades of the blocks before this one and of all blocks: each
    // invocation sums every CULL_WORKGROUP-th block, then the workgroup adds the sums up.
    var sums = vec4<u32>(0u);
    for (var s = local; s < cull.far_base; s = s + CULL_WORKGROUP) {
        let c = lists[counts_at() + s];
        let nm = vec2<u32>(c & 0xffffu, c >> 16u);
        sums = sums + vec4<u32>(select(vec2<u32>(0u), nm, s < slot), nm);
    }
    block_sums[local] = sums;
    workgroupBarrier();
    var totals = vec4<u32>(0u);
    for (var j = 0u; j < CULL_WORKGROUP; j = j + 1u) {
        totals = totals + block_sums[j];
    }
    let near_total = totals.z;
    let mid_total = totals.w;
    let mine = lists[counts_at() + slot];
    let own = own_at() + slot * BLOCK_BLADES;
    var far = 0u;
    var far_box = NO_BOX;
    for (var j = local; j < (mine & 0xffffu); j = j + CULL_WORKGROUP) {
        let i = lists[own + j];
        let at = totals.x + j;
        // Past the near list's end: after the middle list's own blades, or far.
        let spill = mid_total + at - NEAR_CAP;
        if (at < NEAR_CAP) {
            lists[at] = i;
        } else if (spill < MID_CAP) {
            lists[cull.count + spill] = i;
        } else {
            let b = drop_to_far(i);
            far = far + 1u;
            far_box = vec4<f32>(min(far_box.xy, b.xy), max(far_box.zw, b.zw));
        }
    }
    for (var j = local; j < (mine >> 16u); j = j + CULL_WORKGROUP) {
        let i = lists[own + BLOCK_BLADES - 1u - j];
        let at = totals.y + j;
        if (at < MID_CAP) {
            lists[cull.count + at] = i;
        } else {
            let b = drop_to_far(i);
            far = far + 1u;
            far_box = vec4<f32>(min(far_box.xy, b.xy), max(far_box.zw, b.zw));
        }
    }
    add_far(far, far_box);
    // Every workgroup writes the same index counts.
    if (local == 0u) {
        let near_drawn = min(near_total, NEAR_CAP);
        atomicStore(&args[0], near_drawn * NEAR_INDICES);
        atomicStore(&args[5], min(mid_total + near_total - near_drawn, MID_CAP) * MID_INDICES);
    }
}

// Rasterises blade `i`, listed near or middle, as a far blade (both lists are full), under the
// sky's light its invocation of `cs_cull` took; the box of pixels it may cover.
fn drop_to_far(i: u32) -> vec4<f32> {
    let first = i - i % BLADES_PER_INVOCATION;
    return cull_blade(i, far_sky(blades[min(first, cull.count - 1u)].position), true).far_box;
}

// What `cull_blade` did with a blade: the box of pixels it may cover when it was drawn as a
// far blade (else `NO_BOX`), and its level: 0 near, 1 middle (both to be listed), 2 far or
// not drawn.
struct Culled {
    far_box: vec4<f32>,
    level: u32,
};

// Culls blade `i` and evaluates its shape: a near or middle blade writes it to `shapes`, a far
// one (every one with `force_far`) is rasterised under the sky's light `sky`. Its level, and the
// box of pixels it may cover when it was drawn as a far blade (a projected Bézier curve lies in
// the box of its projected control points).
//
// lavapipe runs a vector of invocations through both sides of every branch and through the first
// pass of every loop, masked: it leaves a loop only after a pass that none of them stays in, and
// every assignment under a condition costs it a masked store. So every blade here pays for the
// code of every level, visible or not, and that code is straight-line where it can be; the far
// pipeline (`FAR_ONLY`) leaves the near and middle levels' code out, and the CPU leaves out the
// blocks outside the view (src/render/grass/blocks.rs).
fn cull_blade(i: u32, sky: vec3<f32>, force_far: bool) -> Culled {
    let b = blades[min(i, cull.count - 1u)];
    // A sphere around the blade, wide enough for its bend, the wind and a push.
    let centre = b.position + vec3<f32>(0.0, 0.5 * b.height, 0.0);
    let radius = b.height;
    let d = distance(centre, cull.camera.xyz);
    var inside = i < cull.count && d <= cull.camera.w;
    for (var k = 0u; k < 6u; k = k + 1u) {
        let p = cull.planes[k];
        inside = inside && dot(p.xyz, centre) + p.w >= -radius;
    }
    // Straight-line code from here to the lists (see `rasterise_far`): a blade out of view is
    // worked out too, and neither listed nor drawn.
    let variation = f32(b.packed >> 8u) / 16777216.0;
    // The blade's width direction and the direction it leans, both horizontal.
    let across = vec3<f32>(cos(b.yaw), 0.0, -sin(b.yaw));
    let lean = vec3<f32>(sin(b.yaw), 0.0, cos(b.yaw));
    // The wind at the root: an angle towards the wind's direction from the scrolled noise.
    let wdir = cull.wind.xy;
    let uv = b.position.xz * cull.wind_noise.y - wdir * cull.wind.w * cull.wind_noise.x * cull.wind_noise.y;
    let n = textureSampleLevel(wind_tex, wind_sampler, uv, 0.0).r;
    let sway = cull.wind.z * (0.35 + 0.65 * n) * (0.85 + 0.3 * variation);
    // The total tilt at the tip: the wind plus the pushes away from the eye and the hit point.
    var tilt = wdir * sway;
    // The eye pushes only when it is within 2 m above the blade.
    let eye_near = clamp(2.0 - (cull.eye.y - b.position.y), 0.0, 1.0);
    tilt = tilt + push(b.position, cull.eye.xyz, cull.eye.w, 1.2 * eye_near);
    tilt = tilt + push(b.position, cull.hit.xyz, cull.hit.w, 1.3);
    let tilt_angle = min(length(tilt), 1.45);
    let tilt_axis = normalize(cross(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(tilt.x, 0.0, tilt.y) + vec3<f32>(1e-6, 0.0, 0.0)));

    // Walk up the blade in STEPS segments (FAR_STEPS for a far blade). Segment k's direction
    // is the vertical turned towards `lean` by the gravity bend and then about the tilt axis
    // by its share of the tilt, both at (k + 1/2) / steps of the full angle; the cosines and
    // sines of those angles are advanced by the angle-addition formulas.
    let level = select(select(select(2u, 1u, d < cull.lod_mid), 0u, d < cull.lod_near), 2u, FAR_ONLY || force_far);
    let steps = select(STEPS, FAR_STEPS, level == 2u);
    let n_seg = f32(steps);
    let segment_length = b.height / n_seg;
    let step_bend = b.bend / n_seg;
    let step_tilt = tilt_angle / n_seg;
    let bend_step = vec2<f32>(cos(step_bend), sin(step_bend));
    let tilt_step = vec2<f32>(cos(step_tilt), sin(step_tilt));
    var bend_cs = vec2<f32>(cos(0.5 * step_bend), sin(0.5 * step_bend));
    var tilt_cs = vec2<f32>(cos(0.5 * step_tilt), sin(0.5 * step_tilt));
    let up = vec3<f32>(0.0, 1.0, 0.0);
    var p = vec3<f32>(0.0);
    var middle = vec3<f32>(0.0);
    for (var k = 0u; k < steps; k = k + 1u) {
        let g = up * bend_cs.x - lean * bend_cs.y;
        let dir = g * tilt_cs.x + cross(tilt_axis, g) * tilt_cs.y + tilt_axis * dot(tilt_axis, g) * (1.0 - tilt_cs.x);
        p = p + dir * segment_length;
        if (k + 1u == steps / 2u) {
            middle = p;
        }
        bend_cs = vec2<f32>(bend_cs.x * bend_step.x - bend_cs.y * bend_step.y, bend_cs.y * bend_step.x + bend_cs.x * bend_step.y);
        tilt_cs = vec2<f32>(tilt_cs.x * tilt_step.x - tilt_cs.y * tilt_step.y, tilt_cs.y * tilt_step.x + tilt_cs.x * tilt_step.y);
    }
    // The quadratic Bézier curve from the root through the middle point (at t = 1/2) to the
    // tip: its control point.
    let tip = p;
    let ctrl = 2.0 * middle - 0.5 * tip;

    let listed = !FAR_ONLY && inside && level < 2u;
    if (listed) {
        var s: Shape;
        s.root = b.position;
        let half_width = pack2x16float(vec2<f32>(0.5 * b.width, 0.0)) & 0xffffu;
        s.width_patch = half_width | ((b.packed & 255u) << 16u) | (u32(variation * 255.0) << 24u);
        s.curve0 = pack2x16float(ctrl.xy);
        s.curve1 = pack2x16float(vec2<f32>(ctrl.z, tip.x));
        s.curve2 = pack2x16float(tip.yz);
        s.across = pack2x16float(across.xz);
        shapes[i] = s;
    }
    var out: Culled;
    out.far_box = rasterise_far(inside && level == 2u, b.position, b.position + ctrl, b.position + tip, across, b.packed & 255u, variation, sky);
    out.level = select(2u, level, listed);
    return out;
}
