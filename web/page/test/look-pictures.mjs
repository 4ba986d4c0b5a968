// The side-by-side pictures of docs/headset.md, "Parity with grove's renderer": a few models,
// each on its stage with the sky and ground, drawn by grove's renderer (left: `grove render
// --model FILE`) and by the headset page's drawing (right: web/page/render.mjs, multisampled as
// in the headset), at the same camera.
//
//   node web/page/test/look-pictures.mjs [--out FILE] [--tick T]
//
// FILE defaults to docs/headset-parity.png. Needs GROVE_BIN or target/debug/grove, the module
// (bash web/build.sh) and Chromium.

import { join, resolve } from 'node:path';
import { openStill, writePng } from '../render.mjs';
import { native } from './look.mjs';
import { ROOT } from './harness.mjs';

const MODELS = ['assets/trees/broadleaf-mesh.gltf', 'assets/trees/conifer-billboard.gltf', 'assets/banks/species/oak-lod1/oak-lod1.gltf', 'assets/banks/species/birch-lod1/birch-lod1.gltf'];
const [W, H, PAD] = [480, 360, 8];

const args = process.argv.slice(2);
const out = args.includes('--out') ? resolve(args[args.indexOf('--out') + 1]) : join(ROOT, 'docs/headset-parity.png');
const tick = args.includes('--tick') ? Number(args[args.indexOf('--tick') + 1]) : null;
const width = 2 * W + 3 * PAD;
const height = MODELS.length * (H + PAD) + PAD;
const data = Buffer.alloc(width * height * 4, 255);
const paste = (img, x0, y0) => {
  for (let y = 0; y < img.height; y++) img.data.copy(data, 4 * ((y0 + y) * width + x0), 4 * y * img.width, 4 * (y + 1) * img.width);
};
const still = await openStill();
try {
  for (const [i, m] of MODELS.entries()) {
    const file = join(ROOT, m);
    const y = PAD + i * (H + PAD);
    paste(native(file, { width: W, height: H, tick, background: 'sky' }), PAD, y);
    paste(await still.render(file, { width: W, height: H, tick, background: 'sky' }), 2 * PAD + W, y);
    console.log(`${m}: drawn`);
  }
} finally {
  await still.close();
}
writePng(out, { width, height, data });
console.log(`wrote ${out}: grove render (left) and the headset page's drawing (right), ${MODELS.length} models`);
