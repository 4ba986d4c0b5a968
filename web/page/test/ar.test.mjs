// A scripted participant in immersive-ar (IWER's Quest 3 in a small office from @iwer/sem)
// plants the ray-casting task's 7 trees; the server's file verifies with `grove replay`, `grove
// study` reports the task completed with 7 trees on the room's layout, the final hash is the one
// the same events give natively, and every request the page made went to the server.

import assert from 'node:assert/strict';
import { copyFileSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { fileLines, grove, start, until } from './harness.mjs';
import { enterAndStart, plantAll } from './participant.mjs';

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

test('immersive-ar: 7 trees planted on the room floor, verified, in the study, same hash as native', async (t) => {
  const scratch = [];
  t.after(() => scratch.forEach((d) => rmSync(d, { recursive: true, force: true })));
  const { page } = await h.open('participant=P61&task=ray-casting-7&seed=2019061&quality=low&render_every=4', { xr: true, room: true });
  await enterAndStart(page, 'ar');
  const start = await page.evaluate(() => ({ floor: window.grove.floor, snap: window.grove.snapshot }));
  assert.match(start.floor.source, /^plane detection/, 'the office has a floor plane');
  const moved = start.snap.task.targets.filter((t) => t.moved_to);
  assert.deepEqual(moved.map((t) => [t.model, t.position[1], t.moved_to[1]]), [['birch-billboard', 0.8, 0]], 'the terrace target lies on the floor');
  assert.equal(await plantAll(page), 7);
  await until(page, () => window.grove.state === 'done' && window.grove.verification, null, 60000);
  const done = await page.evaluate(() => ({ v: window.grove.verification, file: window.grove.file, s: window.grove.snapshot }));
  assert.equal(done.v.status, 'verified', JSON.stringify(done.v));
  assert.equal(done.s.trees.length, 7, 'the room has no trees of its own: the 7 planted');
  assert.deepEqual(h.foreign(), [], 'every request went to the server');
  assert.deepEqual(h.errors, []);

  const file = join(h.server.dir, done.file);
  const lines = fileLines(file);
  const header = JSON.parse(lines[0]);
  assert.match(header.scene, /^room-[0-9a-f]{16}\.ron$/);
  const scene = readFileSync(join(h.server.dir, header.scene), 'utf8');
  assert.match(scene, /plane detection/);
  assert.match(scene, /Target 6 \(birch-billboard\) has no plane at 0\.8 m/);
  const replay = grove(['replay', file, '--json']);
  assert.equal(replay.status, 0, replay.stderr);
  const report = JSON.parse(replay.stdout);
  assert.equal(report.task.completed, true);
  assert.deepEqual(report.task.moved_targets.map((m) => m.target), [6]);

  const out = mkdtempSync(join(tmpdir(), 'grove-page-study-'));
  scratch.push(out);
  const study = grove(['study', '--replays', h.server.dir, '--out', out, '--force']);
  assert.equal(study.status, 0, study.stderr);
  const csv = readFileSync(join(out, 'trial_results.csv'), 'utf8').trim().split('\n').map((l) => l.split(','));
  const col = (name) => csv[0].indexOf(name);
  const row = csv.find((r) => r[col('file')] === done.file);
  assert.ok(row, csv.join('\n'));
  assert.equal(row[col('completed')], 'true');
  assert.equal(row[col('trees')], '7');
  assert.equal(row[col('status')], 'verified');
  assert.equal(row[col('layout')], '6:0.80>0.00');

  // The same events re-simulated natively: `grove replay --seal` checks the file, runs its events
  // on a fresh native simulation and writes its own checkpoints and footer. (Its second simulation
  // looks the room's scene up in the working directory: run it where a copy of the scene is.)
  const sealed = mkdtempSync(join(tmpdir(), 'grove-page-seal-'));
  scratch.push(sealed);
  copyFileSync(join(h.server.dir, header.scene), join(sealed, header.scene));
  const seal = grove(['replay', '--seal', file, '--out', join(sealed, 'sealed.jsonl')], sealed);
  assert.equal(seal.status, 0, seal.stderr);
  const footer = (ls) => JSON.parse(ls[ls.length - 1]);
  const native = footer(fileLines(join(sealed, 'sealed.jsonl')));
  assert.deepEqual([native.final_tick, native.final_hash], [footer(lines).final_tick, footer(lines).final_hash]);
});
