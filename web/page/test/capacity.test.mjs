// What a headset holds (docs/headset.md): for every model of each kind the page draws (the
// study's billboards and low-poly meshes, the species bank's level 1 and level 2), the page's
// own view draws no tree, 1 and N (capacity.mjs, capacity-probe.mjs), and three.js's counts of
// the frame (renderer.info.render) give the cost of a model in view (its draw calls, the same
// whatever its count: one InstancedMesh per primitive) and of a tree (its triangles). Then 100
// trees of the study's mix in one frame, and a species' level 1 at sizes on screen about its far
// model's threshold. Held against numbers the page does not give: the models' primitives and
// triangles read from their glTFs' accessors, drawn once by the camera's pass and once more by
// the sun's shadow map (none with the page's quality=low), the far model and the thresholds from
// the bank's catalogue and grove's renderer (levels.test.mjs holds the constants to the Rust ones).

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { BUDGET, MIX_TREES, N, farModels, fit, gltfCounts, measure, models } from './capacity.mjs';
import { FAR_BAND, FAR_PIXELS } from '../draw/levels.mjs';

const PASSES = { shadows: 2, plain: 1 };

test(
  'a model in view costs its primitives in draw calls whatever its count, a tree its triangles; 100 trees of the study mix fit the budget; a far model takes over as grove hands it',
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
    // The species' level 1 about its far model's threshold: all model, the two sharing (the bark
    // the model's, then the far model's), all far model.
    const oak = list.find((m) => m.model === 'oak-lod1');
    const far = farModels(join(oak.file, '../../catalogue.ron'))['oak-lod1'];
    assert.equal(far, 'oak-lod2');
    const hi = FAR_PIXELS * FAR_BAND;
    const pixels = [
      hi * 1.1,
      FAR_PIXELS + 0.6 * (hi - FAR_PIXELS),
      FAR_PIXELS + 0.4 * (hi - FAR_PIXELS),
      FAR_PIXELS * 0.9,
    ];
    const farFile = list.find((m) => m.model === far).file;
    const { rows, mix, levels } = await measure(list, { levels: { file: oak.file, far: farFile, pixels } });
    const broken = [];
    const fixed = { shadows: new Set(), plain: new Set() };
    for (const { model, own, shadows, plain } of rows) {
      for (const [name, m] of Object.entries({ shadows, plain })) {
        const passes = PASSES[name];
        if (m.model_calls !== own.primitives * passes)
          broken.push(
            `${model}, ${name}: ${m.model_calls} draw calls a model, not ${own.primitives} primitives × ${passes} passes`,
          );
        if (m.calls !== 0) broken.push(`${model}, ${name}: ${N} trees draw ${m.calls * (N - 1)} more calls than 1`);
        if (m.triangles !== own.triangles * passes)
          broken.push(`${model}, ${name}: ${m.triangles} triangles a tree, not ${own.triangles} × ${passes} passes`);
        if (m.one.triangles - m.zero.triangles !== own.triangles * passes)
          broken.push(`${model}, ${name}: its one tree draws ${m.one.triangles - m.zero.triangles} triangles`);
        fixed[name].add(`${m.fixed_calls} calls, ${m.fixed_triangles} triangles`);
        if (!(m.fixed_calls > 0)) broken.push(`${model}: no fixed cost (the sky and the ground draw nothing?)`);
      }
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
    // 100 trees of the study's mix: the fixed cost, each model's primitives once per pass, each tree's triangles.
    const own = Object.fromEntries(rows.map((r) => [r.model, r.own]));
    assert.equal(Object.keys(mix.of).length, 8);
    assert.equal(
      Object.values(mix.of).reduce((a, b) => a + b),
      MIX_TREES,
    );
    for (const [name, passes] of Object.entries(PASSES)) {
      const zero = rows[0][name].zero;
      const want = {
        calls: zero.calls + passes * Object.keys(mix.of).reduce((a, m) => a + own[m].primitives, 0),
        triangles: zero.triangles + passes * Object.entries(mix.of).reduce((a, [m, n]) => a + n * own[m].triangles, 0),
      };
      if (mix[name].calls !== want.calls || mix[name].triangles !== want.triangles)
        broken.push(
          `${MIX_TREES} trees of the mix, ${name}: ${JSON.stringify(mix[name])}, not ${JSON.stringify(want)}`,
        );
      if (!(mix[name].calls <= BUDGET.calls && mix[name].triangles <= BUDGET.triangles))
        broken.push(`${MIX_TREES} trees of the mix, ${name}: ${JSON.stringify(mix[name])} over the budget`);
    }
    // The levels: which primitives of oak-lod1 (near) and oak-lod2 (far) each size draws.
    const parts = { near: gltfCounts(oak.file).parts, far: gltfCounts(farFile).parts };
    const drawn = [
      [parts.near, []],
      // A share of 0.4 handed to the far model: its leaves, the model's bark.
      [parts.near, parts.far.filter((p) => p.clipped)],
      // 0.6: the far model's bark.
      [parts.near.filter((p) => p.clipped), parts.far],
      [[], parts.far],
    ];
    assert.ok(parts.near.some((p) => p.clipped) && parts.near.some((p) => !p.clipped));
    for (const [name, passes] of Object.entries(PASSES)) {
      const frames = levels.filter((f) => f.shadows === (name === 'shadows'));
      const zero = frames.find((f) => f.pixels === 0);
      pixels.forEach((p, i) => {
        const ps = [...drawn[i][0], ...drawn[i][1]];
        const want = {
          calls: zero.calls + passes * ps.length,
          triangles: zero.triangles + passes * ps.reduce((a, q) => a + q.triangles, 0),
        };
        const got = frames.find((f) => f.pixels === p);
        if (got.calls !== want.calls || got.triangles !== want.triangles)
          broken.push(
            `oak-lod1 at ${Math.round(p)} px, ${name}: ${got.calls} calls, ${got.triangles} triangles, not ${want.calls}, ${want.triangles}`,
          );
      });
    }
    const lines = [
      '| kind | draw calls / model | triangles / tree | fixed | trees in budget (shadows / low) |',
      '|---|---|---|---|---|',
    ];
    for (const [kind, ms] of Object.entries(kinds)) {
      const rs = rows.filter((r) => ms.some((m) => m.model === r.model));
      const range = (f) => `${Math.min(...rs.map(f))}–${Math.max(...rs.map(f))}`;
      lines.push(
        `| ${kind} | ${range((r) => r.shadows.model_calls)} | ${range((r) => r.shadows.triangles)} | ${rs[0].shadows.fixed_calls} calls, ${rs[0].shadows.fixed_triangles} tris | ${range((r) => fit(r.shadows))} / ${range((r) => fit(r.plain))} |`,
      );
    }
    console.log(
      `0, 1 and ${N} trees a model, budget ${BUDGET.calls} calls and ${BUDGET.triangles} triangles an eye:\n${lines.join('\n')}\n${MIX_TREES} trees of the study's mix: ${JSON.stringify(mix)}`,
    );
    assert.deepEqual(broken, []);
  },
);
