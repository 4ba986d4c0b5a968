// The headset page's trees sway as grove's renderer sways them (docs/headset.md, "Wind"): the
// page's wind GLSL (a lone tree's uniforms and an InstancedMesh's attributes) against grove's CPU
// reference on models' own vertices at three ticks (within a millimetre); with the study's gusts, silhouettes at three ticks half a second apart overlapping
// the native ones (IoU ≥ 0.85) and differing from one another; shadows moving with the trees.

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { openStill } from '../render.mjs';
import { ROOT } from './harness.mjs';
import { iou, mask, native } from './look.mjs';

const TICKS = [120, 150, 180];
const SIZE = { width: 320, height: 240 };
const MODELS = [
  'assets/trees/broadleaf-mesh.gltf',
  'assets/trees/birch-billboard.gltf',
  'assets/banks/species/oak-lod1/oak-lod1.gltf',
].map((m) => join(ROOT, m));

test(
  'the page displaces vertices as grove does, within a millimetre, at three ticks',
  { timeout: 300000 },
  async () => {
    const still = await openStill({ entry: join(ROOT, 'web/page/test/wind-probe.mjs') });
    try {
      for (const model of MODELS) {
        const rows = await still.call('windProbe', model, { ticks: TICKS });
        for (const r of rows) {
          console.log(
            `${model.split('/').pop()} tick ${r.tick}: ${r.points} vertices, gust ${r.gust.toFixed(3)}, largest sway ${(r.sway * 1000).toFixed(1)} mm, largest difference ${(r.error * 1000).toFixed(4)} mm (instanced ${(r.instanced * 1000).toFixed(4)} mm)`,
          );
          assert.ok(r.points > 100, `${model}: ${r.points} vertices sampled`);
          assert.ok(r.sway > 0.01, `${model} at tick ${r.tick}: the wind moves vertices (${r.sway} m)`);
          assert.ok(
            r.error <= 0.001,
            `${model} at tick ${r.tick}: the page's displacement is ${r.error} m from grove's`,
          );
        }
      }
    } finally {
      await still.close();
    }
  },
);

test(
  "with gusts, the page's silhouettes follow grove's at three ticks half a second apart, and its shadows move",
  { timeout: 600000 },
  async () => {
    const still = await openStill();
    try {
      for (const model of MODELS) {
        const masks = [];
        const grounds = [];
        for (const tick of TICKS) {
          const n = mask(native(model, { ...SIZE, tick }));
          const p = mask(await still.render(model, { ...SIZE, tick, background: 'transparent', antialias: false }));
          const overlap = iou(n, p);
          console.log(`${model.split('/').pop()} tick ${tick}: silhouette IoU ${overlap.toFixed(3)}`);
          assert.ok(overlap >= 0.85, `${model} at tick ${tick}: IoU ${overlap}`);
          masks.push(p);
          grounds.push(await still.render(model, { ...SIZE, tick, background: 'sky' }));
        }
        for (let i = 1; i < masks.length; i++) {
          assert.ok(
            iou(masks[i - 1], masks[i]) < 0.999,
            `${model}: the silhouettes at ticks ${TICKS[i - 1]} and ${TICKS[i]} differ`,
          );
          // The ground outside both silhouettes: its shadow moves with the tree.
          const [a, b] = [grounds[i - 1].data, grounds[i].data];
          let moved = 0;
          for (let k = 0; k < masks[i].length; k++) {
            if (masks[i - 1][k] || masks[i][k]) continue;
            if (
              Math.abs(a[4 * k] - b[4 * k]) +
                Math.abs(a[4 * k + 1] - b[4 * k + 1]) +
                Math.abs(a[4 * k + 2] - b[4 * k + 2]) >
              24
            )
              moved++;
          }
          console.log(
            `${model.split('/').pop()} ticks ${TICKS[i - 1]}–${TICKS[i]}: ${moved} ground pixels changed by the shadow`,
          );
          assert.ok(
            moved > 0,
            `${model}: the shadow on the ground moves between ticks ${TICKS[i - 1]} and ${TICKS[i]}`,
          );
        }
      }
    } finally {
      await still.close();
    }
  },
);
