// node web/replay.mjs prints what grove replay prints, with the same exit codes.

import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import test from 'node:test';

import { grove, native, nodeReplay, tempDir } from './common.mjs';

/** The output without the wall-clock figures, which differ from run to run. */
const steady = (text) => text.replace(/ simulated in [\d.]+ s, \d+x\)/g, ' simulated)');

test('a verified, a diverged and a bad recording: same lines and exit codes as grove replay', (t) => {
  const dir = tempDir(t);
  const good = path.join('replays', 'study', 'P02-manual-7.jsonl');
  const lines = readFileSync(good, 'utf8').trimEnd().split('\n');
  // The first Trigger press made a Bumper press, re-signed.
  const at = lines.findIndex((l) => l.includes('"button_down"') && l.includes('"trigger"'));
  const e = JSON.parse(lines[at]);
  e.event.button = 'bumper';
  delete e.sum;
  lines[at] = JSON.stringify(e).slice(0, -1) + ',"sum":"00000000"}';
  const diverged = path.join(dir, 'diverged.jsonl');
  writeFileSync(diverged, grove.rechain(lines).join('\n') + '\n');
  const bad = path.join(dir, 'bad.jsonl');
  writeFileSync(bad, readFileSync(good, 'utf8').replace('"tick":3', '"tick":4'));
  for (const [file, code] of [
    [good, 0],
    [diverged, 1],
    [bad, 2],
    [path.join(dir, 'missing.jsonl'), 2],
  ]) {
    for (const json of [false, true]) {
      const args = json ? [file, '--json'] : [file];
      const [a, b] = [native(['replay', ...args]), nodeReplay(args)];
      assert.equal(b.status, code, `${file}: ${b.stderr}`);
      assert.equal(a.status, code, `${file}: ${a.stderr}`);
      if (code === 2) {
        assert.equal(b.stdout, '');
        assert.equal(b.stderr.split('\n').length, 2, b.stderr);
        assert.match(b.stderr, /^error: /);
        continue;
      }
      if (json) {
        const [x, y] = [JSON.parse(a.stdout), JSON.parse(b.stdout)];
        for (const r of [x, y]) {
          delete r.wall_seconds;
          delete r.speedup;
        }
        assert.deepEqual(y, x);
      } else {
        assert.equal(steady(b.stdout), steady(a.stdout));
      }
    }
  }
  // --until stops where grove replay stops.
  const [a, b] = [native(['replay', good, '--until', '600']), nodeReplay([good, '--until', '600'])];
  assert.equal(b.status, a.status);
  assert.equal(steady(b.stdout), steady(a.stdout));
});
