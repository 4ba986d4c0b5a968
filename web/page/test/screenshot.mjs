// docs/headset.png: the page in immersive-ar (IWER's Quest 3 in @iwer/sem's small office) and in
// immersive-vr (the study scene), side by side, each after a scripted participant planted a few
// of the ray-casting task's trees. Run after the page is built (node web/page/build.mjs):
//
//   node web/page/test/screenshot.mjs OUT.png [TREES]
//
// It uses the tests' server, browser and emulator (harness.mjs) and ImageMagick's `convert`.

import { spawnSync } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { start, ticks } from './harness.mjs';
import { aimAt, enterAndStart, plantAll } from './participant.mjs';

const out = process.argv[2];
if (!out) {
  console.error('usage: node web/page/test/screenshot.mjs OUT.png [TREES]');
  process.exit(2);
}
const trees = Number(process.argv[3] ?? 4);
const scratch = mkdtempSync(join(tmpdir(), 'grove-headset-shot-'));
const h = await start();
try {
  const shots = [];
  for (const [mode, room] of [
    ['ar', true],
    ['vr', false],
  ]) {
    const { page } = await h.open(`participant=SHOT${mode}&task=ray-casting-7&seed=1`, {
      xr: true,
      room,
      width: 640,
      height: 640,
    });
    await enterAndStart(page, mode);
    await plantAll(page, { limit: trees });
    // Point at the next target with the arm stretched out, so that the ray and its marker show
    // and the task panel above the hand leaves the view open.
    const next = await page.evaluate(() => window.grove.snapshot.task.targets.find((t) => !t.satisfied));
    if (next) await aimAt(page, next.moved_to ?? next.position, { x: 0.3, y: -0.45, z: -0.75 });
    await ticks(page, 10);
    const file = join(scratch, `${mode}.png`);
    await page.screenshot({ path: file });
    shots.push(file);
    await page.close();
  }
  const r = spawnSync(
    'convert',
    [...shots, '-background', 'white', '-splice', '8x0', '+append', '-chop', '8x0', resolve(out)],
    { encoding: 'utf8' },
  );
  if (r.status !== 0) throw new Error(`convert: ${r.stderr}`);
  console.log(`${out}: AR (left) and VR (right), ${trees} trees each`);
  if (h.errors.length) console.error(h.errors.join('\n'));
} finally {
  await h.close();
  rmSync(scratch, { recursive: true, force: true });
}
