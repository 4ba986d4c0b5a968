// Every scenario in tests/scenarios/, its steps turned into events natively (the example
// scenario_recording runs it as `grove test` does and records the run), driven through the
// module event by event, reaches the world hash the scenario file pins; and the module's
// recorder, continuing the native header line, writes the native lines byte for byte.

import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { existsSync, readdirSync, readFileSync } from 'node:fs';
import path from 'node:path';
import test from 'node:test';

import { examples, grove, root, tempDir } from './common.mjs';

test('every scenario driven through the module reaches its pinned hash', (t) => {
  const dir = tempDir(t);
  const bin = path.join(examples, 'scenario_recording');
  assert.ok(existsSync(bin), `${bin} is missing: cargo test (or cargo build -p grove-systems --examples) builds it`);
  const run = spawnSync(bin, [dir], { cwd: root, encoding: 'utf8' });
  assert.equal(run.status, 0, run.stderr);
  const made = run.stdout
    .trim()
    .split('\n')
    .map((l) => JSON.parse(l));
  const files = readdirSync(path.join(root, 'tests', 'scenarios')).filter((f) => f.endsWith('.ron'));
  assert.equal(made.length, files.length);
  assert.ok(made.length >= 5);
  for (const { scenario, recording } of made) {
    const pinned = [...readFileSync(path.join(root, scenario), 'utf8').matchAll(/Hash\("([0-9a-f]{16})"\)/g)].map(
      (m) => m[1],
    );
    assert.equal(pinned.length, 1, `${scenario} pins one hash at its end`);
    const lines = readFileSync(recording, 'utf8').trimEnd().split('\n');
    const footer = JSON.parse(lines.at(-1));
    // The module follows the native header line and records the same events.
    const out = [];
    const sim = grove.createSim({ header: lines[0], onLine: (l) => out.push(l) });
    for (const line of lines.slice(1, -1)) {
      const l = JSON.parse(line);
      if (l.type === 'event') {
        while (sim.tick < l.tick) {
          sim.step();
        }
        sim.push(l);
      }
    }
    while (sim.tick < footer.final_tick) {
      sim.step();
    }
    assert.equal(sim.hash(), pinned[0], `${scenario}: the module's world hash`);
    sim.finish();
    sim.free();
    // Every line but the footer's free-form summary is the native recording's, byte for byte.
    assert.deepEqual(out.slice(0, -1), lines.slice(1, -1), scenario);
    assert.equal(JSON.parse(out.at(-1)).final_hash, pinned[0], scenario);
  }
});
