// A scripted participant in immersive-vr (IWER's Quest 3, no room): the study scene's own ground
// (the terrace target stays on its raised plane); a manual-mode drag whose anchor ball turns white
// and whose tree snaps on release; and a page closed in the middle of the task and opened again
// that continues the same file to the end.

import assert from 'node:assert/strict';
import { readdirSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { fileLines, grove, start, until } from './harness.mjs';
import { carry, choose, enterAndStart, grab, plantAll, release } from './participant.mjs';

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

test('immersive-vr: the study scene is the ground, 7 trees planted, the file verified', async () => {
  const { page } = await h.open('participant=P62&task=ray-casting-7&seed=7&quality=low&render_every=4', { xr: true, room: false });
  await enterAndStart(page, 'vr');
  const snap = await page.evaluate(() => window.grove.snapshot);
  assert.equal(await page.evaluate(() => window.grove.floor), null, 'VR uses no floor of a room');
  assert.deepEqual(snap.task.targets.filter((t) => t.moved_to), [], 'no target is moved in the study scene');
  const terrace = snap.task.targets.findIndex((t) => t.position[1] > 0.5);
  assert.ok(terrace >= 0, 'the study scene has its raised target');
  assert.equal(await plantAll(page), 7);
  await until(page, () => window.grove.state === 'done' && window.grove.verification, null, 60000);
  const done = await page.evaluate(() => ({ v: window.grove.verification, file: window.grove.file, s: window.grove.snapshot }));
  assert.equal(done.v.status, 'verified', JSON.stringify(done.v));
  const onTerrace = done.s.trees.filter((t) => Math.abs(t.position[1] - snap.task.targets[terrace].position[1]) < 0.01);
  assert.equal(onTerrace.length, 1, 'one tree stands on the raised plane');
  const file = join(h.server.dir, done.file);
  assert.equal(JSON.parse(fileLines(file)[0]).scene, 'study');
  const replay = grove(['replay', file, '--json']);
  assert.equal(replay.status, 0, replay.stderr);
  const report = JSON.parse(replay.stdout);
  assert.equal(report.task.completed, true);
  assert.deepEqual(report.task.moved_targets ?? [], []);
  assert.deepEqual(h.foreign(), [], 'every request went to the server');
  assert.deepEqual(h.errors, []);
  await page.close();
});

test('manual mode: a dragged tree turns the anchor ball white over the ground and snaps onto it on release', async () => {
  const { page } = await h.open('participant=P64&task=manual-7&seed=8&quality=low&render_every=4', { xr: true, room: false });
  await enterAndStart(page, 'vr');
  const target = (await page.evaluate(() => window.grove.snapshot.task.targets)).find((t) => t.position[1] === 0);
  const own = await page.evaluate(() => window.grove.snapshot.trees.map((t) => t.id));
  await choose(page, target.model);
  await until(page, (n) => window.grove.snapshot.trees.length === n, own.length + 1);
  const spawned = await page.evaluate((own) => window.grove.snapshot.trees.find((t) => !own.includes(t.id)), own);
  assert.equal(spawned.grounded, false, 'a new tree floats in front of the head');
  // Carried high above the target: the ball is green.
  await grab(page, spawned.id);
  const high = await carry(page, spawned.id, [target.position[0], 1.5, target.position[2]]);
  assert.equal(high.anchor_ball.state, 'green');
  assert.equal(await page.evaluate(() => window.grove.overlayBall()), 'green');
  // Lowered to just above the ground: white, and the page draws it white.
  const low = await carry(page, spawned.id, [target.position[0], 0.05, target.position[2]]);
  assert.equal(low.anchor_ball.state, 'white', JSON.stringify(low.anchor_ball));
  assert.equal(await page.evaluate(() => window.grove.overlayBall()), 'white');
  const after = await release(page);
  const tree = after.trees.find((t) => t.id === spawned.id);
  assert.equal(tree.grounded, true, 'the tree snapped');
  // Its lowest point (a little below its origin) on the plane point the ball marked.
  const carried = low.trees.find((t) => t.id === spawned.id).position[1];
  assert.notEqual(tree.position[1], carried, 'the release moved it');
  assert.ok(tree.position[1] > low.anchor_ball.position[1] && tree.position[1] - low.anchor_ball.position[1] < 0.1, `on the ground the ball marked: ${tree.position} / ${low.anchor_ball.position}`);
  assert.deepEqual([tree.position[0], tree.position[2]], [target.position[0], target.position[2]]);
  assert.equal(after.anchor_ball.state, 'hidden');
  assert.equal(after.task.targets.filter((t) => t.satisfied).length, 1, 'its target is satisfied');
  assert.deepEqual(h.errors, []);
  await page.close();
});

test('a page closed in the middle of the task and opened again continues the same file', async () => {
  const query = 'participant=P65&task=ray-casting-7&seed=9&quality=low&render_every=4';
  const first = await h.open(query, { xr: true, room: false });
  await enterAndStart(first.page, 'vr');
  const own = await first.page.evaluate(() => window.grove.snapshot.trees.length);
  assert.equal(await plantAll(first.page, { limit: 3 }), 3);
  const before = await first.page.evaluate(() => ({ file: window.grove.file, trees: window.grove.snapshot.trees }));
  // Wait until the server has every line, then close the page without ending the session.
  await until(first.page, () => window.grove.connection === 'online' && window.grove.pending === 0);
  await first.page.close();

  const again = await h.open(query, { xr: true, room: false, context: first.context });
  assert.match(await again.page.textContent('#title'), new RegExp(`Continue ${before.file}`));
  await again.page.click('#enter-vr');
  await until(again.page, () => ['task', 'error'].includes(window.grove.state), null, 30000);
  const resumed = await again.page.evaluate(() => ({ file: window.grove.file, resumed: window.grove.resumed, s: window.grove.snapshot, error: window.grove.error }));
  assert.equal(resumed.error, null);
  assert.equal(resumed.resumed, true);
  assert.equal(resumed.file, before.file);
  assert.equal(resumed.s.trees.length, own + 3, 'the trees planted before the page closed');
  assert.equal(resumed.s.task.targets.filter((t) => t.satisfied).length, 3);
  // The trees as planted; their sway in the wind (`wind`) goes on with the ticks the page ran since.
  const planted = (trees) => trees.map(({ wind, ...t }) => t);
  assert.deepEqual(planted(resumed.s.trees), planted(before.trees), 'the same trees, bit for bit');
  assert.equal(await plantAll(again.page), 4);
  await until(again.page, () => window.grove.state === 'done' && window.grove.verification, null, 60000);
  assert.equal(await again.page.evaluate(() => window.grove.verification.status), 'verified');
  const files = readdirSync(h.server.dir).filter((f) => f.startsWith('P65-'));
  assert.deepEqual(files, [before.file], 'one file for the participant');
  const replay = grove(['replay', join(h.server.dir, before.file), '--json']);
  assert.equal(replay.status, 0, replay.stderr);
  const report = JSON.parse(replay.stdout);
  assert.equal(report.verified, true);
  assert.equal(report.task.completed, true);
  assert.deepEqual(h.errors, []);
});
