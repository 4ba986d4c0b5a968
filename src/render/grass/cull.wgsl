// Grass blades, compute stage: one invocation per blade of the scene. A blade whose bounding
// sphere lies outside the view frustum or beyond the far distance is dropped; the others are
// appended to the near list (drawn with 15 vertices) or the far list (7 vertices) by distance,
// and the instance counts of the two indirect draws are counted up atomically. No lighting is
// prepended: this module has its own group 0 (src/render/grass/mod.rs).
//
// Units: metres; +Y up.

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
    // Blades nearer than this many metres get the fine level of detail.
    lod_distance: f32,
    // The number of blades.
    count: u32,
    pad0: u32,
    pad1: u32,
};

@group(0) @binding(0) var<uniform> cull: Cull;
@group(0) @binding(1) var<storage, read> blades: array<Blade>;
@group(0) @binding(2) var<storage, read_write> near_list: array<u32>;
@group(0) @binding(3) var<storage, read_write> far_list: array<u32>;
// Two indirect draws of four words each: vertex count, instance count, first vertex, first
// instance. The frame resets the instance counts before this pass.
@group(0) @binding(4) var<storage, read_write> args: array<atomic<u32>, 8>;

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
    if (d < cull.lod_distance) {
        let slot = atomicAdd(&args[1], 1u);
        near_list[slot] = i;
    } else {
        let slot = atomicAdd(&args[5], 1u);
        far_list[slot] = i;
    }
}
