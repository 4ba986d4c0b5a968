// The grass shaders' shared declarations, prepended to cull.wgsl and blades.wgsl
// (src/render/grass/mod.rs): what the cull pass writes for each visible blade and the blade
// draw's uniforms, which the cull pass reads too.
//
// Units: metres, radians; +Y up.

// A visible blade's shape this frame: 32 bytes.
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

// The blade draw's uniforms (`BladeParams` in src/render/grass/data.rs).
struct BladeParams {
    // Per patch: the root colour, then the tip colour (linear RGB).
    colours: array<vec4<f32>, 128>,
    // The image's width and height, pixels; the view depth that the far image's depth codes span,
    // metres; unused.
    viewport: vec4<f32>,
    // The normalised device depth of a point at view depth w is depth.x + depth.y / w.
    depth: vec4<f32>,
    // The unit vector towards the sun; the sun's colour times its intensity and the ambient
    // tint times its strength, linear RGB (as `Frame` in lighting.wgsl gives them).
    sun_dir: vec4<f32>,
    sun_color: vec4<f32>,
    ambient: vec4<f32>,
};
