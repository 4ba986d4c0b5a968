// Impostors: one quad per far tree, facing the camera (the sun in the shadow map), showing the
// three atlas views nearest to its direction blended by barycentric weights, alpha-tested
// against the baked coverage, lit with the baked normals, at the baked depth, and leaned by the
// tree's WindState as its trunk is in wind.wgsl, and faded into the aerial perspective's haze as
// the mesh is. lighting.wgsl, wind.wgsl and
// octa.wgsl are prepended. Units: metres, radians; +Y up.

// #import lighting, wind, octa

// The model's bounding sphere (model-space metres), as baked (src/render/trees/impostor/draw.rs
// `ImpostorParams`).
struct ImpostorParams {
    centre: vec3<f32>,
    radius: f32,
    // The model's extent in each view, in radii: (min x, min y, max x, max y), row-major.
    rects: array<vec4<f32>, 64>,
};

@group(0) @binding(1) var<uniform> wind: WindParams;
@group(2) @binding(0) var<uniform> imp: ImpostorParams;
@group(2) @binding(1) var imp_albedo: texture_2d<f32>;
@group(2) @binding(2) var imp_normal: texture_2d<f32>;
@group(2) @binding(3) var imp_sampler: sampler;

// Whether this pipeline draws into the shadow map: the quads then face the sun.
override SUN_VIEW: bool = false;

// The tree instance (src/render/trees/instances.rs), as in trees.wgsl.
struct ImpostorIn {
    @location(5) origin: vec3<f32>,
    @location(6) scale: f32,
    @location(7) yaw: f32,
    @location(8) bend: vec2<f32>,
    @location(9) gain: f32,
    @location(10) phase: f32,
    @location(11) keep: f32,
    // The share of the tree drawn as an impostor, 0..1 (impostor::fade).
    @location(13) fade: f32,
};

struct ImpostorOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    // The fragment's place in each of the three blended views, in units of the bounding
    // sphere's radius (x right, y up).
    @location(1) s01: vec4<f32>,
    @location(2) s2: vec2<f32>,
    @location(3) @interpolate(flat) fade: f32,
    @location(4) @interpolate(flat) yaw: f32,
    // The direction towards the viewer, world space (xyz), and the bounding sphere's radius in
    // metres (w): the atlas depth moves a fragment along it.
    @location(5) @interpolate(flat) toward: vec4<f32>,
    // The three views' atlas cells and their weights.
    @location(6) @interpolate(flat) cells01: vec4<f32>,
    @location(7) @interpolate(flat) cell2: vec2<f32>,
    @location(8) @interpolate(flat) weights: vec3<f32>,
    // The aerial perspective's haze at the vertex (lighting.wgsl `haze_at`), as on the mesh.
    @location(9) haze: vec4<f32>,
};

fn imp_rotate_y(v: vec3<f32>, yaw: f32) -> vec3<f32> {
    let c = cos(yaw);
    let s = sin(yaw);
    return vec3<f32>(c * v.x + s * v.z, v.y, -s * v.x + c * v.z);
}

// The point `rel` (model space, from the sphere's centre, in the plane facing `m`) seen along
// `m` in the view of `cell`: where the ray through it meets that view's plane, in radii.
fn imp_view_coords(rel: vec3<f32>, m: vec3<f32>, cell: vec2<f32>) -> vec2<f32> {
    let d = impostor_cell_dir(cell);
    let right = impostor_basis_right(d);
    let up = cross(d, right);
    let x = rel - m * (dot(rel, d) / max(dot(m, d), 0.2));
    return vec2<f32>(dot(x, right), dot(x, up)) / imp.radius;
}

// The main view's impostor vertex: `impostor_vertex` faded into the aerial perspective's haze.
@vertex
fn vs_impostor(@builtin(vertex_index) vi: u32, v: ImpostorIn) -> ImpostorOut {
    var out = impostor_vertex(vi, v);
    out.haze = haze_at(out.world_pos);
    return out;
}

// The impostor vertex of the depth-only passes (the main view's pre-pass and the shadow map):
// no haze, which they do not draw (and the shadow map's layout binds no environment map). Its
// clip position is `vs_impostor`'s, computed by the same function.
@vertex
fn vs_impostor_depth(@builtin(vertex_index) vi: u32, v: ImpostorIn) -> ImpostorOut {
    return impostor_vertex(vi, v);
}

// One corner of an impostor's quad (`vi`, two triangles) for the tree instance `v`.
fn impostor_vertex(vi: u32, v: ImpostorIn) -> ImpostorOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let corner = corners[vi];
    let centre = v.origin + imp_rotate_y(imp.centre * v.scale, v.yaw);
    let toward = select(frame.camera_pos - centre, frame.sun_dir, SUN_VIEW);
    // The direction to the viewer in model space (the yaw undone), on the upper hemisphere.
    let mt = imp_rotate_y(toward, -v.yaw);
    let m = normalize(vec3<f32>(mt.x, max(mt.y, 0.0), mt.z) + vec3<f32>(0.0, 1e-4, 0.0));
    // The three views around it: the triangle of cell centres that holds the direction in the
    // atlas's grid, weighted by barycentric coordinates, so a turning tree or a moving viewer
    // passes from view to view without a jump.
    let g = clamp((hemi_oct_encode(m) * 0.5 + 0.5) * IMPOSTOR_GRID - 0.5, vec2<f32>(0.0), vec2<f32>(IMPOSTOR_GRID - 1.0));
    let b = min(floor(g), vec2<f32>(IMPOSTOR_GRID - 2.0));
    let f = g - b;
    var c0 = b;
    var w0 = 1.0 - f.x - f.y;
    if (f.x + f.y > 1.0) {
        c0 = b + vec2<f32>(1.0, 1.0);
        w0 = f.x + f.y - 1.0;
    }
    let c1 = b + vec2<f32>(1.0, 0.0);
    let c2 = b + vec2<f32>(0.0, 1.0);
    let w1 = select(f.x, 1.0 - f.y, f.x + f.y > 1.0);
    let w2 = select(f.y, 1.0 - f.x, f.x + f.y > 1.0);
    let right = impostor_basis_right(m);
    let up = cross(m, right);
    // The quad faces the viewer, cut to the three views' extents together (grown a little,
    // since they look from nearby directions).
    let r0 = imp.rects[u32(c0.y) * u32(IMPOSTOR_GRID) + u32(c0.x)];
    let r1 = imp.rects[u32(c1.y) * u32(IMPOSTOR_GRID) + u32(c1.x)];
    let r2 = imp.rects[u32(c2.y) * u32(IMPOSTOR_GRID) + u32(c2.x)];
    let lo = max(min(min(r0.xy, r1.xy), r2.xy) - 0.05, vec2<f32>(-1.0));
    let hi = min(max(max(r0.zw, r1.zw), r2.zw) + 0.05, vec2<f32>(1.0));
    let q = mix(lo, hi, corner * 0.5 + 0.5);
    let rel = (right * q.x + up * q.y) * imp.radius;
    let local = imp.centre + rel;
    var wp = v.origin + imp_rotate_y(local * v.scale, v.yaw);
    // The whole quad leans with the trunk: bend * h² / trunk_stiffness at height h.
    let h = max(local.y, 0.0) * v.scale;
    let lean = h * h / max(wind.trunk_stiffness, 1e-3);
    wp = wp + vec3<f32>(v.bend.x * lean, 0.0, v.bend.y * lean);
    var out: ImpostorOut;
    out.clip = frame.view_proj * vec4<f32>(wp, 1.0);
    out.world_pos = wp;
    out.s01 = vec4<f32>(imp_view_coords(rel, m, c0), imp_view_coords(rel, m, c1));
    out.s2 = imp_view_coords(rel, m, c2);
    out.fade = v.fade;
    out.yaw = v.yaw;
    out.toward = vec4<f32>(imp_rotate_y(m, v.yaw), imp.radius * v.scale);
    out.cells01 = vec4<f32>(c0, c1);
    out.cell2 = c2;
    out.weights = vec3<f32>(w0, w1, w2);
    out.haze = vec4<f32>(0.0);
    return out;
}

// The atlas coordinates of the place `s` (radii) in the view of `cell`, kept inside the cell.
fn imp_uv(s: vec2<f32>, cell: vec2<f32>) -> vec2<f32> {
    let t = clamp(vec2<f32>(s.x + 1.0, 1.0 - s.y) * 0.5, vec2<f32>(0.0), vec2<f32>(1.0));
    return (cell + t) / IMPOSTOR_GRID;
}

// The albedo atlas blended over the three views.
fn imp_albedo_at(in: ImpostorOut) -> vec4<f32> {
    return textureSample(imp_albedo, imp_sampler, imp_uv(in.s01.xy, in.cells01.xy)) * in.weights.x
        + textureSample(imp_albedo, imp_sampler, imp_uv(in.s01.zw, in.cells01.zw)) * in.weights.y
        + textureSample(imp_albedo, imp_sampler, imp_uv(in.s2, in.cell2)) * in.weights.z;
}

// The normal and depth atlas blended over the three views.
fn imp_normal_at(in: ImpostorOut) -> vec4<f32> {
    return textureSample(imp_normal, imp_sampler, imp_uv(in.s01.xy, in.cells01.xy)) * in.weights.x
        + textureSample(imp_normal, imp_sampler, imp_uv(in.s01.zw, in.cells01.zw)) * in.weights.y
        + textureSample(imp_normal, imp_sampler, imp_uv(in.s2, in.cell2)) * in.weights.z;
}

// The point of the tree's surface a fragment shows, world space: the quad lies in the plane
// through the sphere's centre, and the atlas depth (0 at the side facing the viewer, 1 at the
// far side of the sphere) moves the point towards or away from the viewer.
fn impostor_surface(in: ImpostorOut, depth: f32) -> vec3<f32> {
    return in.world_pos + in.toward.xyz * (in.toward.w * (1.0 - 2.0 * depth));
}

// Whether a fragment of the impostor is kept: covered in the atlas and on the impostor's side
// of the cross-fade dither.
fn impostor_kept(coverage: f32, pixel: vec2<f32>, fade: f32) -> bool {
    return coverage >= 0.5 && impostor_dither(pixel) < fade;
}

// Shades an impostor fragment. It never discards: the depth pre-pass (fs_impostor_depth, with
// the camera's view) kept the fragment, and this pass runs at equal depth (the quad's), so
// each pixel is shaded once however many impostors overlap it, and the early depth test skips
// the rest before any shading. The atlas depth places the point that is lit.
@fragment
fn fs_impostor(in: ImpostorOut) -> @location(0) vec4<f32> {
    let a = imp_albedo_at(in);
    let nd = imp_normal_at(in);
    let surface = impostor_surface(in, nd.a);
    // Empty texels hold zero colour, so a filtered texel at the silhouette is divided back. The
    // atlas is read through a linear view of its sRGB texels (a software rasteriser filters
    // those much faster than sRGB ones), so the colour is decoded here, after the filtering.
    let albedo = srgb_decode(a.rgb / max(a.a, 1e-3));
    let nm = imp_rotate_y(nd.xyz * 2.0 - 1.0, in.yaw);
    let n = select(vec3<f32>(0.0, 1.0, 0.0), nm * inverseSqrt(max(dot(nm, nm), 1e-12)), dot(nm, nm) > 1e-6);
    let c = shade(albedo, n, surface, 0.0, 0.8, 0.3);
    return vec4<f32>(tone(mix(c, in.haze.rgb, in.haze.a)), 1.0);
}

// Depth only, for the main view's pre-pass: coverage and dither, at the quad's depth. (With the
// atlas depth as frag_depth here, the shading pass would have to write it too, and a software
// rasteriser then shades every fragment of every quad before its depth test: several times the
// cost in the forest.)
@fragment
fn fs_impostor_depth(in: ImpostorOut) {
    let a = imp_albedo_at(in).a;
    if (!impostor_kept(a, in.clip.xy, in.fade)) {
        discard;
    }
}

// Depth only, for the shadow map: coverage and dither, at the quad's depth (the plane through
// the bounding sphere's centre facing the sun). Only the view of the largest weight is read.
// The atlas depth is not written: a pass that writes depth loses the early depth test on a
// software rasteriser, and the crown's sunlit half lies in front of that plane, its shaded half
// behind it, so the impostors' own lighting and the ground's shadows barely change.
@fragment
fn fs_impostor_shadow(in: ImpostorOut) {
    let pick_y = in.weights.y > in.weights.x && in.weights.y >= in.weights.z;
    let pick_z = !pick_y && in.weights.z > in.weights.x;
    let s = select(select(in.s01.xy, in.s01.zw, pick_y), in.s2, pick_z);
    let cell = select(select(in.cells01.xy, in.cells01.zw, pick_y), in.cell2, pick_z);
    let a = textureSample(imp_albedo, imp_sampler, imp_uv(s, cell)).a;
    if (!impostor_kept(a, in.clip.xy, in.fade)) {
        discard;
    }
}
