// Renders grove's oak, beech and shrub beside ez-tree's Oak Medium, Ash Medium and Bush 1 presets
// at the same framing, both through the headset page's drawing (page.mjs), and writes the
// labelled grid (docs/species.md, "Beside ez-tree"):
//
//   node web/compare/run.mjs [--out FILE] [--width W] [--height H]
//
// FILE defaults to docs/species-vs-ez-tree.png; it is written under a temporary name beside it
// and renamed when complete. grove's trees come from GROVE_BIN, else target/release/grove, else
// target/debug/grove. Needs `npm ci` in web/ and Chromium (/usr/bin/chromium, or CHROMIUM).

import { renameSync, rmSync, writeFileSync } from 'node:fs';
import { basename, dirname, join, resolve } from 'node:path';
import { EYE, FOV, PAIRS, ROOT, TARGET, groveBin, loadPair, open } from './compare.mjs';

function usage(message) {
  console.error(`error: ${message}\nusage: node web/compare/run.mjs [--out FILE] [--width W] [--height H]`);
  process.exit(2);
}

const args = process.argv.slice(2);
if (args.includes('--help') || args.includes('-h')) {
  console.log(
    "Renders grove's oak, beech and shrub beside ez-tree's Oak Medium, Ash Medium and Bush 1 presets at the\n" +
      'same framing into a labelled grid (docs/species.md).\n\n' +
      'usage: node web/compare/run.mjs [--out FILE] [--width W] [--height H]\n' +
      '  --out FILE    the PNG to write (default docs/species-vs-ez-tree.png)\n' +
      "  --width W     one cell's width in pixels (default 480)\n" +
      "  --height H    one cell's height in pixels (default 400)",
  );
  process.exit(0);
}
const opts = { out: join(ROOT, 'docs/species-vs-ez-tree.png'), width: 480, height: 400 };
for (let i = 0; i < args.length; i += 2) {
  const [flag, value] = [args[i], args[i + 1]];
  if (value === undefined) usage(`${flag} needs a value`);
  if (flag === '--out') opts.out = resolve(value);
  else if (flag === '--width' || flag === '--height') {
    const n = Number(value);
    if (!Number.isInteger(n) || n < 64 || n > 2048) usage(`${flag} ${value}: a whole number of pixels from 64 to 2048`);
    opts[flag.slice(2)] = n;
  } else usage(`unknown argument ${flag}`);
}
if (!opts.out.endsWith('.png')) usage(`--out ${opts.out}: the file must end in .png`);

const { width: w, height: h } = opts;
let bin;
try {
  bin = groveBin();
} catch (e) {
  usage(e.message);
}
const session = await open({ width: w, height: h });
let png;
try {
  const cells = [];
  const rows = [];
  for (const pair of PAIRS) {
    const t0 = Date.now();
    const { height, grove, ez, view } = await loadPair(session, pair, { aspect: w / h, bin });
    const left = await session.call('render', 'grove', view, w, h);
    const right = await session.call('render', 'ez', view, w, h);
    cells.push([left, right]);
    rows.push([
      pair.label[0],
      `beside ${pair.ez}`,
      `${height.toFixed(1)} m tall`,
      `camera ${view.distance.toFixed(1)} m away`,
      `grove ${Math.round(grove.triangles / 1000)}k triangles`,
      `ez-tree ${Math.round(ez.triangles / 1000)}k`,
    ]);
    const tone = [];
    for (const handle of ['grove', 'ez']) {
      const c = await session.call('colours', handle, view, w, h);
      tone.push(
        `${handle} ${c.pixels} px, mean sRGB (${c.mean.map((v) => v.toFixed(0)).join(', ')}), luma ${c.luma.toFixed(1)}, ${(c.dark * 100).toFixed(1)} % near black`,
      );
    }
    console.log(
      `${pair.grove} / ${pair.ez}: ${height.toFixed(2)} m, camera at ${view.distance.toFixed(2)} m, ${grove.triangles} and ${ez.triangles} triangles, ${((Date.now() - t0) / 1000).toFixed(1)} s; the trees' pixels: ${tone.join('; ')}`,
    );
  }
  const title = `grove (left) and ez-tree 1.1.0 (right) through the headset page's drawing, at the grove tree's height; eye ${EYE} m, ${FOV}° field of view, aim ${TARGET * 100} % up`;
  const url = await session.call('grid', cells, ['grove', 'ez-tree'], rows, w, h, title);
  png = Buffer.from(url.slice(url.indexOf(',') + 1), 'base64');
  if (session.foreign.length) throw new Error(`the page asked for ${session.foreign.join(', ')}`);
} catch (e) {
  await session.close();
  console.error(`error: ${e.message}`);
  process.exit(1);
}
await session.close();

const tmp = join(dirname(opts.out), `.${basename(opts.out, '.png')}.tmp-${process.pid}.png`);
try {
  writeFileSync(tmp, png);
  renameSync(tmp, opts.out);
} catch (e) {
  rmSync(tmp, { force: true });
  console.error(`error: ${opts.out}: cannot write (${e.message})`);
  process.exit(2);
}
console.log(`wrote ${opts.out} (${png.length} bytes)`);
