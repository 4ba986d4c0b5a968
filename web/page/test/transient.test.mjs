// Gaze and pinch (`transient-pointer`, as Apple Vision Pro's Safari gives it; IWER does not
// emulate it, so emulator.mjs's test doubles of XRInputSource stand in, read by the page's own
// input layer): in immersive-vr a participant plants trees where they look (the right hand's
// pinch), opens the menu with the left hand's held pinch, and in the manual task drags a tree by
// moving the pinching hand, the ray fixed where the gaze began; both files verify and `grove
// study` says they were made with gaze and pinch.

import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import { start, studyRows, until, verified } from './harness.mjs';
import { frames } from './participant.mjs';
import { chooseIn, enterAndTouch, openMenu, pinch } from './doubles.mjs';

const DEVICE = { profile: 'generic-button', target_ray_mode: 'transient-pointer', mapping: 'transient-pointer' };

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

/** Ends the task from the menu and waits for the server's verification; returns the file's replay report. */
async function finish(page) {
  await openMenu(page, 'pinch');
  await chooseIn(page, 'finish', 'pinch');
  return verified(page, h.server.dir, DEVICE);
}

test('gaze and pinch: trees planted where the eyes look, the menu from the left hand, the file verified', async () => {
  const { page } = await h.open('participant=P68&task=ray-casting-7&seed=12&quality=low&render_every=4', {
    xr: true,
    room: false,
    device: 'visionpro',
  });
  await enterAndTouch(page, 'vr', 'pinch');
  assert.equal(await page.evaluate(() => window.grove.error), null);
  assert.deepEqual(await page.evaluate(() => window.grove.device), DEVICE);
  const targets = await page.evaluate(() => window.grove.snapshot.task.targets);
  const own = await page.evaluate(() => window.grove.snapshot.trees.length);
  for (const i of [1, 0]) {
    await openMenu(page, 'pinch');
    await chooseIn(page, targets[i].model, 'pinch');
    await pinch(page, targets[i].position);
    await until(page, (i) => window.grove.snapshot.task.targets[i].satisfied, i, 30000);
  }
  assert.equal(
    await page.evaluate(() => window.grove.snapshot.trees.length),
    own + 2,
    "two trees, none planted by the menu's pinches",
  );
  // A short left pinch is Bumper, at its gaze: it removes the tree looked at.
  // Held two frames: the page times the pinch by the clock, and a loaded machine's five frames can pass 0.5 s (Menu).
  await pinch(page, targets[0].position, 'left', 2);
  await until(page, (n) => window.grove.snapshot.trees.length === n, own + 1, 30000);
  const report = await finish(page);
  assert.equal(report.task.trees.length, 2, 'both targets were satisfied (a removal does not take that back)');
  assert.equal(report.task.error_kinds.removals, 1);
  assert.deepEqual(report.device, DEVICE);
  assert.deepEqual(h.errors, []);
  await page.close();
});

test('gaze and pinch in the manual task: a tree dragged by the pinching hand snaps onto its target', async () => {
  const { page } = await h.open('participant=P69&task=manual-7&seed=13&quality=low&render_every=4', {
    xr: true,
    room: false,
    device: 'visionpro',
  });
  await enterAndTouch(page, 'vr', 'pinch');
  const target = (await page.evaluate(() => window.grove.snapshot.task.targets)).find((x) => x.position[1] === 0);
  const own = await page.evaluate(() => window.grove.snapshot.trees.map((x) => x.id));
  await openMenu(page, 'pinch');
  await chooseIn(page, target.model, 'pinch');
  const spawned = await page.evaluate((own) => window.grove.snapshot.trees.find((x) => !own.includes(x.id)), own);
  assert.ok(spawned && !spawned.grounded, 'a new tree floats in front of the head');
  // Look at the tree and pinch: grabbed. The hand then carries it, the gaze ray moving with the grip.
  const box = await page.evaluate(() => window.grove.snapshot.bounding_box);
  const grip = [0.2, 1.2, 5.6];
  await page.evaluate(({ p, grip }) => window.xrDouble.pinch(p, 'right', grip), { p: box.center, grip });
  await frames(page, 6);
  const to = [target.position[0], 0.1, target.position[2]];
  const d = to.map((v, i) => v - spawned.position[i]);
  for (let k = 1; k <= 40; k++) {
    await page.evaluate(
      (g) => window.xrDouble.moveGrip(g),
      grip.map((v, i) => v + (d[i] * k) / 40),
    );
    await frames(page, 2);
  }
  await until(page, () => window.grove.snapshot.anchor_ball.state === 'white', null, 30000);
  const carried = await page.evaluate((id) => window.grove.snapshot.trees.find((x) => x.id === id), spawned.id);
  assert.ok(
    Math.hypot(carried.position[0] - to[0], carried.position[2] - to[2]) < 0.02,
    `carried to ${carried.position}, not ${to}`,
  );
  await page.evaluate(() => window.xrDouble.lift('right'));
  await until(page, (id) => window.grove.snapshot.trees.find((x) => x.id === id)?.grounded, spawned.id, 30000);
  assert.equal(
    await page.evaluate(() => window.grove.snapshot.task.targets.filter((x) => x.satisfied).length),
    1,
    'its target is satisfied',
  );
  const report = await finish(page);
  assert.equal(report.task.trees.length, 1);
  const row = studyRows(h.server.dir).find((r) => r.file === report.name);
  assert.deepEqual(
    [row.device, row.target_ray_mode, row.status],
    ['transient-pointer', 'transient-pointer', 'verified'],
  );
  assert.deepEqual(h.errors, []);
});
