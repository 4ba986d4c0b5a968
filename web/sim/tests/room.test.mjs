// A room's scene is built in one place (systems/src/room.rs, the module's grove_room_scene) and
// taken or refused by one rule (systems/src/scene_text.rs), which the module and `grove serve`
// both keep: every room the module builds, from floors and plane sets of every sort, is taken by
// the module's simulations and by the server's open request; scene texts that break the rule
// are refused by both; and for every text here the two give the same verdict.

import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { startServer } from '../../client/test/helpers.mjs';
import { grove, root } from './common.mjs';

let server = null;
before(async () => {
  server = await startServer();
});
after(async () => {
  await server?.stop();
});

/** A polygon of `n` points on a circle of radius `r` around (x, z) at height y, in order (clockwise when `cw`). */
function polygon(n, { x = 0, z = 0, y = 0.75, r = 0.6, cw = false } = {}) {
  const points = [];
  for (let i = 0; i < n; i++) {
    const a = ((cw ? -1 : 1) * 2 * Math.PI * i) / n;
    points.push({ x: x + r * Math.cos(a), y, z: z + r * Math.sin(a) });
  }
  return points;
}

/** What a page finds: the floor's source and height, planes, a task. */
const rooms = {
  'a floor alone': { source: 'plane detection (floor)', floor_y: -0.02, planes: [], task: 'ray-casting-7' },
  'no task, no planes field': { source: 'hit test', floor_y: 0 },
  'a table and a shelf, either way round': { source: 'plane detection (floor)', floor_y: 0.01, task: 'manual-7', planes: [{ label: 'table', points: polygon(4, { x: 1, z: 2 }) }, { label: 'shelf', points: polygon(5, { x: -2, y: 1.4, cw: true }) }] },
  'forty planes: the first sixteen in the band are kept': { source: 'plane detection', floor_y: 0, task: 'ray-casting-7', planes: Array.from({ length: 40 }, (_, i) => ({ label: i % 3 ? 'table' : null, points: polygon(3 + (i % 7), { x: i - 20, z: -i / 4, y: 0.1 + i * 0.06, cw: i % 2 === 0 }) })) },
  'planes at the band and the outline limits': {
    source: 'plane detection',
    floor_y: 0,
    planes: [
      { label: 'at_0.3', points: polygon(4, { y: 0.3 }) },
      { label: 'above_0.3', points: polygon(4, { y: 0.3001 }) },
      { label: 'below_2.2', points: polygon(4, { y: 2.1999 }) },
      { label: 'at_2.2', points: polygon(4, { y: 2.2 }) },
      { label: 'most_points', points: polygon(128, { y: 1 }) },
      { label: 'too_many_points', points: polygon(129, { y: 1 }) },
      { label: 'two_points', points: polygon(2, { y: 1 }) },
      { label: 'far', points: polygon(4, { x: 999990, z: -999990, y: 1 }) },
      { label: 'degenerate', points: [{ x: 0, y: 1, z: 0 }, { x: 1, y: 1, z: 0 }, { x: 2, y: 1, z: 0 }] },
    ],
  },
  'sixteen of the largest outlines': { source: 'plane detection', floor_y: 0, task: 'manual-7', planes: Array.from({ length: 16 }, (_, i) => ({ label: 'Wall-Top "\n', points: polygon(128, { x: -123.4567 + i, y: 0.5 + i * 0.1, r: 33.3333 }) })) },
  'a source with line breaks and quotes': { source: 'plane detection\nScene(name: "x"\u0007', floor_y: 1e-9, planes: [{ points: polygon(3) }] },
};

/** What the page cannot make a room of: the module refuses these. */
const unbuildable = {
  'a plane beyond the coordinate limit': { source: 'x', floor_y: 0, planes: [{ points: polygon(4, { x: 2e6, y: 1 }) }] },
  'an unknown task': { source: 'x', floor_y: 0, task: 'knitting-7' },
  'no floor height': { source: 'x' },
  'points without a height': { source: 'x', floor_y: 0, planes: [{ points: [{ x: 0, z: 0 }] }] },
};

const study = readFileSync(path.join(root, 'assets', 'scenes', 'study.ron'), 'utf8');
const floorRoom = () => grove.roomScene(rooms['a floor alone']);

/** Scene texts that break the rule, and two that keep it, as a client could send them. */
const texts = {
  'the study scene': study,
  'a room padded to the limit with quotes': (() => {
    const t = floorRoom();
    return t + `// ${'"'.repeat((1 << 20) - Buffer.byteLength(t) - 4)}\n`;
  })(),
  'a room one byte over the limit': (() => {
    const t = floorRoom();
    return t + `// ${'"'.repeat((1 << 20) - Buffer.byteLength(t) - 3)}\n`;
  })(),
  'a room naming model banks': floorRoom().replace('name: "room",', 'name: "room", banks: ["../bank"],'),
  'a room with aerial photographs': floorRoom().replace('name: "room",', 'name: "room", aerial: Some((summer: "s.png", winter: "w.png", gsd_m: 0.5, origin: (0.0, 0.0))),'),
  'a room with aerial crowns': floorRoom().replace('name: "room",', 'name: "room", aerial: Some((summer: "s.png", winter: "w.png", gsd_m: 0.5, origin: (0.0, 0.0), crowns: Some("c.csv"))),'),
  'a control character': floorRoom().replace('name: "room"', 'name: "ro\u0001om"'),
  'not a scene': 'Scene(name: "x"',
  'no plane': floorRoom().replace(/planes: \[[\s\S]*?\n    \],/, 'planes: [],'),
  'a floor beyond the coordinate limit': floorRoom().replace('min: (-20.0, -14.0)', 'min: (-2000000.0, -14.0)'),
  'a floor of too many cells': floorRoom().replace('cell: 2.0', 'cell: 0.05'),
};

/** Whether the module takes a scene text for a simulation. */
function moduleTakes(text) {
  try {
    grove.createSim({ scene: 'room.ron', scene_text: text }).free();
    return true;
  } catch (e) {
    assert.equal(e.name, 'GroveError', e.stack);
    return false;
  }
}

/** Whether grove serve takes a scene text with a session's open request (and its refusal's status). */
async function serverTakes(text) {
  const r = await fetch(new URL('/api/sessions', server.url), { method: 'POST', headers: { 'grove-writer': 'page' }, body: JSON.stringify({ participant: 'R01', task: 'ray-casting-7', scene_text: text }) });
  const body = await r.json();
  assert.ok(r.status === 201 || r.status === 400 || r.status === 413, `${r.status} ${JSON.stringify(body)}`);
  return r.status === 201;
}

test('every room the module builds is taken by the module and by grove serve', async () => {
  for (const [name, room] of Object.entries(rooms)) {
    const text = grove.roomScene(room);
    assert.ok(moduleTakes(text), `${name}: the module refuses its own room`);
    assert.ok(await serverTakes(text), `${name}: the server refuses a room the module built`);
  }
  // What the rooms hold: the band's planes, at most sixteen, none with too many points.
  const limits = grove.roomScene(rooms['planes at the band and the outline limits']);
  const names = [...limits.matchAll(/name: "([a-z_]+-\d+)"/g)].map((m) => m[1]);
  assert.deepEqual(names, ['above_-1', 'below_-2', 'most_points-3', 'far-4', 'degenerate-5']);
  const forty = grove.roomScene(rooms['forty planes: the first sixteen in the band are kept']);
  assert.equal([...forty.matchAll(/shape: Mesh/g)].length, 16);
  assert.match(grove.roomScene(rooms['a floor alone']), /Target 6 \(birch-billboard\) has no plane at 0\.8 m/);
});

test('what no room can be made of is refused by the module with its reason', () => {
  for (const [name, room] of Object.entries(unbuildable)) {
    assert.throws(() => grove.roomScene(room), (e) => e.name === 'GroveError' && /^room: /.test(e.message), name);
  }
});

test('scene texts that break the rule are refused by both, and both give the same verdict on each', async () => {
  const verdicts = {};
  for (const [name, text] of Object.entries(texts)) {
    const [m, s] = [moduleTakes(text), await serverTakes(text)];
    assert.equal(s, m, `${name}: the module ${m ? 'takes' : 'refuses'} it, the server ${s ? 'takes' : 'refuses'} it`);
    verdicts[name] = m;
  }
  assert.deepEqual(
    Object.keys(verdicts).filter((n) => verdicts[n]),
    ['the study scene', 'a room padded to the limit with quotes'],
  );
});
