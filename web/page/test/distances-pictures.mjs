// docs/species.md's sheet "From 3, 10 and 30 m" drawn through the headset page's drawing
// (web/page/render.mjs, multisampled as in the headset): every species at level of detail 1 (the
// species bank's `NAME-lod1`, the model grove's sheet draws) in rows, from 3, 10 and 30 m in
// columns, 320 × 240 each, at the walker's view the native sheet takes
// (grove_systems::stage::walker_view, through the module: `render.mjs --from D`).
//
//   node web/page/test/distances-pictures.mjs [--out FILE]
//
// FILE defaults to docs/species-distances-page.png. For each cell it prints the tree's pixels
// (drawn alone, coverage over one half) and their mean luma in the page's drawing and in grove's
// sheet (docs/species-distances.png) at the same pixels. Needs the module (bash web/build.sh) and
// Chromium.

import { join, resolve } from 'node:path';
import { openStill, writePng } from '../render.mjs';
import { readPng } from './look.mjs';
import { ROOT } from './harness.mjs';

export const SPECIES = ['oak', 'birch', 'beech', 'scots_pine', 'norway_spruce', 'shrub'];
export const DISTANCES = [3, 10, 30];
export const [W, H] = [320, 240];

/** The species bank's level of detail 1 of `species`. */
export const modelOf = (species) => join(ROOT, `assets/banks/species/${species}-lod1/${species}-lod1.gltf`);

const luma = (d, i) => 0.2126 * d[i] + 0.7152 * d[i + 1] + 0.0722 * d[i + 2];

async function main() {
  const args = process.argv.slice(2);
  const out = args.includes('--out')
    ? resolve(args[args.indexOf('--out') + 1])
    : join(ROOT, 'docs/species-distances-page.png');
  const grove = readPng(join(ROOT, 'docs/species-distances.png'));
  const width = W * DISTANCES.length;
  const data = Buffer.alloc(width * H * SPECIES.length * 4, 255);
  const still = await openStill();
  try {
    console.log('| species | from | tree pixels | mean luma page / grove |\n|---|---|---|---|');
    for (const [row, species] of SPECIES.entries()) {
      for (const [col, from] of DISTANCES.entries()) {
        const img = await still.render(modelOf(species), { width: W, height: H, from });
        const alone = await still.render(modelOf(species), { width: W, height: H, from, background: 'transparent' });
        let [n, page, native] = [0, 0, 0];
        for (let y = 0; y < H; y++) {
          const at = 4 * ((row * H + y) * width + col * W);
          img.data.copy(data, at, 4 * y * W, 4 * (y + 1) * W);
          for (let x = 0; x < W; x++) {
            const i = 4 * (y * W + x);
            if (alone.data[i + 3] < 128) continue;
            n++;
            page += luma(img.data, i);
            native += luma(grove.data, at + 4 * x);
          }
        }
        const share = `${n} (${((100 * n) / (W * H)).toFixed(1)} %)`;
        console.log(
          `| ${species} | ${from} m | ${share} | ${(page / Math.max(n, 1)).toFixed(1)} / ${(native / Math.max(n, 1)).toFixed(1)} |`,
        );
      }
    }
  } finally {
    await still.close();
  }
  writePng(out, { width, height: H * SPECIES.length, data });
  console.log(`wrote ${out}: ${SPECIES.length} species from ${DISTANCES.join(', ')} m through the page's drawing`);
}

await main();
