// Grass blades, compute stage: one invocation per blade of the scene. A blade whose bounding
// sphere lies outside the view frustum or beyond the far distance is dropped. For every other
// blade this pass does all the per-blade work of the frame once: the wind (a rotation towards
// the wind's direction whose angle comes from a world-space noise texture scrolled along the
// wind, so neighbouring blades move together), the pushes away from the eye and the controller's
// hit point, and the gravity bend, and writes the blade's final shape (a quadratic Bézier curve
// through its root, middle and tip) into `shapes`. It then appends the blade's index to one of
// three lists by the level of detail its distance calls for: near (7 segments), middle (3) and
// far (a line), counting the vertices of three non-instanced indirect draws. The
// vertex shader (blades.wgsl) is left with a few multiply-adds per vertex. No lighting is
// prepended: this module has its own group 0 (src/render/grass/mod.rs).
//
// Units: metres, radians, seconds; +Y up.

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

// A visible blade's shape this frame (matches `Shape` in blades.wgsl): 32 bytes.
struct Shape {
    // The root, metres.
    root: vec3<f32>,
    // Bits 0..15 the half width at the root (metres, a half float), bits 16..23 the patch
    // index, bits 24..31 the blade's variation (0..255).
    width_patch: u32,
    // The Bézier control point and the tip relative to the root, metres, as six half floats:
    // (ctrl.x, ctrl.y), (ctrl.z, tip.x), (tip.y, tip.z).
    curve0: u32,
    curve1: u32,
    curve2: u32,
    // The horizontal width direction (x, z) as two half floats.
    across: u32,
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
    // The number of blades.
    count: u32,
    pad0: u32,
    // The wind: direction (x, z), the bend it gives (radians at the tip), the time, seconds.
    wind: vec4<f32>,
    // The scroll speed of the wind noise (m/s), its scale (per metre), unused, unused.
    wind_noise: vec4<f32>,
    // The eye, metres, and the radius within which blades bend away from it.
    eye: vec4<f32>,
    // The controller's hit point, metres, and its radius (0: no hit point).
    hit: vec4<f32>,
};

@group(0) @binding(0) var<uniform> cull: Cull;
@group(0) @binding(1) var<storage, read> blades: array<Blade>;
@group(0) @binding(2) var<storage, read_write> shapes: array<Shape>;
// The three lists of blade indices, `count` entries each: near, middle, far.
@group(0) @binding(3) var<storage, read_write> lists: array<u32>;
// Three indirect draws: two indexed ones (index count, instance count 1, first index, base
// vertex, first instance) for the near and middle blades, then a plain one (vertex count,
// instance count 1, first vertex, first instance) for the far lines. The frame resets the
// counts before this pass; each visible blade adds its level's indices or vertices. The base
// vertex of the middle draw and the first vertex of the far one point at their lists (`count`
// times their vertices a blade), so that vertex / vertices a blade is the index into `lists`.
@group(0) @binding(4) var<storage, read_write> args: array<atomic<u32>, 14>;
@group(0) @binding(5) var wind_tex: texture_2d<f32>;
@group(0) @binding(6) var wind_sampler: sampler;

// The indices of a blade at each level of detail (indexed triangle lists, and a line's two
// vertices; blades.wgsl), and the most blades the near and middle index buffers hold
// (`NEAR_CAP`, `MID_CAP` in src/render/grass/data.rs): blades beyond them drop a level.
const NEAR_INDICES: u32 = 39u;
const MID_INDICES: u32 = 15u;
const FAR_VERTICES: u32 = 2u;
const NEAR_CAP: u32 = 65536u;
const MID_CAP: u32 = 262144u;
// The segments the blade's curve is integrated over before it is fitted (even).
const STEPS: u32 = 8u;

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

@compute @workgroup_size(256)
fn cs_cull(@builtin(global_invocation_id) id: vec3<u32>) {
    // A 2D dispatch when there are more than 65,535 workgroups of blades.
    let i = id.x + id.y * 65535u * 256u;
    if (i >= cull.count) {
        return;
    }
    let b = blades[i];
    // A sphere around the blade, wide enough for its bend, the wind and a push.
    let centre = b.position + vec3<f32>(0.0, 0.5 * b.height, 0.0);
    let radius = b.height;
    for (var k = 0u; k < 6u; k = k + 1u) {
        let p = cull.planes[k];
        if (dot(p.xyz, centre) + p.w < -radius) {
            return;
        }
    }
    let d = distance(centre, cull.camera.xyz);
    if (d > cull.camera.w) {
        return;
    }

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

    // Walk up the blade in STEPS segments. Segment k's direction is the vertical turned towards
    // `lean` by the gravity bend and then about the tilt axis by its share of the tilt, both at
    // (k + 1/2) / STEPS of the full angle; the cosines and sines of those angles are advanced by
    // the angle-addition formulas.
    let n_seg = f32(STEPS);
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
    for (var k = 0u; k < STEPS; k = k + 1u) {
        let g = up * bend_cs.x - lean * bend_cs.y;
        let dir = g * tilt_cs.x + cross(tilt_axis, g) * tilt_cs.y + tilt_axis * dot(tilt_axis, g) * (1.0 - tilt_cs.x);
        p = p + dir * segment_length;
        if (k + 1u == STEPS / 2u) {
            middle = p;
        }
        bend_cs = vec2<f32>(bend_cs.x * bend_step.x - bend_cs.y * bend_step.y, bend_cs.y * bend_step.x + bend_cs.x * bend_step.y);
        tilt_cs = vec2<f32>(tilt_cs.x * tilt_step.x - tilt_cs.y * tilt_step.y, tilt_cs.y * tilt_step.x + tilt_cs.x * tilt_step.y);
    }
    // The quadratic Bézier curve from the root through the middle point (at t = 1/2) to the
    // tip: its control point.
    let tip = p;
    let ctrl = 2.0 * middle - 0.5 * tip;

    var s: Shape;
    s.root = b.position;
    let half_width = pack2x16float(vec2<f32>(0.5 * b.width, 0.0)) & 0xffffu;
    s.width_patch = half_width | ((b.packed & 255u) << 16u) | (u32(variation * 255.0) << 24u);
    s.curve0 = pack2x16float(ctrl.xy);
    s.curve1 = pack2x16float(vec2<f32>(ctrl.z, tip.x));
    s.curve2 = pack2x16float(tip.yz);
    s.across = pack2x16float(across.xz);
    shapes[i] = s;

    // A full list passes the blade on to the next level: the first NEAR_CAP blades to come
    // get slots, every later one takes its count back.
    var level = select(select(2u, 1u, d < cull.lod_mid), 0u, d < cull.lod_near);
    if (level == 0u) {
        let slot = atomicAdd(&args[0], NEAR_INDICES) / NEAR_INDICES;
        if (slot < NEAR_CAP) {
            lists[slot] = i;
            return;
        }
        atomicSub(&args[0], NEAR_INDICES);
        level = 1u;
    }
    if (level == 1u) {
        let slot = atomicAdd(&args[5], MID_INDICES) / MID_INDICES;
        if (slot < MID_CAP) {
            lists[cull.count + slot] = i;
            return;
        }
        atomicSub(&args[5], MID_INDICES);
    }
    let slot = atomicAdd(&args[10], FAR_VERTICES) / FAR_VERTICES;
    lists[2u * cull.count + slot] = i;
}
