// Real things hide the trees (draw/occlusion.mjs): in immersive-ar on IWER's Quest 3 in
// @iwer/sem's small office, whose depth sensing IWER emulates from the room's meshes, a shrub
// planted behind the office's desk (desk.mjs) loses the pixels the desk hides and keeps the
// others, with a soft edge; the ray's marker on the open floor stays. On the same headset
// without depth sensing nothing is hidden.

import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import { deskRow, shrubBehindDesk } from './desk.mjs';
import { start } from './harness.mjs';

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

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
  const on = await shrubBehindDesk(h, { depth: true });
  const off = await shrubBehindDesk(h, { depth: false });
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
