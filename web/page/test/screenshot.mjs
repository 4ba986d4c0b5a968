// docs/headset.png: the page in immersive-ar (IWER's Quest 3 in @iwer/sem's small office) and in
// immersive-vr (the study scene), side by side, each after a scripted participant planted a few
// of the ray-casting task's trees. In AR the task is laid out in the room (the default, a scale
// model on the office's floor behind the participant), so the headset then turns round and looks
// down at it from a step away. Run after the page is built (node web/page/build.mjs):
//
//   node web/page/test/screenshot.mjs OUT.png [TREES] [MODES]
//
// MODES: `ar,vr` (the default), or one of them alone.
// It uses the tests' server, browser and emulator (harness.mjs) and ImageMagick's `convert`.

import { spawnSync } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { start, ticks } from './harness.mjs';
import { aimAt, enterAndStart, plantAll } from './participant.mjs';

/**
 * Turns the headset towards the room's layout: a step (`back` metres) from the middle of the
 * task's targets, on the side the participant started from, `up` metres above the floor, looking
 * down at them. Returns where the controller is to be held from the head: to the right of it,
 * below and forward, along the way the head faces.
 */
async function lookAtLayout(page, { back = 1.3, up = 1.1 } = {}) {
  return page.evaluate(
    ({ back, up }) => {
      const d = window.xrDevice;
      const points = window.grove.snapshot.task.targets.map((t) => window.grove.toSession(t.moved_to ?? t.position));
      const mid = ['x', 'y', 'z'].map((k) => points.reduce((s, p) => s + p[k], 0) / points.length);
      const [dx, dz] = [mid[0] - d.position.x, mid[2] - d.position.z];
      const n = Math.hypot(dx, dz);
      const [fx, fz] = [dx / n, dz / n];
      d.position.set(mid[0] - fx * back, mid[1] + up, mid[2] - fz * back);
      const yaw = Math.atan2(-fx, -fz);
      const pitch = -Math.atan2(up - 0.15, back);
      const [cy, sy, cp, sp] = [Math.cos(yaw / 2), Math.sin(yaw / 2), Math.cos(pitch / 2), Math.sin(pitch / 2)];
      d.quaternion.set(cy * sp, sy * cp, -sy * sp, cy * cp);
      return { x: -fz * 0.3 + fx * 0.2, y: -0.65, z: fx * 0.3 + fz * 0.2 };
    },
    { back, up },
  );
}

const out = process.argv[2];
if (!out) {
  console.error('usage: node web/page/test/screenshot.mjs OUT.png [TREES]');
  process.exit(2);
}
const trees = Number(process.argv[3] ?? 4);
const modes = (process.argv[4] ?? 'ar,vr').split(',');
const scratch = mkdtempSync(join(tmpdir(), 'grove-headset-shot-'));
const h = await start();
try {
  const shots = [];
  for (const [mode, room] of [
    ['ar', true],
    ['vr', false],
  ].filter(([m]) => modes.includes(m))) {
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
    const hand = mode === 'ar' ? await lookAtLayout(page) : { x: 0.3, y: -0.45, z: -0.75 };
    const next = await page.evaluate(() => window.grove.snapshot.task.targets.find((t) => !t.satisfied));
    if (next) await aimAt(page, next.moved_to ?? next.position, hand);
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
