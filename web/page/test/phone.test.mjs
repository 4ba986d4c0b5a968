// A phone in AR (a `screen` input source, as Android Chrome gives it; IWER does not emulate it,
// so emulator.mjs's test doubles of XRInputSource and of the hit test for transient input stand
// in, read by the page's own input layer) over IWER's small office: a tap starts the task, taps
// choose in the menu and plant, the touch bar's Menu and Remove work and a tap on them plants
// nothing, and in the manual task a tree dragged by the finger comes down onto its target and
// snaps, and the Scale pad grows it; both files verify and `grove study` says they were made on a phone's screen.

import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import { fileLines, start, studyRows, until, verified } from './harness.mjs';
import { frames } from './participant.mjs';
import { chooseIn, drag, enterAndTouch, openMenu, press, tap } from './doubles.mjs';

const DEVICE = { profile: 'generic-touchscreen', target_ray_mode: 'screen', mapping: 'screen' };

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

async function finish(page) {
  await openMenu(page, 'screen');
  await chooseIn(page, 'finish', 'screen');
  return verified(page, h.server.dir, DEVICE);
}

test("a phone: taps plant, the touch bar's taps never reach the scene, Remove takes the tree last tapped", async () => {
  const { page } = await h.open('participant=P70&task=ray-casting-7&seed=14&quality=low&render_every=4', {
    xr: true,
    room: true,
    device: 'phone',
    width: 360,
    height: 640,
  });
  await page.click('#enter-ar');
  await until(page, () => window.grove.state === 'instructions' && window.xrDevice.activeSession, null, 30000);
  assert.equal(await page.textContent('#message'), 'Tap the scene to start.');
  assert.equal(await page.isVisible('#touch-menu'), true, "the touch bar shows over the camera's view");
  await frames(page, 10);
  await tap(page, [0, 0, -2]); // the tap that starts the task
  await until(page, () => window.grove.snapshot?.task, null, 30000);
  assert.equal(await page.evaluate(() => window.grove.error), null);
  assert.deepEqual(await page.evaluate(() => window.grove.device), DEVICE);
  const targets = await page.evaluate(() => window.grove.snapshot.task.targets);
  assert.deepEqual(
    await page.evaluate(() => window.grove.snapshot.trees.length),
    0,
    'the tap that started the task planted nothing',
  );
  for (const i of [3, 4]) {
    await openMenu(page, 'screen');
    await chooseIn(page, targets[i].model, 'screen');
    await tap(page, targets[i].position);
    await until(page, (i) => window.grove.snapshot.task.targets[i].satisfied, i, 30000);
  }
  assert.equal(await page.evaluate(() => window.grove.snapshot.trees.length), 2);
  // A press on Menu makes a screen touch too (as a phone's browser does), right over a target: the
  // bar claims it, the menu opens, nothing is planted; its beforexrselect is cancelled.
  const cancelled = await page.evaluate(() => {
    const e = new Event('beforexrselect', { bubbles: true, cancelable: true });
    document.getElementById('touch-menu').dispatchEvent(e);
    return e.defaultPrevented;
  });
  assert.equal(cancelled, true);
  await press(page, '#touch-menu', 8, () => page.evaluate((p) => window.xrDouble.touch(p), targets[5].position));
  await page.evaluate(() => window.xrDouble.lift());
  await frames(page, 5);
  const after = await page.evaluate(() => window.grove.snapshot);
  assert.equal(after.menu.open, true, 'Menu opened the menu');
  assert.equal(after.trees.length, 2, 'the touch on the bar planted nothing');
  assert.equal(after.controller.buttons[0], false, 'and never pressed the trigger');
  await tap(page, [0, 0, 4]); // a tap off the menu's items closes it
  await until(page, () => !window.grove.snapshot.menu.open, null, 30000);
  // Remove: on the tree last tapped.
  await tap(page, [targets[4].position[0], 0.05, targets[4].position[2]]);
  await until(page, () => window.grove.snapshot.bounding_box, null, 30000);
  await press(page, '#touch-remove');
  await until(page, () => window.grove.snapshot.trees.length === 1, null, 30000);
  const report = await finish(page);
  assert.equal(report.task.error_kinds.removals, 1);
  assert.deepEqual(report.device, DEVICE);
  assert.deepEqual(h.errors, []);
  await page.close();
});

test('a phone in the manual task: a tree dragged by the finger comes down onto its target and snaps', async () => {
  const { page } = await h.open('participant=P71&task=manual-7&seed=15&quality=low&render_every=4', {
    xr: true,
    room: true,
    device: 'phone',
    width: 360,
    height: 640,
  });
  await enterAndTouch(page, 'ar', 'screen');
  const target = (await page.evaluate(() => window.grove.snapshot.task.targets))[2];
  await openMenu(page, 'screen');
  await chooseIn(page, target.model, 'screen');
  const box = await page.evaluate(() => window.grove.snapshot.bounding_box);
  assert.ok(box, 'the new tree is selected');
  let ball = null;
  await drag(page, box.center, target.position, {
    before: async () => {
      ball = await page.evaluate(() => window.grove.snapshot.anchor_ball.state);
    },
  });
  assert.equal(ball, 'white', 'the tree came down to the floor under the finger');
  await until(page, (t) => window.grove.snapshot.task.targets[t].satisfied, 2, 30000).catch(async (e) => {
    const s = await page.evaluate(() => window.grove.snapshot);
    throw new Error(
      `${e.message}: tree ${JSON.stringify(s.trees)}, target ${target.position}, ball ${JSON.stringify(s.anchor_ball)}`,
    );
  });
  const tree = await page.evaluate((id) => window.grove.snapshot.trees.find((x) => x.id === id), box.tree);
  assert.equal(tree.grounded, true);
  assert.ok(
    Math.hypot(tree.position[0] - target.position[0], tree.position[2] - target.position[2]) < 0.01,
    `${tree.position} on ${target.position}`,
  );
  // The Scale pad: a thumb dragged up grows the selected tree, which stays on the floor; the
  // pad's touch plants and selects nothing.
  const pad = await page.locator('#touch-scale').boundingBox();
  const [px, py] = [pad.x + pad.width / 2, pad.y + pad.height / 2];
  await page.mouse.move(px, py);
  await page.mouse.down();
  await page.mouse.move(px, py - 100, { steps: 4 });
  await frames(page, 30);
  await page.mouse.up();
  await frames(page, 5);
  const grown = await page.evaluate(() => window.grove.snapshot.trees);
  assert.equal(grown.length, 1, 'the pad planted nothing');
  assert.ok(grown[0].scale > tree.scale * 1.1, `scale ${tree.scale} -> ${grown[0].scale}`);
  assert.equal(grown[0].grounded, true);
  assert.equal(grown[0].selected, true);
  const report = await finish(page);
  assert.equal(report.task.trees.length, 1);
  const values = fileLines(report.path)
    .map((l) => JSON.parse(l).event)
    .filter((e) => e?.kind === 'scale_axis')
    .map((e) => e.value);
  assert.ok(values.length >= 2 && values.at(-1) === 0 && values.some((v) => v > 0.5), `${values}`);
  const row = studyRows(h.server.dir).find((r) => r.file === report.name);
  assert.deepEqual(
    [row.device, row.target_ray_mode, row.input_profile, row.status],
    ['screen', 'screen', 'generic-touchscreen', 'verified'],
  );
  assert.match(row.layout, /^room:/);
  assert.deepEqual(h.errors, []);
});
