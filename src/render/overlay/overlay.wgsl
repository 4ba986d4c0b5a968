// Interaction visuals: the controller ray, the hit marker, the anchor ball, the selection box
// and its handles, and the task's target markers. Flat colours with a simple sun term; lines
// (zero normal) are unlit. Uses only the frame uniforms (group 0) from lighting.wgsl.

// #import lighting

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) color: vec4<f32>,
    @location(2) normal: vec3<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
    @location(1) normal: vec3<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(v.position, 1.0);
    out.color = v.color;
    out.normal = v.normal;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    if (dot(in.normal, in.normal) < 0.25) {
        return in.color;
    }
    let n = normalize(in.normal);
    let k = 0.55 + 0.45 * max(dot(n, normalize(vec3<f32>(0.3, 1.0, 0.2))), 0.0);
    return vec4<f32>(in.color.rgb * k, in.color.a);
}
