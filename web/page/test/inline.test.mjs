// The inline preview, with no headset: the mouse is the controller (its ray leaves the head
// through the pointer), M opens the menu, the left button chooses and plants; the events reach
// the server's file.

import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { WEB, fileLines, start, ticks, until } from './harness.mjs';

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

/** Presses the left button at a point of the simulation's frame, a few ticks down. */
async function clickAt(page, simPoint) {
  const { x, y } = await page.evaluate((p) => window.grove.screenPoint(p), simPoint);
  await page.mouse.move(x, y);
  await ticks(page, 3);
  await page.mouse.down();
  await ticks(page, 4);
  await page.mouse.up();
  await ticks(page, 4);
}

test('the inline preview: the mouse chooses a model in the menu and plants it on its target', async () => {
  const { page } = await h.open('participant=P63&task=ray-casting-7&seed=3&quality=low');
  assert.ok(await page.isVisible('#enter-inline'));
  await page.click('#enter-inline');
  await until(page, () => ['task', 'error'].includes(window.grove.state));
  assert.equal(await page.evaluate(() => window.grove.error), null);
  await until(page, () => window.grove.snapshot.task);
  const snap = await page.evaluate(() => window.grove.snapshot);
  const own = snap.trees.length;
  // A target on the ground that the first view shows.
  const size = page.viewportSize();
  const onScreen = [];
  for (const [i, t] of snap.task.targets.entries()) {
    const s = await page.evaluate((p) => window.grove.screenPoint(p), t.position);
    if (t.position[1] === 0 && s.x > 20 && s.x < size.width - 20 && s.y > 20 && s.y < size.height - 20)
      onScreen.push(i);
  }
  assert.ok(onScreen.length > 0, 'a target in view');
  const i = onScreen[0];
  const target = snap.task.targets[i];

  await page.keyboard.down('m');
  await until(page, () => window.grove.snapshot.menu.open);
  await page.keyboard.up('m');
  await clickAt(page, await page.evaluate((m) => window.grove.menuItemPoint(m), target.model));
  await until(
    page,
    (m) => !window.grove.snapshot.menu.open && window.grove.snapshot.menu.current_model === m,
    target.model,
  );

  await clickAt(page, target.position);
  await until(page, (i) => window.grove.snapshot.task.targets[i].satisfied, i, 20000);
  const after = await page.evaluate(() => window.grove.snapshot);
  assert.equal(after.trees.length, own + 1);
  const planted = after.trees.at(-1);
  assert.equal(planted.model, target.model);
  assert.ok(
    Math.hypot(planted.position[0] - target.position[0], planted.position[2] - target.position[2]) < 0.5,
    `${planted.position} near ${target.position}`,
  );

  // The events are on the server's disk: the menu, the choice, the press.
  await until(page, () => window.grove.pending === 0);
  const file = await page.evaluate(() => window.grove.file);
  const kinds = fileLines(join(h.server.dir, file))
    .map((l) => JSON.parse(l))
    .filter((l) => l.type === 'event')
    .map((l) => l.event.kind);
  for (const k of ['start_task', 'controller_pose', 'button_down', 'choose_model', 'button_up'])
    assert.ok(kinds.includes(k), `${k} in ${kinds}`);
  assert.deepEqual(h.foreign(), [], 'every request went to the server');
  assert.deepEqual(h.errors, []);
});

test('the page a headset gets carries no emulator', () => {
  const js = readFileSync(join(WEB, 'dist/page.js'), 'utf8');
  for (const word of ['installRuntime', 'SyntheticEnvironment', 'metaQuest3']) assert.ok(!js.includes(word), word);
  assert.ok(js.includes('immersive-ar'), 'the bundle is the page');
});
