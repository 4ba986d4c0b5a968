// Recordings made by the module's recorder, checked by the native build: `grove replay`
// verifies them, `grove study` evaluates them exactly as the same events recorded natively, and
// one event changed (its checksums redone) is found as a divergence.

import assert from 'node:assert/strict';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import test from 'node:test';

import { grove, native, scriptedTask, tempDir } from './common.mjs';

function write(file, lines) {
  writeFileSync(file, lines.join('\n') + '\n');
}

test('a scripted run recorded by the module verifies with native grove replay', (t) => {
  const dir = tempDir(t);
  const { lines, snapshot } = scriptedTask();
  assert.ok(snapshot.task.completed && snapshot.task.done, JSON.stringify(snapshot.task));
  assert.equal(snapshot.task.satisfied, 7);
  const file = path.join(dir, 'W01-ray-casting-7.jsonl');
  write(file, lines);
  const out = native(['replay', file]);
  assert.equal(out.status, 0, out.stderr);
  assert.match(out.stdout, /: verified, complete \(\d+ ticks/);
  assert.match(out.stdout, /task ray-casting-7 \(ray-casting\): completed, [\d.]+ s, 7 trees, 0 errors/);
  const report = JSON.parse(native(['replay', '--json', file]).stdout);
  assert.equal(report.final_hash, snapshot.hash);
  assert.equal(report.final_hash, JSON.parse(lines.at(-1)).final_hash);
  assert.equal(report.checkpoints_checked, lines.filter((l) => l.includes('"type":"checkpoint"')).length + 1);
});

test('grove study evaluates a module recording exactly as the same events recorded natively', (t) => {
  const dir = tempDir(t);
  const [made, sealed] = [path.join(dir, 'wasm'), path.join(dir, 'native')];
  mkdirSync(made);
  mkdirSync(sealed);
  const { lines } = scriptedTask();
  const name = 'W01-ray-casting-7.jsonl';
  write(path.join(made, name), lines);
  // The same events, re-simulated and recorded natively.
  const seal = native(['replay', '--seal', path.join(made, name), '--out', path.join(sealed, name)]);
  assert.equal(seal.status, 0, seal.stderr);
  const nativeLines = readFileSync(path.join(sealed, name), 'utf8').trimEnd().split('\n');
  // Header, events and checkpoints are the module's byte for byte; only the footer's free-form
  // summary differs.
  assert.deepEqual(nativeLines.slice(0, -1), lines.slice(0, -1));
  assert.equal(JSON.parse(nativeLines.at(-1)).final_hash, JSON.parse(lines.at(-1)).final_hash);
  const study = (replays) => {
    const out = native(['study', '--replays', replays, '--out', path.join(replays, 'out'), '--json']);
    assert.equal(out.status, 0, out.stderr);
    return {
      json: JSON.parse(out.stdout),
      csv: readFileSync(path.join(replays, 'out', 'trial_results.csv'), 'utf8'),
      trees: readFileSync(path.join(replays, 'out', 'trees.csv'), 'utf8'),
    };
  };
  const [a, b] = [study(made), study(sealed)];
  assert.equal(a.csv, b.csv);
  assert.equal(a.trees, b.trees);
  // The summaries agree but for the time each run took.
  delete a.json.summary.wall_seconds;
  delete b.json.summary.wall_seconds;
  assert.deepEqual(a.json.summary, b.json.summary);
  assert.equal(a.json.summary.completed, 1);
});

test('one event changed in a module recording, checksums redone, diverges natively at that event', (t) => {
  const dir = tempDir(t);
  const { lines } = scriptedTask();
  // Move the controller pose stamped tick 171 (the fourth target's aim) 1 m east; the
  // checkpoint that follows it is tick 180.
  const at = lines.findIndex((l) => l.includes('"tick":171,') && l.includes('controller_pose'));
  assert.ok(at > 0);
  const event = JSON.parse(lines[at]);
  event.event.pose.position[0] += 1.0;
  delete event.sum;
  const changed = [...lines];
  changed[at] = JSON.stringify(event).slice(0, -1) + ',"sum":"00000000"}';
  const resigned = grove.rechain(changed);
  const file = path.join(dir, 'changed.jsonl');
  write(file, resigned);
  const out = native(['replay', '--json', file]);
  assert.equal(out.status, 1, out.stderr);
  const report = JSON.parse(out.stdout);
  assert.equal(report.status, 'diverged');
  assert.equal(report.first_divergence.tick, 180);
  assert.ok(
    report.first_divergence.differing.some((d) => d.component === 'Controller'),
    JSON.stringify(report.first_divergence),
  );
  // Without the change the same file verifies: the divergence is the event's.
  write(file, grove.rechain(lines));
  assert.equal(native(['replay', file]).status, 0);
});
