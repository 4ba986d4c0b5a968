// Real things hide the trees (draw/occlusion.mjs): in immersive-ar on IWER's Quest 3 in
// @iwer/sem's small office, whose depth sensing IWER emulates from the room's meshes, a shrub
// planted behind the office's desk loses the pixels the desk hides and keeps the others, with a
// soft edge; the shadow on the floor in front of the desk stays. On the same headset without
// depth sensing nothing is hidden.

import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import { start, ticks, until } from './harness.mjs';
import { aimAt, choose, click, enterAndStart, frames } from './participant.mjs';

/** The ray-casting task's shrub target, the simulation's frame. */
const SHRUB = [-3, 0, -9.5];
/** Where the shrub is to stand in the office (local-floor): behind the front of its desk (the desk spans z −1.03 to −0.27, its top at 0.75 m). */
const BEHIND_DESK = { x: 0.06, z: -0.65 };
/** Where the participant presses the trigger, facing −Z: the task's targets are laid out from there, the shrub's behind the desk. */
const START = { x: BEHIND_DESK.x - SHRUB[0], y: 1.6, z: BEHIND_DESK.z - SHRUB[2] + 6 };
/** Where the headset then looks at the desk from, level, facing −Z. */
const VIEW = { x: 0.06, y: 1.1, z: 1.0 };
/** The row of the desk's front top edge (0.75 m high at z −0.27) on a canvas of `h` rows, from the top, for IWER's 90° field of view. */
const deskRow = (h) => Math.round((h / 2) * (1 + (VIEW.y - 0.75) / (VIEW.z + 0.27)));
/** Open floor in front of the desk (local-floor), and the pitch that looks down at it from (0.06, 1.6, 1.1). */
const FLOOR = { x: 0.06, z: 0.6 };
const DOWN = -1.1;
/** A point of the office's floor in the simulation's frame (the offset of START facing −Z). */
const sim = (p) => [p.x - START.x, 0, p.z - START.z + 6];

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

/**
 * The page's own canvas (its alpha is what the page drew over the room, rows from the top),
 * read in a frame the page drew (it draws one in four while the run goes on: render_every=4).
 */
function readCanvas(page) {
  return page.evaluate(
    () =>
      new Promise((resolve) => {
        const session = window.xrDevice.activeSession;
        const read = () => {
          if (window.grove.frames % 4 !== 0) return session.requestAnimationFrame(read);
          const gl = document.getElementById('canvas').getContext('webgl2');
          const [w, h] = [gl.drawingBufferWidth, gl.drawingBufferHeight];
          const px = new Uint8Array(w * h * 4);
          gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
          const alpha = new Array(w * h);
          for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) alpha[y * w + x] = px[((h - 1 - y) * w + x) * 4 + 3];
          resolve({ w, h, alpha });
        };
        session.requestAnimationFrame(read);
      }),
  );
}

/** Places the headset at `at`, pitched by `pitch` radians, and the controller at `hand` aiming at `aim` (the simulation's frame). */
async function look(page, at, pitch, hand, aim) {
  await page.evaluate(
    ({ at, pitch }) => {
      const d = window.xrDevice;
      d.position.set(at.x, at.y, at.z);
      d.quaternion.set(Math.sin(pitch / 2), 0, 0, Math.cos(pitch / 2));
    },
    { at, pitch },
  );
  await aimAt(page, aim, hand);
}

/**
 * Plants the shrub behind the desk, then reads the page's canvas looking at the desk, and looking
 * down at the open floor in front of it with the ray's marker on the floor.
 */
async function shrubBehindDesk(depth) {
  const { page } = await h.open('participant=OCC&task=ray-casting-7&seed=1&quality=low&render_every=4', { xr: true, room: true, depth, width: 320, height: 320 });
  await page.evaluate((p) => window.xrDevice.position.set(p.x, p.y, p.z), START);
  await enterAndStart(page, 'ar');
  await until(page, () => window.grove.snapshot?.task);
  const targets = await page.evaluate(() => window.grove.snapshot.task.targets);
  const i = targets.findIndex((t) => t.model === 'shrub-billboard');
  assert.deepEqual(targets[i].position, SHRUB, 'the task lays its shrub where the test stands it');
  await choose(page, 'shrub-billboard');
  await aimAt(page, SHRUB);
  await click(page, 'trigger');
  await until(page, (i) => window.grove.snapshot.task.targets[i].satisfied, i, 20000);
  // At the desk, the controller low and behind the head, its ray on the ground beside the view.
  await look(page, VIEW, 0, { x: 0.3, y: -0.5, z: 0.6 }, sim({ x: 1.1, z: 1.3 }));
  const desk = await readCanvas(page);
  // Looking down at the open floor in front of the desk, the ray's marker on it.
  await look(page, { x: 0.06, y: 1.6, z: 1.1 }, DOWN, { x: 0.15, y: -0.3, z: -0.25 }, sim(FLOOR));
  const floor = await readCanvas(page);
  const occlusion = await page.evaluate(() => window.grove.occlusion);
  await page.close();
  return { desk, floor, occlusion };
}

/** Pixels drawn (alpha over 250) and partly drawn (alpha 5 to 250) in rows [top, bottom) and columns [left, right). */
function coverage({ w, alpha }, top, bottom, left = 0, right = w) {
  let full = 0;
  let part = 0;
  for (let y = top; y < bottom; y++) {
    for (let x = left; x < right; x++) {
      const a = alpha[y * w + x];
      if (a > 250) full++;
      else if (a >= 5) part++;
    }
  }
  return { full, part };
}

/** Pixels drawn whole without depth sensing and partly with it: the soft edge. */
function softened(on, off) {
  let n = 0;
  for (let i = 0; i < on.alpha.length; i++) if (off.alpha[i] > 250 && on.alpha[i] >= 5 && on.alpha[i] <= 250) n++;
  return n;
}

test('a shrub behind the office desk loses the pixels the desk hides, with a soft edge; the floor keeps what lies on it; without depth sensing nothing is hidden', async () => {
  const on = await shrubBehindDesk(true);
  const off = await shrubBehindDesk(false);
  assert.deepEqual(on.occlusion, { usage: 'gpu-optimized', format: 'float32' }, "the session's depth sensing is in use");
  assert.equal(off.occlusion, null, 'a headset without depth sensing hides nothing');
  const { w, h: rows } = on.desk;
  const row = deskRow(rows);
  // Below the desk's top its front is nearer than the shrub: hidden with depth sensing.
  const below = [coverage(on.desk, row + 4, rows), coverage(off.desk, row + 4, rows)];
  // Above it the shrub stands before the wall (the desk's monitor hides a little of it).
  const above = [coverage(on.desk, 0, row - 4), coverage(off.desk, 0, row - 4)];
  const report = JSON.stringify({ row, below, above });
  assert.ok(below[1].full > 3000, `without depth sensing the shrub is drawn below the desk's top: ${report}`);
  assert.ok(below[0].full < 0.5 * below[1].full, `with it the desk hides most of that: ${report}`);
  assert.ok(above[1].full > 2000 && above[0].full > 0.85 * above[1].full, `and keeps the shrub above the desk: ${report}`);
  const soft = softened(on.desk, off.desk);
  const hidden = below[1].full - below[0].full;
  assert.ok(soft >= 100 && soft < hidden, `the hidden part's outline is soft: ${soft} pixels partly kept, ${hidden} hidden (${report})`);
  // The ray's marker on the open floor (in the middle of the lower half) stands on the sensed floor: kept whole.
  const marker = [coverage(on.floor, rows / 2, rows * 0.7, w * 0.35, w * 0.65), coverage(off.floor, rows / 2, rows * 0.7, w * 0.35, w * 0.65)];
  assert.ok(marker[1].full > 50, `the marker is drawn: ${JSON.stringify(marker)}`);
  assert.ok(Math.abs(marker[0].full - marker[1].full) <= 0.05 * marker[1].full, `the sensed floor does not hide the marker on it: ${JSON.stringify(marker)}`);
  assert.deepEqual(h.errors, []);
});
