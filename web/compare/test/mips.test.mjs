// web/page/draw/mips.mjs, through which web/compare draws grove's leaf textures, builds their mips as
// grove's renderer does (textures.rs): alpha the 2 × 2 mean raised by 15 %, colour averaged in
// linear light weighted by alpha.

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { mipChain } from '../../page/draw/mips.mjs';

/** The levels below the image, as mipChain gives them after level 0. */
const coverageMips = (w, h, px) => mipChain(px, w, h).slice(1);

/** A w × h image of one texel colour [r, g, b, a], with `at` overriding texels by index. */
function image(w, h, texel, at = {}) {
  const px = new Uint8ClampedArray(w * h * 4);
  for (let i = 0; i < w * h; i++) px.set(at[i] ?? texel, i * 4);
  return px;
}

test('the chain halves down to 1 × 1, a non-square image too', () => {
  assert.deepEqual(
    coverageMips(8, 2, image(8, 2, [0, 0, 0, 255])).map((l) => [l.width, l.height]),
    [
      [4, 1],
      [2, 1],
      [1, 1],
    ],
  );
});

test('alpha: a quarter covered becomes 0.25 × 1.15 of 255, and coverage grows level by level instead of fading', () => {
  const one = coverageMips(2, 2, image(2, 2, [0, 0, 0, 0], { 0: [0, 0, 0, 255] }));
  assert.equal(one[0].data[3], Math.round(0.25 * 1.15 * 255));
  // A comb three quarters opaque (a needle texture): its mean stays 0.75 under a plain average,
  // and reaches full coverage at 1 × 1 here.
  const comb = image(8, 8, [0, 0, 0, 255], {
    0: [0, 0, 0, 0],
    6: [0, 0, 0, 0],
    17: [0, 0, 0, 0],
    19: [0, 0, 0, 0],
    32: [0, 0, 0, 0],
    34: [0, 0, 0, 0],
    49: [0, 0, 0, 0],
    55: [0, 0, 0, 0],
    60: [0, 0, 0, 0],
    62: [0, 0, 0, 0],
    9: [0, 0, 0, 0],
    27: [0, 0, 0, 0],
    41: [0, 0, 0, 0],
    44: [0, 0, 0, 0],
    13: [0, 0, 0, 0],
    30: [0, 0, 0, 0],
  });
  const levels = coverageMips(8, 8, comb);
  assert.equal(levels.at(-1).data[3], 255);
});

test('colour: transparent texels do not darken it, opaque ones average in linear light', () => {
  // Green opaque beside black transparent: the colour stays green.
  const half = coverageMips(2, 1, image(2, 1, [0, 0, 0, 0], { 0: [40, 200, 60, 255] }));
  assert.deepEqual([...half[0].data.slice(0, 3)], [40, 200, 60]);
  // Black and white, both opaque: the linear mean 0.5 is sRGB 188, not 128.
  const grey = coverageMips(2, 1, image(2, 1, [0, 0, 0, 255], { 1: [255, 255, 255, 255] }));
  assert.equal(grey[0].data[0], 188);
});
