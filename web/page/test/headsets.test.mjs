// Headsets beside the Quest 3, in AR in IWER's small office. IWER's Meta Quest 2 (Touch
// controllers, profile oculus-touch-v3; no depth sensing): the task is laid out on the office's
// floor, planted by the controller's trigger, one tree removed by its squeeze; the file verifies
// with `grove replay`, and `grove study` names the Quest 2's controller. A Pico 4 (a double: its
// controllers as the pico-4 profile, no hit test, no depth): the page draws the controller from
// the profile it ships, plants, removes, finishes from the menu, and the file verifies.

import assert from 'node:assert/strict';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { fileLines, grove, start, studyRows, until } from './harness.mjs';
import { aimAt, click, enterAndStart, finishTask, plantAll } from './participant.mjs';

const DEVICE = { profile: 'oculus-touch-v3', target_ray_mode: 'tracked-pointer', mapping: 'controller' };

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

test("a Quest 2 in AR: the task laid out in the room, planted by its Touch controller's trigger, a tree removed by its squeeze, verified", async () => {
  const { page } = await h.open('participant=P72&task=ray-casting-7&seed=16&quality=low&render_every=4', {
    xr: true,
    room: true,
    device: 'quest2',
  });
  await enterAndStart(page, 'ar');
  await until(page, () => window.grove.snapshot?.task);
  const begun = await page.evaluate(() => ({
    device: window.grove.device,
    floor: window.grove.floor,
    depth: window.grove.occlusion ?? null,
    agent: navigator.userAgent,
  }));
  assert.match(begun.agent, /Quest 2/, 'the emulated headset is the Quest 2');
  assert.deepEqual(begun.device, DEVICE);
  assert.match(begun.floor.source, /^plane detection/, 'the office has a floor plane');
  // Three trees, then the last one removed with the squeeze (Bumper), then the rest.
  assert.equal(await plantAll(page, { limit: 3 }), 3);
  const last = await page.evaluate(() => window.grove.snapshot.trees.at(-1));
  await aimAt(page, [last.position[0], last.position[1] + 0.05, last.position[2]]);
  await click(page, 'squeeze');
  await until(page, () => window.grove.snapshot.trees.length === 2, null, 30000);
  // A target once met stays met (systems/src/systems/task.rs): four are left.
  assert.equal(await plantAll(page), 4);
  await until(page, () => window.grove.state === 'done' && window.grove.verification, null, 60000);
  const done = await page.evaluate(() => ({ v: window.grove.verification, file: window.grove.file }));
  assert.equal(done.v.status, 'verified', JSON.stringify(done.v));
  const path = join(h.server.dir, done.file);
  assert.deepEqual(JSON.parse(fileLines(path)[0]).device, DEVICE);
  const replay = grove(['replay', path, '--json']);
  assert.equal(replay.status, 0, replay.stderr);
  const report = JSON.parse(replay.stdout);
  assert.equal(report.task.completed, true);
  assert.equal(report.task.error_kinds.removals, 1);
  const row = studyRows(h.server.dir).find((r) => r.file === done.file);
  assert.deepEqual(
    [row.device, row.target_ray_mode, row.input_profile, row.status],
    ['controller', 'tracked-pointer', 'oculus-touch-v3', 'verified'],
  );
  assert.match(row.layout, /^room:/);
  assert.deepEqual(h.errors, []);
  await page.close();
});

test('a Pico 4 in AR: its controller drawn from the shipped pico-4 profile, trees planted and one removed, finished from the menu, verified', async () => {
  const device = { profile: 'pico-4', target_ray_mode: 'tracked-pointer', mapping: 'controller' };
  const { page } = await h.open('participant=P74&task=ray-casting-7&seed=18&quality=low&render_every=4', {
    xr: true,
    room: true,
    device: 'pico4',
  });
  await enterAndStart(page, 'ar');
  await until(page, () => window.grove.snapshot?.task);
  assert.deepEqual(await page.evaluate(() => window.grove.device), device);
  assert.match(await page.evaluate(() => window.grove.floor.source), /^plane detection/);
  await until(page, () => window.grove.profiles().includes('pico-4'), null, 30000);
  assert.equal(await plantAll(page, { limit: 2 }), 2);
  const last = await page.evaluate(() => window.grove.snapshot.trees.at(-1));
  await aimAt(page, [last.position[0], last.position[1] + 0.05, last.position[2]]);
  await until(page, (id) => window.grove.snapshot.controller.hit?.entity === id, last.id, 10000);
  await click(page, 'squeeze');
  await until(page, () => window.grove.snapshot.trees.length === 1, null, 30000);
  await finishTask(page);
  await until(page, () => window.grove.state === 'done' && window.grove.verification, null, 60000);
  const done = await page.evaluate(() => ({ v: window.grove.verification, file: window.grove.file }));
  assert.equal(done.v.status, 'verified', JSON.stringify(done.v));
  const path = join(h.server.dir, done.file);
  assert.deepEqual(JSON.parse(fileLines(path)[0]).device, device);
  const report = JSON.parse(grove(['replay', path, '--json']).stdout);
  assert.equal(report.task.completed, false, 'finished with five targets open');
  assert.equal(report.task.error_kinds.removals, 1);
  assert.deepEqual(h.foreign(), [], 'the profile came from the server');
  assert.deepEqual(h.errors, []);
  await page.close();
});
