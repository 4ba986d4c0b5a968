// A controller without a squeeze, as Magic Leap 2's is in Wolvic (emulator.mjs's `magicleap`: the
// magicleap-one profile, a trigger and a touchpad), in immersive-vr on the study scene: the
// touchpad held 0.5 s opens the menu, the trigger chooses and plants, a short touchpad click is
// Bumper and removes the tree under the ray; the file verifies and `grove study` names the
// mapping.

import assert from 'node:assert/strict';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { fileLines, grove, start, studyRows, until } from './harness.mjs';
import { aimAt, click, enterAndStart, plantAll } from './participant.mjs';

const DEVICE = { profile: 'magicleap-one', target_ray_mode: 'tracked-pointer', mapping: 'controller-no-squeeze' };

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

test('a controller without a squeeze: the touchpad held opens the menu, a short click removes, the task verifies', async () => {
  const { page } = await h.open('participant=P73&task=ray-casting-7&seed=17&quality=low&render_every=4', {
    xr: true,
    room: false,
    device: 'magicleap',
  });
  await enterAndStart(page, 'vr');
  assert.deepEqual(await page.evaluate(() => window.grove.device), DEVICE);
  const own = await page.evaluate(() => window.grove.snapshot.trees.length);
  assert.equal(await plantAll(page, { limit: 2, menu: 'touchpad' }), 2);
  assert.equal(await page.evaluate(() => window.grove.snapshot.trees.length), own + 2);
  const planted = await page.evaluate((own) => window.grove.snapshot.trees.slice(own), own);
  const last = planted.at(-1);
  await aimAt(page, [last.position[0], last.position[1] + 0.3, last.position[2]]);
  await until(page, (id) => window.grove.snapshot.controller.hit?.entity === id, last.id, 10000);
  await click(page, 'touchpad', 4);
  await until(page, (n) => window.grove.snapshot.trees.length === n, own + 1, 30000);
  assert.equal(await page.evaluate(() => window.grove.snapshot.menu.open), false, 'a short click opened no menu');
  assert.equal(await plantAll(page, { menu: 'touchpad' }), 5);
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
  assert.deepEqual([row.device, row.input_profile, row.status], ['controller-no-squeeze', 'magicleap-one', 'verified']);
  assert.deepEqual(h.errors, []);
  await page.close();
});
