// Headsets beside the Quest 3, each through the page's own input layer, each file verified with
// `grove replay` and its header naming the device:
// - IWER's Meta Quest 2 (Touch controllers, profile oculus-touch-v3; no depth sensing) in AR in the
//   small office: the task laid out on its floor, planted by the trigger, one tree removed by the
//   squeeze, finished from the menu; `grove study` names the controller.
// - A Pico 4 (a double: its controllers as the pico-4 profile, no hit test, no depth) in AR: the
//   page draws the controller from the profile it ships, plants, removes, finishes from the menu.
// - A controller without a squeeze, as Magic Leap 2's is in Wolvic (a double: magicleap-one, a
//   trigger and a touchpad), in VR on the study scene: the touchpad held 0.5 s opens the menu, a
//   short click is Bumper and removes the tree under the ray, the task finished from the menu.

import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import { start, studyRows, until, verified } from './harness.mjs';
import { aimAt, click, enterAndStart, finishTask, plantAll } from './participant.mjs';

const controller = (profile, mapping = 'controller') => ({ profile, target_ray_mode: 'tracked-pointer', mapping });

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

/** Opens the task on `device` in `mode` and holds that the page names `want` as the device. */
async function begin(query, device, mode, want) {
  const { page } = await h.open(`${query}&task=ray-casting-7&quality=low&render_every=4`, {
    xr: true,
    room: mode === 'ar',
    device,
  });
  await enterAndStart(page, mode);
  await until(page, () => window.grove.snapshot?.task);
  assert.deepEqual(await page.evaluate(() => window.grove.device), want);
  if (mode === 'ar') assert.match(await page.evaluate(() => window.grove.floor.source), /^plane detection/);
  return page;
}

/** Plants `n` trees (the menu opened with `menu`), then removes the last with `remove` (`hold` ticks). */
async function plantAndRemove(page, n, { menu = 'b-button', remove = 'squeeze', hold = 4 } = {}) {
  const before = await page.evaluate(() => window.grove.snapshot.trees.length);
  assert.equal(await plantAll(page, { limit: n, menu }), n);
  const last = await page.evaluate(() => window.grove.snapshot.trees.at(-1));
  // Just above its base: the room layout's trees are a few centimetres tall.
  await aimAt(page, [last.position[0], last.position[1] + 0.05, last.position[2]]);
  await until(page, (id) => window.grove.snapshot.controller.hit?.entity === id, last.id, 10000);
  await click(page, remove, hold);
  await until(page, (k) => window.grove.snapshot.trees.length === k, before + n - 1, 30000);
  assert.equal(await page.evaluate(() => window.grove.snapshot.menu.open), false, 'the removal opened no menu');
}

test("a Quest 2 in AR: the task laid out in the room, planted by its Touch controller's trigger, a tree removed by its squeeze, finished, verified", async () => {
  const device = controller('oculus-touch-v3');
  const page = await begin('participant=P72&seed=16', 'quest2', 'ar', device);
  assert.match(await page.evaluate(() => navigator.userAgent), /Quest 2/, 'the emulated headset is the Quest 2');
  await plantAndRemove(page, 3);
  await finishTask(page);
  const report = await verified(page, h.server.dir, device);
  // A target once met stays met (systems/src/systems/task.rs): three of seven.
  assert.deepEqual([report.task.completed, report.task.trees.length], [false, 3]);
  assert.equal(report.task.error_kinds.removals, 1);
  const row = studyRows(h.server.dir).find((r) => r.file === report.name);
  assert.deepEqual(
    [row.device, row.target_ray_mode, row.input_profile, row.status],
    ['controller', 'tracked-pointer', 'oculus-touch-v3', 'verified'],
  );
  assert.match(row.layout, /^room:/);
  assert.deepEqual(h.errors, []);
  await page.close();
});

test('a Pico 4 in AR: its controller drawn from the shipped pico-4 profile, trees planted and one removed, finished from the menu, verified', async () => {
  const device = controller('pico-4');
  const page = await begin('participant=P74&seed=18', 'pico4', 'ar', device);
  await until(page, () => window.grove.profiles().includes('pico-4'), null, 30000);
  await plantAndRemove(page, 2);
  await finishTask(page);
  const report = await verified(page, h.server.dir, device);
  assert.equal(report.task.completed, false, 'finished with five targets open');
  assert.equal(report.task.error_kinds.removals, 1);
  assert.deepEqual(h.foreign(), [], 'the profile came from the server');
  assert.deepEqual(h.errors, []);
  await page.close();
});

test('a controller without a squeeze: the touchpad held opens the menu, a short click removes, the file verifies', async () => {
  const device = controller('magicleap-one', 'controller-no-squeeze');
  const page = await begin('participant=P73&seed=17', 'magicleap', 'vr', device);
  // The click is timed by the page's clock: two ticks stay well under 0.5 s on a loaded machine too.
  await plantAndRemove(page, 2, { menu: 'touchpad', remove: 'touchpad', hold: 2 });
  await finishTask(page, 'touchpad');
  const report = await verified(page, h.server.dir, device);
  assert.deepEqual([report.task.completed, report.task.trees.length], [false, 2]);
  assert.equal(report.task.error_kinds.removals, 1);
  const row = studyRows(h.server.dir).find((r) => r.file === report.name);
  assert.deepEqual([row.device, row.input_profile, row.status], ['controller-no-squeeze', 'magicleap-one', 'verified']);
  assert.deepEqual(h.errors, []);
  await page.close();
});
