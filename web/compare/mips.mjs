// The mip chain of an alpha-cut (MASK) leaf texture built as grove's renderer builds it
// (`mip_chain` in src/render/assets/textures.rs), so that three.js draws grove's leaf cards with the
// same coverage at a distance: each level a 2 × 2 box filter of the one above, its colour averaged
// in linear light weighted by alpha, its alpha the mean raised by 15 % (at most 1). three.js's own
// mips (the GPU's generateMipmap) average alpha, so a mostly transparent sprig or spray falls below
// the cutoff a few levels down and a far crown loses its leaves (docs/species.md, "Beside ez-tree").

/** The raise of alpha per mip level (textures.rs). */
export const ALPHA_RAISE = 1.15;

const toLinear = (c) => (c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4);
const toSrgb = (c) => (c <= 0.0031308 ? c * 12.92 : 1.055 * c ** (1 / 2.4) - 0.055);

/**
 * The levels below `rgba` (width × height RGBA8, colour sRGB-encoded where `srgb`), down to 1 × 1:
 * an array of { width, height, data } (Uint8ClampedArray), the first level half the size of the
 * image. Where a 2 × 2 block is wholly transparent its colour is `fill` (sRGB bytes [r, g, b]),
 * the colour grove's leaf atlas paints under alpha 0, when given.
 */
export function coverageMips(width, height, rgba, { srgb = true, fill = null } = {}) {
  const lin = srgb ? toLinear : (c) => c;
  const enc = srgb ? toSrgb : (c) => c;
  const byte = (v) => Math.floor(Math.min(Math.max(v, 0), 1) * 255 + 0.5);
  const levels = [];
  let [w, h, cur] = [width, height, rgba];
  while (w > 1 || h > 1) {
    const [nw, nh] = [Math.max(w >> 1, 1), Math.max(h >> 1, 1)];
    const next = new Uint8ClampedArray(nw * nh * 4);
    for (let y = 0; y < nh; y++) {
      for (let x = 0; x < nw; x++) {
        const sum = [0, 0, 0];
        let [wsum, asum] = [0, 0];
        for (const [dx, dy] of [[0, 0], [1, 0], [0, 1], [1, 1]]) {
          const i = (Math.min(y * 2 + dy, h - 1) * w + Math.min(x * 2 + dx, w - 1)) * 4;
          const a = cur[i + 3] / 255;
          asum += a;
          // Weighted by alpha (plus a little, as textures.rs) so transparent texels do not darken edges.
          for (let c = 0; c < 3; c++) sum[c] += lin(cur[i + c] / 255) * (a + 1e-3);
          wsum += a + 1e-3;
        }
        const o = (y * nw + x) * 4;
        for (let c = 0; c < 3; c++) next[o + c] = asum === 0 && fill ? fill[c] : byte(enc(sum[c] / wsum));
        next[o + 3] = byte(Math.min((asum / 4) * ALPHA_RAISE, 1));
      }
    }
    levels.push({ width: nw, height: nh, data: next });
    [w, h, cur] = [nw, nh, next];
  }
  return levels;
}

/** The mean colour (sRGB bytes) of the opaque texels of `rgba`, or null when there are none. */
export function opaqueMean(rgba) {
  const sum = [0, 0, 0];
  let n = 0;
  for (let i = 0; i < rgba.length; i += 4) {
    if (rgba[i + 3] < 128) continue;
    for (let c = 0; c < 3; c++) sum[c] += rgba[i + c];
    n++;
  }
  return n ? sum.map((v) => Math.round(v / n)) : null;
}
