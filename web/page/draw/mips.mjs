// The mip chain of a tree's albedo (and specular) texture as grove's renderer builds it
// (src/render/assets/textures.rs `mip_chain`): each level the box filter of the one above,
// colours averaged in linear light and weighted by alpha (so transparent texels do not darken a
// leaf's edge), alpha raised by 1.15 a level (so an alpha-tested leaf keeps its coverage when it
// is small on screen, and the specular map, whose strength is its alpha, its highlights).
// WebGL's own mipmaps average the encoded colours and let the alpha fade, which drew far leaves
// darker and thinner than grove draws them.

import * as THREE from 'three';

const toLinear = (c) => (c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4);
const toSrgb = (c) => (c <= 0.0031308 ? c * 12.92 : 1.055 * c ** (1 / 2.4) - 0.055);

/** The levels below an RGBA8 image (`data`, `width` × `height`), sRGB-encoded colours: [{ data, width, height }]. */
export function mipChain(data, width, height) {
  const lut = new Float32Array(256).map((_, i) => toLinear(i / 255));
  const levels = [{ data, width, height }];
  let [w, h, cur] = [width, height, data];
  while (w > 1 || h > 1) {
    const [nw, nh] = [Math.max(1, w >> 1), Math.max(1, h >> 1)];
    const next = new Uint8Array(nw * nh * 4);
    for (let y = 0; y < nh; y++) {
      for (let x = 0; x < nw; x++) {
        const taps = [[0, 0], [1, 0], [0, 1], [1, 1]].map(([dx, dy]) => 4 * (Math.min(y * 2 + dy, h - 1) * w + Math.min(x * 2 + dx, w - 1)));
        const o = 4 * (y * nw + x);
        let alpha = 0;
        let weights = 0;
        const sum = [0, 0, 0];
        for (const t of taps) {
          const a = cur[t + 3] / 255 + 1e-3;
          alpha += cur[t + 3] / 255;
          weights += a;
          for (let c = 0; c < 3; c++) sum[c] += lut[cur[t + c]] * a;
        }
        for (let c = 0; c < 3; c++) next[o + c] = Math.floor(Math.min(Math.max(toSrgb(sum[c] / weights), 0), 1) * 255 + 0.5);
        next[o + 3] = Math.floor(Math.min((alpha / 4) * 1.15, 1) * 255 + 0.5);
      }
    }
    levels.push({ data: next, width: nw, height: nh });
    [w, h, cur] = [nw, nh, next];
  }
  return levels;
}

/** The texels of a loaded texture's image (an ImageBitmap, image or canvas), RGBA8. */
function texels(image) {
  const c = document.createElement('canvas');
  c.width = image.width;
  c.height = image.height;
  const g = c.getContext('2d', { willReadFrequently: true });
  g.drawImage(image, 0, 0);
  return g.getImageData(0, 0, c.width, c.height).data;
}

const made = new WeakMap();

/**
 * An albedo texture with grove's mip chain: a DataTexture sampling as `texture` does (its wrap,
 * colour space and orientation), made once per texture.
 */
export function groveMips(texture) {
  if (!texture?.image?.width) return texture;
  if (made.has(texture)) return made.get(texture);
  const { width, height } = texture.image;
  const levels = mipChain(new Uint8Array(texels(texture.image).buffer), width, height);
  const t = new THREE.DataTexture(levels[0].data, width, height, THREE.RGBAFormat);
  t.mipmaps = levels;
  t.generateMipmaps = false;
  t.minFilter = THREE.LinearMipmapLinearFilter;
  t.magFilter = THREE.LinearFilter;
  t.colorSpace = texture.colorSpace;
  t.wrapS = texture.wrapS;
  t.wrapT = texture.wrapT;
  t.flipY = texture.flipY;
  t.channel = texture.channel;
  t.anisotropy = texture.anisotropy;
  t.offset.copy(texture.offset);
  t.repeat.copy(texture.repeat);
  t.rotation = texture.rotation;
  t.needsUpdate = true;
  made.set(texture, t);
  return t;
}
