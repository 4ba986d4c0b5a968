// Shared by the lit passes (prepended with lighting.wgsl, src/render/gpu.rs) and the impostor bake
// (src/render/trees/impostor/bake.rs).

// An sRGB-encoded colour (0..1) to linear, for textures whose encoded bytes are sampled through
// a linear format (`ENCODED_FORMAT` in src/render/assets/textures.rs: the environment cube, the
// ground, the models' albedo) and decoded after filtering. A cubic through 0 and 1 fitted to the
// sRGB curve: decoded and encoded again, each of the 256 byte values comes back within 1.4 of
// 255.
fn srgb_decode(c: vec3<f32>) -> vec3<f32> {
    return c * (c * (c * 0.406 + 0.546) + 0.048);
}
