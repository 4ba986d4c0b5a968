// What a headset holds (docs/headset.md): for every model of each kind the page draws (the
// study's billboards and low-poly meshes, the species bank's level 1 and level 2), the page's
// own view draws 1 tree and N (capacity.mjs, capacity-probe.mjs), and three.js's counts of the
// frame (renderer.info.render) give the cost of a tree as the slope between them. Held against
// numbers the page does not give: the model's primitives and triangles read from its glTF's
// accessors, drawn once by the camera's pass and once more by the sun's shadow map (none with
// the page's quality=low). The frame's fixed cost (sky, ground) is the same whatever the trees.

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { BUDGET, N, fit, measure, models } from './capacity.mjs';

test(
  'a tree costs the page its primitives in draw calls and its triangles, once per pass',
  { timeout: 300000 },
  async () => {
    const list = models();
    const kinds = {};
    for (const m of list) (kinds[m.kind] ??= []).push(m);
    assert.deepEqual(Object.fromEntries(Object.entries(kinds).map(([k, v]) => [k, v.length])), {
      billboard: 4,
      'low-poly mesh': 4,
      'species level 1': 6,
      'species level 2': 6,
    });
    const rows = await measure(list);
    const broken = [];
    const fixed = { shadows: new Set(), plain: new Set() };
    for (const { model, own, shadows, plain } of rows) {
      for (const [name, m, passes] of [
        ['shadows on', shadows, 2],
        ['shadows off', plain, 1],
      ]) {
        if (m.calls !== own.primitives * passes)
          broken.push(
            `${model}, ${name}: ${m.calls} draw calls a tree, not ${own.primitives} primitives × ${passes} passes`,
          );
        if (m.triangles !== own.triangles * passes)
          broken.push(`${model}, ${name}: ${m.triangles} triangles a tree, not ${own.triangles} × ${passes} passes`);
      }
      fixed.shadows.add(`${shadows.fixed_calls} calls, ${shadows.fixed_triangles} triangles`);
      fixed.plain.add(`${plain.fixed_calls} calls, ${plain.fixed_triangles} triangles`);
      if (!(shadows.fixed_calls > 0 && plain.fixed_calls > 0))
        broken.push(`${model}: no fixed cost (the sky and the ground draw nothing?)`);
    }
    for (const [name, set] of Object.entries(fixed))
      if (set.size !== 1) broken.push(`the fixed cost (${name}) depends on the model: ${[...set].join(' / ')}`);
    // The study's billboard of a species costs fewer triangles than its low-poly mesh (the paper's premise).
    for (const b of rows.filter((r) => r.kind === 'billboard')) {
      const mesh = rows.find((r) => r.model === b.model.replace('-billboard', '-mesh'));
      if (!(b.shadows.triangles < mesh.shadows.triangles))
        broken.push(
          `${b.model}: ${b.shadows.triangles} triangles a tree, no fewer than ${mesh.model}'s ${mesh.shadows.triangles}`,
        );
    }
    const lines = [
      '| kind | draw calls / tree | triangles / tree | fixed | trees in budget (shadows / low) |',
      '|---|---|---|---|---|',
    ];
    for (const [kind, ms] of Object.entries(kinds)) {
      const rs = rows.filter((r) => ms.some((m) => m.model === r.model));
      const range = (f) => `${Math.min(...rs.map(f))}–${Math.max(...rs.map(f))}`;
      lines.push(
        `| ${kind} | ${range((r) => r.shadows.calls)} | ${range((r) => r.shadows.triangles)} | ${rs[0].shadows.fixed_calls} calls, ${rs[0].shadows.fixed_triangles} tris | ${range((r) => fit(r.shadows))} / ${range((r) => fit(r.plain))} |`,
      );
    }
    console.log(
      `1 and ${N} trees a model, budget ${BUDGET.calls} calls and ${BUDGET.triangles} triangles an eye:\n${lines.join('\n')}`,
    );
    assert.deepEqual(broken, []);
  },
);
