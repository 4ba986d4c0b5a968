// The page's levels of detail (web/page/draw/levels.mjs) against grove's renderer: its thresholds
// and dither are the Rust side's constants (read from the Rust and WGSL sources, not copied), and
// its hand-off follows far_share's rule on the numbers of instances.rs's own test. No browser.

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import * as THREE from 'three';
import { DITHER_GLSL, FAR_BAND, FAR_PIXELS, farShare, levels } from '../draw/levels.mjs';

const ROOT = join(import.meta.dirname, '../../..');
const source = (file) => readFileSync(join(ROOT, file), 'utf8');
const constant = (file, re) => {
  const m = source(file).match(re);
  assert.ok(m, `${file}: no ${re}`);
  return m.slice(1).map(Number);
};

test("the far model's band, threshold and dither are grove's renderer's", () => {
  assert.deepEqual([FAR_BAND], constant('src/render/trees/instances.rs', /pub const FAR_BAND: f32 = ([\d.]+);/));
  assert.deepEqual([FAR_PIXELS], constant('src/render/options.rs', /pub const DEFAULT_FAR_PIXELS: f32 = ([\d.]+);/));
  const wgsl = constant(
    'src/render/trees/impostor/octa.wgsl',
    /fn impostor_dither[^{]*\{\s*return fract\(([\d.]+) \* fract\(dot\(floor\(p\), vec2<f32>\(([\d.]+), ([\d.]+)\)\)\)\);/,
  );
  const glsl = DITHER_GLSL.match(
    /fract\( ([\d.]+) \* fract\( dot\( floor\( gl_FragCoord\.xy \), vec2\( ([\d.]+), ([\d.]+) \) \) \) \)/,
  );
  assert.ok(glsl, DITHER_GLSL);
  assert.deepEqual(glsl.slice(1).map(Number), wgsl);
});

test("a tree hands its pixels to its far model by far_share's rule", () => {
  // instances.rs's test: a model 10 m tall and 2 m wide, 720 lines at 60°.
  const box = new THREE.Box3(new THREE.Vector3(-1, 0, -1), new THREE.Vector3(1, 10, 1));
  const ppr = (720 * 0.5) / Math.tan((30 * Math.PI) / 180);
  const soft = (d, scale = 1) => farShare(box, scale, d, ppr);
  assert.ok(Math.abs(soft(30) - (500 - 419.8) / 100) < 2e-3, String(soft(30)));
  assert.equal(soft(50), 1);
  assert.equal(soft(60, 0.5), 1);
  assert.equal(soft((2 * 10.0995 * ppr) / (400 * FAR_BAND * 1.01)), 0);
  assert.equal(farShare(box, 1, 1e6, ppr, 0), 0);
  // The levels drawn: the model alone, both (the bark to the larger share), the far model alone.
  assert.deepEqual(levels(null), [{ far: false, share: 0, bark: true }]);
  assert.deepEqual(levels(0), [{ far: false, share: 0, bark: true }]);
  assert.deepEqual(levels(1), [{ far: true, share: 0, bark: true }]);
  assert.deepEqual(levels(0.25), [
    { far: false, share: 0.75, bark: true },
    { far: true, share: -0.75, bark: false },
  ]);
  assert.deepEqual(
    levels(0.75).map((l) => l.bark),
    [false, true],
  );
});
