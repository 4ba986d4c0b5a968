// The shipped recordings and a fresh synthetic study of three techniques, re-simulated by the
// WebAssembly module, reach the native build's checkpoint hashes and final hash, through the
// verifying replay and through the Sim API a page uses.

import assert from 'node:assert/strict';
import { readdirSync, readFileSync } from 'node:fs';
import path from 'node:path';
import test from 'node:test';

import { driveThrough, grove, native, root, tempDir } from './common.mjs';

function recordingsIn(dir) {
  return readdirSync(dir)
    .filter((f) => f.endsWith('.jsonl'))
    .sort()
    .map((f) => path.join(dir, f));
}

/** The module's replay of `file` agrees with `grove replay --json` on it, field for field. */
function agreesWithNative(file) {
  const text = readFileSync(file);
  const { report } = grove.replay(text, { file });
  const out = native(['replay', '--json', file]);
  assert.equal(out.status, 0, `${file}: ${out.stderr}`);
  const expected = JSON.parse(out.stdout);
  for (const key of [
    'status',
    'complete',
    'checkpoints_checked',
    'ticks',
    'final_hash',
    'events',
    'participant',
    'synthetic',
    'task',
    'first_divergence',
  ]) {
    assert.deepEqual(report[key], expected[key], `${file}: ${key}`);
  }
  assert.equal(report.status, 'verified', file);
  const footer = JSON.parse(text.toString('utf8').trimEnd().split('\n').at(-1));
  assert.equal(report.final_hash, footer.final_hash, file);
  return report;
}

test('every recording in replays/study/ verifies in the module as natively', () => {
  const files = recordingsIn(path.join(root, 'replays', 'study'));
  assert.equal(files.length, 24);
  for (const file of files) {
    const report = agreesWithNative(file);
    assert.ok(report.checkpoints_checked > 20, file);
  }
});

test('the scenario and gaze-dwell recordings verify in the module as natively', () => {
  for (const file of [
    ...recordingsIn(path.join(root, 'replays', 'scenarios')),
    ...recordingsIn(path.join(root, 'techniques', 'gaze-dwell', 'replays')),
  ]) {
    agreesWithNative(file);
  }
});

test('driven event by event through the Sim API, study recordings meet every checkpoint', () => {
  for (const name of ['P01-ray-casting-7.jsonl', 'P01-manual-7.jsonl', 'P07-manual-7.jsonl']) {
    const hashes = driveThrough(readFileSync(path.join(root, 'replays', 'study', name), 'utf8'));
    assert.ok(hashes.length > 30, name);
    for (const h of hashes) {
      assert.equal(h.actual, h.expected, `${name} at tick ${h.tick}`);
    }
  }
  const gaze = driveThrough(
    readFileSync(path.join(root, 'techniques', 'gaze-dwell', 'replays', 'P01-gaze-dwell.jsonl'), 'utf8'),
  );
  assert.deepEqual(
    gaze.map((h) => h.actual),
    gaze.map((h) => h.expected),
  );
});

test('a synthetic study of ray-casting, manual and gaze-dwell made natively verifies in the module', (t) => {
  const dir = tempDir(t);
  const out = native(['synth', '--techniques', 'ray-casting,manual,gaze-dwell', '--out', dir]);
  assert.equal(out.status, 0, out.stderr);
  const files = recordingsIn(dir);
  assert.equal(files.length, 36, 'twelve participants, three techniques');
  const modes = new Set();
  for (const file of files) {
    const { report } = grove.replay(readFileSync(file), { file });
    assert.equal(report.status, 'verified', `${file}: ${JSON.stringify(report.first_divergence)}`);
    assert.ok(report.complete && report.task.completed, file);
    modes.add(report.task.mode);
  }
  assert.deepEqual([...modes].sort(), ['gaze-dwell', 'manual', 'ray-casting']);
});
