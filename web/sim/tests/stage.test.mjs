// The model stage with a walker's view (`stage.from`, grove_systems::stage::walker_view): the
// camera of docs/species.md's sheets, which the headset page's `render.mjs --from` takes from the
// module rather than from numbers of its own.

import assert from 'node:assert/strict';
import test from 'node:test';

import { GroveError } from '../grove-sim.mjs';
import { grove } from './common.mjs';

const BOX = { min: [-3, 0, -3], max: [3, 20, 3], aspect: 4 / 3 };

test('a walker stands at eye height `from` metres away and looks at 45 % of the model', () => {
  const sim = grove.createSim({ stage: { ...BOX, from: 10 } });
  try {
    const { head, fov_y, sun_direction } = sim.snapshot();
    [0, 1.7, 10].forEach((v, i) => assert.ok(Math.abs(head.position[i] - v) < 1e-5, `head at ${head.position}`));
    const aim = [0, 0.45 * 20 - head.position[1], -10];
    const len = Math.hypot(...aim);
    // The head looks along its -z: the rotation's image of (0, 0, -1).
    const [x, y, z, w] = head.rotation;
    const forward = [-(2 * (x * z + w * y)), -(2 * (y * z - w * x)), -(1 - 2 * (x * x + y * y))];
    const cos = forward.reduce((s, f, i) => s + (f * aim[i]) / len, 0);
    assert.ok(cos > 0.99999, `looks ${Math.acos(Math.min(cos, 1))} rad off the aim`);
    assert.ok(Math.abs(fov_y - (50 * Math.PI) / 180) < 1e-6, `fov_y ${fov_y}`);
    assert.ok(Math.abs(Math.asin(sun_direction[1]) - (40 * Math.PI) / 180) < 1e-4, `sun ${sun_direction}`);
  } finally {
    sim.free();
  }
  // Without `from`, the framing of the bounds: not a walker's.
  const framed = grove.createSim({ stage: BOX });
  try {
    assert.ok(Math.abs(framed.snapshot().head.position[1] - 1.7) > 0.1, 'framed from above');
  } finally {
    framed.free();
  }
});

test('a walker too near, too far or not a number is refused', () => {
  for (const from of [0, -2, 5000, 'far']) {
    assert.throws(
      () => grove.createSim({ stage: { ...BOX, from } }),
      (e) => e instanceof GroveError && /from|invalid type/.test(e.message),
      `from ${from}`,
    );
  }
});
