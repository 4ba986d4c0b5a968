// Impostor views: the hemi-octahedral layout of the atlas and the screen-door dither of the
// cross-fade, shared by the mesh shader (trees.wgsl), the impostor shader and the bake. The CPU
// twins are in src/render/trees/impostor/mod.rs (`hemi_oct_encode`, `hemi_oct_decode`,
// `view_basis`). Directions are model space, +Y up; only the upper hemisphere is stored.

// The number of views along each side of the atlas (IMPOSTOR_GRID × IMPOSTOR_GRID views).
const IMPOSTOR_GRID: f32 = 8.0;

// A direction with y >= 0 to the square [-1, 1]²: the octahedral projection, turned by 45° so
// that the upper hemisphere fills the whole square.
fn hemi_oct_encode(d: vec3<f32>) -> vec2<f32> {
    let a = d / max(abs(d.x) + abs(d.y) + abs(d.z), 1e-6);
    return vec2<f32>(a.x + a.z, a.z - a.x);
}

// The inverse of hemi_oct_encode: a point of [-1, 1]² to a unit direction with y >= 0.
fn hemi_oct_decode(e: vec2<f32>) -> vec3<f32> {
    let x = (e.x - e.y) * 0.5;
    let z = (e.x + e.y) * 0.5;
    return normalize(vec3<f32>(x, max(1.0 - abs(x) - abs(z), 0.0), z));
}

// The atlas cell (column, row) whose view is nearest to the model-space direction `d`.
fn impostor_cell(d: vec3<f32>) -> vec2<f32> {
    let e = hemi_oct_encode(vec3<f32>(d.x, max(d.y, 0.0), d.z));
    return clamp(floor((e * 0.5 + 0.5) * IMPOSTOR_GRID), vec2<f32>(0.0), vec2<f32>(IMPOSTOR_GRID - 1.0));
}

// The view direction (towards the viewer) of an atlas cell.
fn impostor_cell_dir(cell: vec2<f32>) -> vec3<f32> {
    return hemi_oct_decode((cell + 0.5) / IMPOSTOR_GRID * 2.0 - 1.0);
}

// The right and up axes of the view looking along -d (d points towards the viewer).
fn impostor_basis_right(d: vec3<f32>) -> vec3<f32> {
    let up_ref = select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, -1.0), abs(d.y) > 0.999);
    return normalize(cross(up_ref, d));
}

// Interleaved gradient noise (Jimenez 2014) of a pixel position, in [0, 1): the threshold of
// the dithered cross-fade. A mesh fragment is kept where it is at least the tree's fade and an
// impostor fragment where it is below, so the two fill complementary pixels.
fn impostor_dither(p: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(floor(p), vec2<f32>(0.06711056, 0.00583715))));
}
