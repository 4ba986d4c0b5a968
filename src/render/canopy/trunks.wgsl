// The trunks under the canopy's crowns: one instanced draw of a tapered six-sided prism (no
// caps: the foot stands in the ground and the top inside the crown), lit by the sun and casting
// shadows. No sway: the canopy layers above do not sway either.
// lighting.wgsl is prepended (src/render/canopy/trunks.rs).

// #import lighting

struct TrunkIn {
    // The tree's foot (world, metres) and the trunk's radius at the foot, metres.
    @location(0) foot_radius: vec4<f32>,
    // The trunk's height over the foot, metres, and padding.
    @location(1) height_pad: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

// How much narrower the trunk is at its top than at its foot.
const TAPER: f32 = 0.4;
// The prism's sides.
const SIDES: u32 = 6u;

@vertex
fn vs_main(@builtin(vertex_index) i: u32, t: TrunkIn) -> VertexOut {
    // Side s is two triangles: (bottom a, top a, bottom b) and (bottom b, top a, top b).
    let side = i / 6u;
    let corner = array<vec2<u32>, 6>(vec2<u32>(0u, 0u), vec2<u32>(0u, 1u), vec2<u32>(1u, 0u), vec2<u32>(1u, 0u), vec2<u32>(0u, 1u), vec2<u32>(1u, 1u));
    let c = corner[i % 6u];
    let angle = f32(side + c.x) * 6.2831853 / f32(SIDES);
    let up = f32(c.y);
    let r = t.foot_radius.w * (1.0 - TAPER * up);
    let dir = vec3<f32>(cos(angle), 0.0, sin(angle));
    var out: VertexOut;
    out.world_pos = t.foot_radius.xyz + dir * r + vec3<f32>(0.0, up * t.height_pad.x, 0.0);
    out.clip = frame.view_proj * vec4<f32>(out.world_pos, 1.0);
    // The taper leans the sides' normals a little upwards.
    out.normal = normalize(dir + vec3<f32>(0.0, TAPER * t.foot_radius.w / max(t.height_pad.x, 0.01), 0.0));
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    // Grey-brown bark, linear RGB.
    let albedo = vec3<f32>(0.11, 0.085, 0.065);
    let c = shade(albedo, normalize(in.normal), in.world_pos, 0.05, 0.9, 0.0);
    return vec4<f32>(tone(aerial(c, in.world_pos)), 1.0);
}
