// Bad input to the module comes back as an error naming the problem (a GroveError); the module
// never traps, and the simulation it had is unchanged.

import assert from 'node:assert/strict';
import { readdirSync, readFileSync } from 'node:fs';
import path from 'node:path';
import test from 'node:test';

import { GroveError } from '../grove-sim.mjs';
import { grove, root } from './common.mjs';

/** Runs `f`, which must throw a GroveError whose message contains `says`. */
function refused(f, says) {
  assert.throws(f, (e) => {
    assert.ok(e instanceof GroveError, `not a GroveError: ${e}`);
    assert.ok(e.message.includes(says), `"${e.message}" does not say "${says}"`);
    return true;
  });
}

test('bad events and ticks are refused by name and change nothing', () => {
  const lines = [];
  const sim = grove.createSim({ seed: 3, record: true, onLine: (l) => lines.push(l) });
  const twin = grove.createSim({ seed: 3 });
  for (const s of [sim, twin]) {
    s.push({ tick: 2, event: { kind: 'open_menu' } });
    for (let i = 0; i < 10; i++) {
      s.step();
    }
  }
  const before = { hash: sim.hash(), tick: sim.tick, lines: lines.length, snapshot: sim.snapshot() };
  refused(() => sim.push({ kind: 'teleport' }), 'unknown variant `teleport`');
  refused(() => sim.push({ kind: 'touchpad_axes', axes: [0, 1.5] }), 'touchpad axes outside [-1, 1]');
  refused(
    () => sim.push({ kind: 'controller_pose', pose: { position: [0, 1, 0], rotation: [0, 0, 0, 3] } }),
    'not a unit quaternion',
  );
  refused(
    () => sim.push({ kind: 'controller_pose', pose: { position: [0, 1e9, 0], rotation: [0, 0, 0, 1] } }),
    'more than 100 km',
  );
  refused(
    () => sim.push({ tick: 4, event: { kind: 'close_menu' } }),
    'event stamped tick 4 is out of tick order: the simulation is at tick 10',
  );
  refused(
    () => sim.push({ tick: 100000000, event: { kind: 'close_menu' } }),
    'tick 100000000 is beyond the limit of 100000000 ticks',
  );
  refused(() => sim.push({ kind: 'choose_model', model: 'palm' }), 'palm');
  refused(() => sim.push('{"kind": '), 'event:');
  sim.push({ tick: 30, event: { kind: 'close_menu' } });
  twin.push({ tick: 30, event: { kind: 'close_menu' } });
  refused(() => sim.push({ tick: 20, event: { kind: 'end_task' } }), 'an event stamped tick 30 was pushed before it');
  assert.equal(sim.hash(), before.hash);
  assert.equal(sim.tick, before.tick);
  assert.equal(lines.length, before.lines);
  assert.deepEqual(sim.snapshot(), before.snapshot);
  // And it goes on as the twin that saw none of it.
  for (const s of [sim, twin]) {
    while (s.tick < 70) {
      s.step();
    }
  }
  assert.equal(sim.hash(), twin.hash());
  assert.equal(sim.snapshot().menu.open, false);
  sim.finish();
  refused(() => sim.step(), 'the recording is finished');
  refused(() => sim.push({ kind: 'open_menu' }), 'the recording is finished');
  sim.free();
  twin.free();
  refused(() => sim.hash(), `no simulation with handle ${sim.handle}`);
});

test('bad options and scene text are refused by name', () => {
  refused(() => grove.createSim({ scene: 'meadow.ron', scene_text: 'Scene(planes: [' }), 'scene "meadow.ron": line');
  refused(() => grove.createSim({ scene: 'atlantis' }), 'not a built-in scene');
  refused(() => grove.createSim({ set: ['snap_threshold=-1'] }), "snap_threshold: '-1' must be a number from 0 to 10");
  refused(() => grove.createSim({ set: ['gravity=2'] }), "unknown parameter 'gravity'");
  refused(() => grove.createSim({ header: '{"type":"header"}' }), 'header line:');
  refused(() => grove.createSim({ seeds: 4 }), 'unknown field `seeds`');
  refused(() => grove.createSim({ task: 'knitting', record: true }), 'knitting');
  // The module still works.
  const sim = grove.createSim({ set: ['snap_threshold=0.2'] });
  sim.step();
  assert.equal(sim.tick, 1);
  sim.free();
});

test('every hostile recording is refused by the module replay, never a trap', () => {
  const dir = path.join(root, 'tests', 'hostile');
  const files = readdirSync(dir).filter((f) => f.endsWith('.jsonl'));
  assert.ok(files.length >= 15);
  for (const f of files) {
    refused(() => grove.replay(readFileSync(path.join(dir, f)), { file: f }), f);
  }
  refused(() => grove.replay('', { file: 'empty.jsonl' }), 'empty.jsonl');
  refused(() => grove.replay(Buffer.from([0xff, 0xfe, 0x0a]), { file: 'binary.jsonl' }), 'binary.jsonl:1');
  // A tick beyond the limit, in a header-and-event file.
  const study = readFileSync(path.join(root, 'replays', 'study', 'P01-ray-casting-7.jsonl'), 'utf8').split('\n');
  const far = grove.rechain([
    study[0],
    '{"type":"event","tick":100000001,"ms":0,"frame":0,"event":{"kind":"end_task"},"sum":"00000000"}',
  ]);
  refused(() => grove.replay(far.join('\n') + '\n', { file: 'far.jsonl' }), 'far.jsonl:2');
  // The module replays a good file afterwards.
  const { report } = grove.replay(study.join('\n'), { file: 'P01' });
  assert.equal(report.status, 'verified');
});
