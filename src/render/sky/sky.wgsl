// The sky background: the environment cubemap seen through each pixel, dimmed with the sun's
// elevation, with a sun disc and glow. lighting.wgsl is prepended.

// #import lighting

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // The view ray through the pixel, world space, not normalised. For a perspective camera it
    // is an affine function of the pixel's position, so interpolating it from the corners is
    // exact and spares each pixel the inverse projection.
    @location(0) ray: vec3<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> VertexOut {
    // One triangle that covers the screen.
    let x = f32(i32(i & 1u) * 4 - 1);
    let y = f32(i32(i >> 1u) * 4 - 1);
    var out: VertexOut;
    out.clip = vec4<f32>(x, y, 1.0, 1.0);
    let far = frame.inv_view_proj * vec4<f32>(x, y, 1.0, 1.0);
    out.ray = far.xyz / far.w - frame.camera_pos;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let dir = normalize(in.ray);
    // The sky takes the ambient light's tint (warmer when the sun is low).
    let tint = frame.ambient / max(frame.ambient.r, 0.001);
    var c = srgb_decode(textureSampleLevel(env_map, env_sampler, dir, 0.0).rgb) * frame.sky * tint;
    // Sun disc, a halo, and a wide glow that is strongest when the sun is near the horizon:
    // s^600, s^40 and s^4 from one logarithm.
    let ls = log2(max(dot(dir, frame.sun_dir), 1e-6));
    let low = 1.0 - clamp(frame.sun_dir.y * 2.0, 0.0, 1.0);
    c = c + frame.sun_color * (exp2(600.0 * ls) * 4.0 + exp2(40.0 * ls) * 0.12 + exp2(4.0 * ls) * 0.25 * low);
    return vec4<f32>(tone(c), 1.0);
}
