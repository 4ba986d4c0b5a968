// A tree's levels of detail as grove's renderer chooses them (src/render/trees/instances.rs): a
// tree whose bounding sphere covers fewer than FAR_PIXELS pixels on screen is drawn as its
// model's far model (the bank catalogue's `far:`, e.g. oak-lod1 -> oak-lod2), one covering more
// than FAR_BAND times as many as its model, and one between as both, sharing its pixels by the
// impostors' screen-door dither (interleaved gradient noise, src/render/trees/impostor/octa.wgsl's
// `impostor_dither`): the model keeps the pixels whose dither is below 1 - share, the far model
// the others; opaque parts (bark) are drawn by the one with the larger share. The page has no
// impostors (grove's renderer goes on to them below `impostor_pixels`). levels.test.mjs holds
// FAR_BAND and FAR_PIXELS equal to the Rust constants.

/** The band of the cross-fade, times FAR_PIXELS (instances.rs FAR_BAND). */
export const FAR_BAND = 1.25;
/** grove's default on-screen size, pixels, below which a far model stands in (options.rs DEFAULT_FAR_PIXELS). */
export const FAR_PIXELS = 400;

/**
 * The share handed to the coarser level, 0 to 1 (impostor/mod.rs fade_in_band): a sphere of
 * `diameter` m at `distance` m and `pixelsPerRadian` against the threshold `below` pixels and a
 * band of `band` times it (1 or less: a hard switch).
 */
export function fadeInBand(diameter, distance, pixelsPerRadian, below, band) {
  if (below <= 0 || !(diameter > 0)) return 0;
  const pixels = (diameter * pixelsPerRadian) / Math.max(distance, 0.01);
  if (band <= 1) return pixels < below ? 1 : 0;
  const hi = below * band;
  return Math.min(Math.max((hi - pixels) / (hi - below), 0), 1);
}

/**
 * The share of a tree handed to its model's far model (instances.rs far_share): its model's box
 * `box` (model space, a THREE.Box3), the tree's `scale` and `distance` from the eye.
 */
export function farShare(box, scale, distance, pixelsPerRadian, farPixels = FAR_PIXELS) {
  const r = Math.hypot(
    Math.max(Math.abs(box.min.x), Math.abs(box.max.x)),
    Math.max(Math.abs(box.min.y), Math.abs(box.max.y)),
    Math.max(Math.abs(box.min.z), Math.abs(box.max.z)),
  );
  return fadeInBand(2 * r * scale, distance, pixelsPerRadian, farPixels, FAR_BAND);
}

/**
 * The levels a tree is drawn as, given its share `s` handed to its far model (null: it has
 * none): [{ far, share }], `share` the instanced attribute of the cross-fade (0: every pixel;
 * above 0: the pixels whose dither is below it; below 0: those whose dither is at least its
 * opposite), `bark` whether its opaque parts are drawn.
 */
export function levels(s) {
  if (s === null || s <= 0) return [{ far: false, share: 0, bark: true }];
  if (s >= 1) return [{ far: true, share: 0, bark: true }];
  return [
    { far: false, share: 1 - s, bark: s <= 0.5 },
    { far: true, share: -(1 - s), bark: s > 0.5 },
  ];
}

// The cross-fade in a tree's shaders (an InstancedMesh's: its `treeLevel.w`, wind.mjs's
// TREE_GLSL), in the camera's pass and the shadow map's alike.
const VARYING = 'flat varying float vGroveShare;';
/** The dither of a pixel (octa.wgsl's impostor_dither; levels.test.mjs holds its constants to it). */
export const DITHER_GLSL =
  'fract( 52.9829189 * fract( dot( floor( gl_FragCoord.xy ), vec2( 0.06711056, 0.00583715 ) ) ) )';
const DITHER = /* glsl */ `
	{
		float d = ${DITHER_GLSL};
		if ( ( vGroveShare > 0.0 && d >= vGroveShare ) || ( vGroveShare < 0.0 && d < - vGroveShare ) ) discard;
	}
	#include <alphahash_fragment>`;

/** Patches a tree material's shaders (after wind.mjs's vertex patch) with the cross-fade. */
export function crossFade(shader) {
  const { vertexShader: v, fragmentShader: f } = shader;
  if (!v.includes('#include <begin_vertex>') || !f.includes('#include <alphahash_fragment>'))
    throw new Error("levels: three.js's tree shaders are not the ones this page patches");
  shader.vertexShader = `${VARYING}\n${v}`.replace(
    '#include <begin_vertex>',
    '#include <begin_vertex>\n#ifdef USE_INSTANCING\n\tvGroveShare = treeLevel.w;\n#else\n\tvGroveShare = 0.0;\n#endif',
  );
  shader.fragmentShader = `${VARYING}\n${f}`.replace('#include <alphahash_fragment>', DITHER);
}
