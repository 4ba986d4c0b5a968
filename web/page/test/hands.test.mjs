// Hands (IWER's Quest 3 with hand tracking, its hands' pinch emulated): a scripted participant
// plants the ray-casting task's 7 trees in immersive-vr by pinches (the right hand's pinch is
// the trigger, the left hand's held pinch opens the menu); the file verifies, the same events
// give the same final hash natively, and `grove study` says the trial was made with hands.

import assert from 'node:assert/strict';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { fileLines, grove, start, studyRows, until } from './harness.mjs';
import { enterAndStart, plantAll } from './participant.mjs';

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

test('hands: the ray-casting task planted by pinches verifies, natively too, and the study says hands', async (t) => {
  const { page } = await h.open('participant=P67&task=ray-casting-7&seed=11&quality=low&render_every=4', { xr: true, room: false });
  await page.evaluate(() => (window.xrDevice.primaryInputMode = 'hand'));
  await enterAndStart(page, 'vr');
  const device = await page.evaluate(() => window.grove.device);
  assert.deepEqual(device, { profile: 'oculus-hand', target_ray_mode: 'tracked-pointer', mapping: 'hands' });
  assert.equal(await plantAll(page), 7);
  await until(page, () => window.grove.state === 'done' && window.grove.verification, null, 60000);
  const done = await page.evaluate(() => ({ v: window.grove.verification, file: window.grove.file }));
  assert.equal(done.v.status, 'verified', JSON.stringify(done.v));
  assert.deepEqual(h.errors, []);

  const path = join(h.server.dir, done.file);
  const lines = fileLines(path);
  assert.deepEqual(JSON.parse(lines[0]).device, device);
  const replay = JSON.parse(grove(['replay', path, '--json']).stdout);
  assert.equal(replay.verified, true);
  assert.equal(replay.task.completed, true);
  assert.deepEqual(replay.device, device);
  // Natively: `grove replay --seal` re-simulates the events and reaches the same final hash.
  const sealed = mkdtempSync(join(tmpdir(), 'grove-page-hands-'));
  t.after(() => rmSync(sealed, { recursive: true, force: true }));
  const seal = grove(['replay', '--seal', path, '--out', join(sealed, 'sealed.jsonl')]);
  assert.equal(seal.status, 0, seal.stderr);
  const footer = (ls) => JSON.parse(ls[ls.length - 1]);
  assert.deepEqual(footer(fileLines(join(sealed, 'sealed.jsonl'))).final_hash, footer(lines).final_hash);
  const row = studyRows(h.server.dir).find((r) => r.file === done.file);
  assert.deepEqual([row.completed, row.device, row.input_profile], ['true', 'hands', 'oculus-hand']);
});
