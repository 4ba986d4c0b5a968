// docs/headset-occlusion.png: the page in immersive-ar (IWER's Quest 3 in @iwer/sem's small
// office) with the ray-casting task's shrub planted behind the office's desk (desk.mjs), seen from
// in front of the desk: on the left a headset without depth sensing, on the right with it, the
// desk and its monitor hiding the shrub's lower part. Run after the page is built:
//
//   node web/page/test/occlusion-screenshot.mjs OUT.png
//
// It uses the tests' server, browser and emulator (harness.mjs) and ImageMagick's `convert`.

import { spawnSync } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { shrubBehindDesk } from './desk.mjs';
import { start } from './harness.mjs';

const out = process.argv[2];
if (!out) {
  console.error('usage: node web/page/test/occlusion-screenshot.mjs OUT.png');
  process.exit(2);
}
const scratch = mkdtempSync(join(tmpdir(), 'grove-occlusion-shot-'));
const h = await start();
try {
  const shots = [];
  for (const depth of [false, true]) {
    const file = join(scratch, `${depth}.png`);
    await shrubBehindDesk(h, { depth, quality: 'high', every: 1, size: 480, shot: (page) => page.screenshot({ path: file }) });
    shots.push(file);
  }
  const r = spawnSync('convert', [...shots, '-background', 'white', '-splice', '8x0', '+append', '-chop', '8x0', resolve(out)], { encoding: 'utf8' });
  if (r.status !== 0) throw new Error(`convert: ${r.stderr}`);
  console.log(`${out}: without depth sensing (left) and with it (right)`);
  if (h.errors.length) console.error(h.errors.join('\n'));
} finally {
  await h.close();
  rmSync(scratch, { recursive: true, force: true });
}
