#!/usr/bin/env node
// node web/page/bench.mjs [--frames N] [--trees N] [--note TEXT] [--out FILE]
//
// The headset page's figures (docs/headset.md, docs/benchmarks.md): the JavaScript each frame
// spends on the simulation's steps (with their input events), its snapshot and the scene's update
// (three.js objects from the snapshot: trees, ray, ball, box, menu, panel), in headless Chromium
// (SwiftShader) with IWER's Quest 3 in immersive-vr, on the study scene with 9 trees (its 2 and 7
// planted) or --trees N (its 2 and the rest planted on a grid over the ground, farthest first,
// the study's 8 models in turn from the menu) while the controller sweeps across them (a new pose
// every frame); and the size of the
// bundle a headset loads. Drawing (WebGL) is not the page's JavaScript and is left out. Run after
// node web/page/build.mjs; prints one JSON object as `grove bench` does (or writes --out).

import { readFileSync, renameSync, writeFileSync } from 'node:fs';
import { cpus } from 'node:os';
import { join } from 'node:path';
import { WEB, start, ticks, until } from './test/harness.mjs';
import { aimAt, choose, click, enterAndStart } from './test/participant.mjs';

const args = { frames: 600, trees: 9, note: null, out: null };
const argv = process.argv.slice(2);
for (let i = 0; i < argv.length; i += 2) {
  const [a, v] = [argv[i], argv[i + 1]];
  if (a === '--frames' && /^[1-9]\d{1,4}$/.test(v ?? '')) args.frames = Number(v);
  else if (a === '--trees' && /^[1-9]\d{0,2}$/.test(v ?? '') && Number(v) >= 9) args.trees = Number(v);
  else if (a === '--note' && v) args.note = v;
  else if (a === '--out' && v) args.out = v;
  else {
    console.error(
      `error: unknown or incomplete argument ${a}; usage: node web/page/bench.mjs [--frames N] [--trees N (9 to 999)] [--note TEXT] [--out FILE]`,
    );
    process.exit(2);
  }
}

const quantile = (xs, q) => {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor(q * s.length))];
};
const round = (x, d = 3) => Math.round(x * 10 ** d) / 10 ** d;

/** The study site's holes and terrace (assets/scenes/study.ron): [x, z, radius] and its box. */
const HOLES = [
  [5.5, -4, 1.1],
  [-7.5, -9, 1.6],
  [-2, 4.5, 0.8],
  [10, 6, 1.3],
];
const TERRACE = { x: [4, 12], z: [-13.5, -8.5], y: 0.8 };

/**
 * Plants `n` trees on a grid over the study site's ground, 2 m apart, row by row from the far
 * edge (then the middles of its squares, the same way), the menu's models in turn: for each spot
 * the head stands low, 1.5 m nearer than the spot, so that the ray passes under the crowns
 * planted before it; a spot that plants nothing (the ray meets a crown) is passed over. The head
 * goes back where it stood.
 */
async function plantGrid(page, n) {
  const { models } = await page.evaluate(() => window.grove.snapshot.menu);
  const home = await page.evaluate(() => [
    window.xrDevice.position.x,
    window.xrDevice.position.y,
    window.xrDevice.position.z,
  ]);
  const spots = [];
  // A grid 2 m apart, then the middles of its squares.
  for (const [x0, z0] of [
    [-13, -13],
    [-12, -12],
  ])
    for (let z = z0; z <= 5; z += 2)
      for (let x = x0; x <= 13; x += 2) {
        if (HOLES.some(([hx, hz, r]) => Math.hypot(x - hx, z - hz) < r + 0.5)) continue;
        const terrace = x >= TERRACE.x[0] && x <= TERRACE.x[1] && z >= TERRACE.z[0] && z <= TERRACE.z[1];
        const edge = x > TERRACE.x[0] - 2 && x < TERRACE.x[1] + 2 && z > TERRACE.z[0] - 2 && z < TERRACE.z[1] + 2;
        if (terrace || !edge) spots.push([x, terrace ? TERRACE.y : 0, z]);
      }
  const per = Math.ceil(n / models.length);
  let planted = 0;
  let chosen = -1;
  try {
    for (const [x, y, z] of spots) {
      if (planted >= n) break;
      if (Math.floor(planted / per) !== chosen) {
        chosen = Math.floor(planted / per);
        await page.evaluate((h) => window.xrDevice.position.set(...h), home);
        await choose(page, models[chosen % models.length]);
      }
      await page.evaluate(
        (p) => {
          const s = window.grove.toSession(p);
          window.xrDevice.position.set(s.x, s.y, s.z);
        },
        [x, y + 0.7, z + 1.5],
      );
      const before = await page.evaluate(() => window.grove.snapshot.trees.length);
      await aimAt(page, [x, y, z]);
      await click(page, 'trigger');
      if ((await page.evaluate(() => window.grove.snapshot.trees.length)) > before) planted++;
    }
  } finally {
    await page.evaluate((h) => window.xrDevice.position.set(...h), home);
  }
}

const h = await start();
let result;
try {
  // Drawn one frame in ten, without antialiasing or shadows, so that SwiftShader leaves the frame
  // rate near a headset's and a frame runs about one step, as it does there.
  const { page } = await h.open('participant=BENCH&task=ray-casting-7&seed=1&quality=low&render_every=10', {
    xr: true,
    room: false,
  });
  await enterAndStart(page, 'vr');
  const own = await page.evaluate(() => window.grove.snapshot.trees.length);
  const count = () => page.evaluate(() => window.grove.snapshot.trees.length);
  if (args.trees === 9) {
    // Seven trees of the current model on the ground in front, off the targets (the task goes on).
    for (let k = 0; k < 7; k++) {
      await aimAt(page, [-3 + k, 0, 1.5 - (k % 2)]);
      await click(page, 'trigger');
    }
  } else await plantGrid(page, args.trees - own);
  const trees = await count();
  if (trees !== args.trees || (args.trees === 9 && own !== 2))
    throw new Error(`expected ${args.trees} trees, have ${trees}`);
  // The controller sweeps across the trees, a new pose every frame.
  await page.evaluate(() => {
    const c = window.xrDevice.controllers.right;
    const t0 = performance.now();
    const sweep = () => {
      // A yaw of ±0.35 rad about straight ahead, pitched 0.3 rad down (no roll).
      const yaw = 0.35 * Math.sin((performance.now() - t0) / 700);
      const [sy, cy, sp, cp] = [Math.sin(yaw / 2), Math.cos(yaw / 2), Math.sin(-0.15), Math.cos(-0.15)];
      c.quaternion.set(cy * sp, sy * cp, -sy * sp, cy * cp);
      window.__sweep = requestAnimationFrame(sweep);
    };
    sweep();
  });
  await ticks(page, 30);
  await page.evaluate(() => (window.grove.perf.length = 0));
  await until(page, (n) => window.grove.perf.length >= n, args.frames, 600000);
  const perf = (await page.evaluate(() => window.grove.perf)).slice(0, args.frames);
  const hits = await page.evaluate(() => window.grove.snapshot.controller.hit?.kind ?? null);
  const total = perf.map((p) => p.step + p.snapshot + p.update);
  const framed = perf.filter((p) => p.steps > 0);
  const build = JSON.parse(readFileSync(join(WEB, 'dist/build.json'), 'utf8'));
  const version = h.browser.version();
  result = {
    machine: `${cpus()[0]?.model?.trim() ?? 'unknown'}, ${cpus().length} cores`,
    command: `node web/page/bench.mjs --frames ${args.frames}${args.trees === 9 ? '' : ` --trees ${args.trees}`}`,
    date: new Date().toISOString().slice(0, 10),
    build: `page.js minified by esbuild, headless Chromium ${version} (SwiftShader), IWER Quest 3 immersive-vr, Node ${process.versions.node}`,
    threads: 1,
    note:
      (args.note ? args.note + '; ' : '') +
      `per frame of the task, medians over ${perf.length} frames (${framed.length} with a step), the study scene with ${trees} trees${trees === 9 ? '' : " (its 2 and the rest planted, the menu's models in turn)"}, the controller sweeping across them (its ray last on ${hits ?? 'nothing'}); step: the simulation's steps with their input events, snapshot: the module's snapshot, update: the three.js scene from it; drawing (WebGL) left out, one frame in ten drawn; Chromium's performance.now() counts in steps of 0.1 ms here (no cross-origin isolation), so the means are given beside the medians`,
    page_frame: {
      trees,
      frames: perf.length,
      steps_per_frame: round(perf.reduce((s, p) => s + p.steps, 0) / perf.length, 2),
      step_ms: round(
        quantile(
          framed.map((p) => p.step),
          0.5,
        ),
      ),
      snapshot_ms: round(
        quantile(
          framed.map((p) => p.snapshot),
          0.5,
        ),
      ),
      update_ms: round(
        quantile(
          perf.map((p) => p.update),
          0.5,
        ),
      ),
      total_ms: round(quantile(total, 0.5)),
      total_ms_p95: round(quantile(total, 0.95)),
      total_ms_mean: round(total.reduce((a, b) => a + b, 0) / total.length),
      step_ms_per_step_mean: round(framed.reduce((a, p) => a + p.step, 0) / framed.reduce((a, p) => a + p.steps, 0)),
      goal_ms: 3,
    },
    page_bundle: {
      page_js_bytes: build.page_js_bytes,
      page_js_gzip_bytes: build.page_js_gzip_bytes,
      wasm_bytes: build.wasm_bytes,
      wasm_gzip_bytes: build.wasm_gzip_bytes,
    },
  };
  if (h.errors.length) throw new Error(h.errors.join('\n'));
} finally {
  await h.close();
}
const text = JSON.stringify(result, null, 2) + '\n';
if (args.out) {
  writeFileSync(`${args.out}.tmp`, text);
  renameSync(`${args.out}.tmp`, args.out);
}
process.stdout.write(text);
