// The sky background: the environment cubemap seen through each pixel, dimmed with the sun's
// elevation, with a sun disc, halo and glow (lighting.wgsl's `sky_lit`, which the aerial
// perspective fades distant surfaces towards). lighting.wgsl is prepended.

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
    // The sky along the ray (lighting.wgsl's `sky_lit`: below the horizon, where the terrain
    // has ended at the far plane, the colour the faded terrain takes), and the sun's disc above
    // the horizon only (the ground hides it below): s^600 of the cosine to the sun.
    let u = normalize(in.ray);
    let ls = log2(max(dot(u, frame.sun_dir), 1e-6));
    let disc = exp2(600.0 * ls) * 4.0 * select(0.0, 1.0, u.y > 0.0);
    return vec4<f32>(tone(sky_lit(u, ls) + frame.sun_color * disc), 1.0);
}
