// The page's WebGL renderer, as the headset page and web/page/render.mjs make it: antialiased at
// every quality (the leaves' alpha-to-coverage needs the multisampled target, in WebXR too),
// PCF shadows unless `low`, no tone mapping of three's own (the materials apply grove's tone
// curve, shading.mjs), and the environment light of a world (light.mjs), prefiltered once per
// kind and kept.

import * as THREE from 'three';
import { Light } from './light.mjs';

/**
 * A renderer on `canvas`; `preserve` keeps the drawing buffer for reading it back;
 * `antialias: false` only for comparing with grove's renderer, which takes one sample a pixel.
 */
export function createRenderer(canvas, { low = false, preserve = false, antialias = true } = {}) {
  const renderer = new THREE.WebGLRenderer({ canvas, antialias, alpha: true, powerPreference: 'high-performance', preserveDrawingBuffer: preserve });
  renderer.shadowMap.enabled = !low;
  renderer.shadowMap.type = THREE.PCFShadowMap;
  renderer.toneMapping = THREE.NoToneMapping;
  return renderer;
}

const environments = new WeakMap();

/** The environment light for a world ({ sh, map }, light.mjs): the sky's (`cube`), or a neutral one in AR (`ar`). */
export function environmentFor(renderer, { ar = false, cube = null } = {}) {
  let kept = environments.get(renderer);
  if (!kept) environments.set(renderer, (kept = new Map()));
  const key = ar || !cube ? 'room' : 'sky';
  if (!kept.has(key)) kept.set(key, Light.environment(renderer, key === 'sky' ? cube : null));
  return kept.get(key);
}
