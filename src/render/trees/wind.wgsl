// Per-vertex wind models for tree vertex shaders.
//
// This file holds only pure functions (no bindings, no entry points): a shader that animates
// trees includes this source and binds one `WindParams` uniform itself. `WindParams` is declared
// once, in Rust (`grove_systems::wind_model::WindParams`), and imported as the piece
// `wind_params`. The CPU reference of every function is in `systems/src/wind_model.rs` (named
// without the `wind_` prefix); tests/wind_gpu.rs runs these functions in a compute pass and
// checks that they agree with it to within 1e-4 m.
//
// Units: metres, seconds, hertz. World axes: +Y up, -Z north, +X east. `direction` is the
// horizontal unit vector (world X, Z) the wind blows towards.

// #import wind_params

const WIND_TAU: f32 = 6.2831855;
const WIND_INV_TAU: f32 = 0.15915494;
const WIND_NOISE_SEED: u32 = 0x67726f76u;

// A 32-bit integer hash ("lowbias32"). CPU: hash_u32.
fn wind_hash(x_in: u32) -> u32 {
    var x = x_in;
    x = x ^ (x >> 16u);
    x = x * 0x7feb352du;
    x = x ^ (x >> 15u);
    x = x * 0x846ca68bu;
    x = x ^ (x >> 16u);
    return x;
}

// The hash of an integer lattice point, in place of Perlin's permutation table. CPU: lattice_hash.
fn wind_lattice_hash(i: vec3<i32>) -> u32 {
    let hz = wind_hash(bitcast<u32>(i.z) + WIND_NOISE_SEED);
    let hy = wind_hash(bitcast<u32>(i.y) + hz);
    return wind_hash(bitcast<u32>(i.x) + hy);
}

// Perlin's improved-noise gradient: one of 12 edge directions dotted with p. CPU: grad.
fn wind_grad(h_in: u32, p: vec3<f32>) -> f32 {
    let h = h_in & 15u;
    let u = select(p.y, p.x, h < 8u);
    let v = select(select(p.z, p.x, h == 12u || h == 14u), p.y, h < 4u);
    let a = select(-u, u, (h & 1u) == 0u);
    let b = select(-v, v, (h & 2u) == 0u);
    return a + b;
}

// Perlin's fade curve 6t^5 - 15t^4 + 10t^3. CPU: fade.
fn wind_fade(t: vec3<f32>) -> vec3<f32> {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

fn wind_lerp(a: f32, b: f32, t: f32) -> f32 {
    return a + t * (b - a);
}

// Classic 3D gradient noise, roughly in [-1, 1], 0 on the lattice. CPU: perlin3.
fn wind_perlin3(p: vec3<f32>) -> f32 {
    let fl = floor(p);
    let i = vec3<i32>(fl);
    let f = p - fl;
    let u = wind_fade(f);
    let n000 = wind_grad(wind_lattice_hash(i), f);
    let n100 = wind_grad(wind_lattice_hash(i + vec3<i32>(1, 0, 0)), f - vec3<f32>(1.0, 0.0, 0.0));
    let n010 = wind_grad(wind_lattice_hash(i + vec3<i32>(0, 1, 0)), f - vec3<f32>(0.0, 1.0, 0.0));
    let n110 = wind_grad(wind_lattice_hash(i + vec3<i32>(1, 1, 0)), f - vec3<f32>(1.0, 1.0, 0.0));
    let n001 = wind_grad(wind_lattice_hash(i + vec3<i32>(0, 0, 1)), f - vec3<f32>(0.0, 0.0, 1.0));
    let n101 = wind_grad(wind_lattice_hash(i + vec3<i32>(1, 0, 1)), f - vec3<f32>(1.0, 0.0, 1.0));
    let n011 = wind_grad(wind_lattice_hash(i + vec3<i32>(0, 1, 1)), f - vec3<f32>(0.0, 1.0, 1.0));
    let n111 = wind_grad(wind_lattice_hash(i + vec3<i32>(1, 1, 1)), f - vec3<f32>(1.0, 1.0, 1.0));
    let x00 = wind_lerp(n000, n100, u.x);
    let x10 = wind_lerp(n010, n110, u.x);
    let x01 = wind_lerp(n001, n101, u.x);
    let x11 = wind_lerp(n011, n111, u.x);
    let y0 = wind_lerp(x00, x10, u.y);
    let y1 = wind_lerp(x01, x11, u.y);
    return wind_lerp(y0, y1, u.z);
}

// Gradient noise mapped to [0, 1]. CPU: noise01.
fn wind_noise01(p: vec3<f32>) -> f32 {
    return clamp(0.5 + 0.5 * wind_perlin3(p), 0.0, 1.0);
}

// noise(density * v0, t): the noise field at world point v0, drifting downwind at `speed` m/s.
// CPU: noise_at.
fn wind_noise_at(v0: vec3<f32>, dir: vec2<f32>, density: f32, speed: f32, t: f32) -> f32 {
    let drift = speed * t;
    let p = vec3<f32>(v0.x - dir.x * drift, v0.y, v0.z - dir.y * drift);
    return wind_noise01(density * p);
}

// sin(2 pi cycles), with the argument reduced to [-pi, pi) first. CPU: wave.
fn wind_wave(cycles: f32) -> f32 {
    let u = cycles + 0.5;
    let f = u - floor(u);
    return sin(WIND_TAU * (f - 0.5));
}

// Noise displacement: v0 + d * s * w * (noise(density * v0, t) - 0.5). v0 in world space, w the
// per-vertex weight (0 at the attachment, growing outward), s the effective strength.
// CPU: displace_noise.
fn wind_displace_noise(v0: vec3<f32>, w: f32, s: f32, dir: vec2<f32>, density: f32, speed: f32, t: f32) -> vec3<f32> {
    let n = wind_noise_at(v0, dir, density, speed, t);
    let k = s * w * (n - 0.5);
    return vec3<f32>(v0.x + dir.x * k, v0.y, v0.z + dir.y * k);
}

// Hierarchical model. v0: rest position, world space. ch: the _WIND channels in world metres
// (x height to root, y distance to trunk, z distance to branch, each times the instance scale;
// w the branch phase 0..1). bend: the tree's WindState.bend (lean, metres per metre, world X, Z).
// gain: WindState.gain. tree_phase: WindState.phase, radians. CPU: displace_hierarchical.
fn wind_displace_hierarchical(v0: vec3<f32>, ch: vec4<f32>, bend: vec2<f32>, gain: f32, tree_phase: f32, p: WindParams) -> vec3<f32> {
    let h = ch.x;
    let r = ch.y;
    let b = ch.z;
    let phi = ch.w + tree_phase * WIND_INV_TAU;
    let s = p.strength * p.gust * gain;
    let t = p.time;
    // Trunk: leans with the CPU-driven bend, growing with the square of the height.
    let lean = h * h / p.trunk_stiffness;
    let trunk = vec3<f32>(bend.x * lean, 0.0, bend.y * lean);
    // Branches: bob mostly vertically with the square of their distance to the trunk.
    let bob = s * (r * r / p.branch_stiffness) * wind_wave(p.branch_frequency * t + phi);
    let branch = vec3<f32>(0.4 * p.direction.x * bob, bob, 0.4 * p.direction.y * bob);
    // Leaves: flutter in all three axes with their distance to the branch.
    let a = s * p.leaf_flutter * b;
    let f = p.leaf_frequency;
    let leaf = vec3<f32>(
        a * wind_wave(f * t + phi),
        a * wind_wave(1.37 * f * t + phi + 0.25),
        a * wind_wave(1.71 * f * t + phi + 0.5),
    );
    return v0 + trunk + branch + leaf;
}

// Either model: `model` 0 = noise, anything else = hierarchical (pass p.model for the global
// choice, or a per-model override). The noise model's weight is ch.x + ch.y and its strength
// strength * gust * gain * noise_amplitude. CPU: displace.
fn wind_displace(model: u32, v0: vec3<f32>, ch: vec4<f32>, bend: vec2<f32>, gain: f32, tree_phase: f32, p: WindParams) -> vec3<f32> {
    if model == 0u {
        let s = p.strength * p.gust * gain * p.noise_amplitude;
        return wind_displace_noise(v0, ch.x + ch.y, s, p.direction, p.density, p.noise_speed, p.time);
    }
    return wind_displace_hierarchical(v0, ch, bend, gain, tree_phase, p);
}
