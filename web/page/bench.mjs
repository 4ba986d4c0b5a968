#!/usr/bin/env node
// node web/page/bench.mjs [--frames N] [--note TEXT] [--out FILE]
//
// The headset page's figures (docs/headset.md, docs/benchmarks.md): the JavaScript each frame
// spends on the simulation's steps (with their input events), its snapshot and the scene's update
// (three.js objects from the snapshot: trees, ray, ball, box, menu, panel), in headless Chromium
// (SwiftShader) with IWER's Quest 3 in immersive-vr, on the study scene with 9 trees (its 2 and 7
// planted) while the controller sweeps across them (a new pose every frame); and the size of the
// bundle a headset loads. Drawing (WebGL) is not the page's JavaScript and is left out. Run after
// node web/page/build.mjs; prints one JSON object as `grove bench` does (or writes --out).

import { readFileSync, renameSync, writeFileSync } from 'node:fs';
import { cpus } from 'node:os';
import { join } from 'node:path';
import { WEB, start, ticks, until } from './test/harness.mjs';
import { aimAt, click, enterAndStart } from './test/participant.mjs';

const args = { frames: 600, note: null, out: null };
const argv = process.argv.slice(2);
for (let i = 0; i < argv.length; i += 2) {
  const [a, v] = [argv[i], argv[i + 1]];
  if (a === '--frames' && /^[1-9]\d{1,4}$/.test(v ?? '')) args.frames = Number(v);
  else if (a === '--note' && v) args.note = v;
  else if (a === '--out' && v) args.out = v;
  else {
    console.error(
      `error: unknown or incomplete argument ${a}; usage: node web/page/bench.mjs [--frames N] [--note TEXT] [--out FILE]`,
    );
    process.exit(2);
  }
}

const quantile = (xs, q) => {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor(q * s.length))];
};
const round = (x, d = 3) => Math.round(x * 10 ** d) / 10 ** d;

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
  // Seven trees of the current model on the ground in front, off the targets (the task goes on).
  for (let k = 0; k < 7; k++) {
    await aimAt(page, [-3 + k, 0, 1.5 - (k % 2)]);
    await click(page, 'trigger');
  }
  const trees = await page.evaluate(() => window.grove.snapshot.trees.length);
  if (trees !== own + 7 || own + 7 !== 9) throw new Error(`expected 9 trees, have ${trees}`);
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
    command: `node web/page/bench.mjs --frames ${args.frames}`,
    date: new Date().toISOString().slice(0, 10),
    build: `page.js minified by esbuild, headless Chromium ${version} (SwiftShader), IWER Quest 3 immersive-vr, Node ${process.versions.node}`,
    threads: 1,
    note:
      (args.note ? args.note + '; ' : '') +
      `per frame of the task, medians over ${perf.length} frames (${framed.length} with a step), the study scene with 9 trees, the controller sweeping across them (its ray last on ${hits ?? 'nothing'}); step: the simulation's steps with their input events, snapshot: the module's snapshot, update: the three.js scene from it; drawing (WebGL) left out, one frame in ten drawn; Chromium's performance.now() counts in steps of 0.1 ms here (no cross-origin isolation), so the means are given beside the medians`,
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
