#!/usr/bin/env node
// node web/bench.mjs [--native BIN] [--pairs N] [--note TEXT] [--out FILE]
//
// The WebAssembly module's figures (docs/wasm.md, docs/benchmarks.md): its size; a 5-minute
// study session, recorded by the module, re-simulated by the module under Node (the first run
// of a fresh instance, and the median of warm runs); one tick of the study scene with 9 trees,
// the controller aiming. With --native BIN (systems/examples/replay_speed.rs in release), the
// native build replays the same file, the two run in turn (A B A B, --pairs times) and the
// per-pair ratios are reported. Prints one JSON object as `grove bench` does (or writes --out).

import { spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { cpus, tmpdir } from 'node:os';
import path from 'node:path';
import { performance } from 'node:perf_hooks';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { gzipSync } from 'node:zlib';

import { loadGrove } from './sim/grove-sim.mjs';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const wasmFile = process.env.GROVE_WASM ?? path.join(root, 'target', 'wasm', 'grove_sim.wasm');

function parseArgs(argv) {
  const args = { native: null, pairs: 3, out: null, note: null };
  for (let i = 0; i < argv.length; i++) {
    const [a, v] = [argv[i], argv[i + 1]];
    if (a === '--native' && v) {
      args.native = v;
      i++;
    } else if (a === '--pairs' && /^[1-9]\d?$/.test(v ?? '')) {
      args.pairs = Number(v);
      i++;
    } else if (a === '--note' && v) {
      args.note = v;
      i++;
    } else if (a === '--out' && v) {
      args.out = v;
      i++;
    } else {
      throw new Error(
        `unknown or incomplete argument ${a}; usage: node web/bench.mjs [--native BIN] [--pairs N] [--note TEXT] [--out FILE]`,
      );
    }
  }
  return args;
}

const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
const round = (x, digits) => Math.round(x * 10 ** digits) / 10 ** digits;

/** A unit quaternion [x, y, z, w] turning −Z towards `dir` with no roll. */
function lookRotation([dx, dy, dz]) {
  const n = Math.hypot(dx, dy, dz);
  const yaw = Math.atan2(-dx / n, -dz / n);
  const pitch = Math.asin(dy / n);
  const [sy, cy, sp, cp] = [Math.sin(yaw / 2), Math.cos(yaw / 2), Math.sin(pitch / 2), Math.cos(pitch / 2)];
  return [cy * sp, sy * cp, -sy * sp, cy * cp];
}

const HAND = [0.25, 1.3, 5.7];
const aim = (target) => ({
  kind: 'controller_pose',
  pose: { position: HAND, rotation: lookRotation(target.map((c, i) => c - HAND[i])) },
});

/**
 * A 5-minute session recorded by the module: the controller sweeps over the ground at 30 Hz and
 * plants a tree every 8 s and removes one 4 s later (as `grove bench replay`'s session does).
 */
export function fiveMinuteSession(grove) {
  const lines = [];
  const sim = grove.createSim({ scene: 'study', seed: 7, record: true, onLine: (l) => lines.push(l) });
  const models = sim.snapshot().menu.models;
  const ticks = 300 * 60;
  for (let k = 0; 2 * k + 2 < ticks; k++) {
    const a = k * 0.02;
    const target = [6 * Math.sin(a), 0, -5 + 3 * Math.cos(0.7 * a)];
    const t = 2 * k;
    if (k % 240 === 0) {
      sim.push({ tick: t, event: { kind: 'choose_model', model: models[(k / 240) % models.length] } });
      sim.push({ tick: t, event: aim(target) });
      sim.push({ tick: t + 1, event: { kind: 'button_down', button: 'trigger' } });
      sim.push({ tick: t + 2, event: { kind: 'button_up', button: 'trigger' } });
    } else if (k % 240 === 120) {
      sim.push({ tick: t, event: aim([target[0], 2, target[2]]) });
      sim.push({ tick: t + 1, event: { kind: 'button_down', button: 'bumper' } });
      sim.push({ tick: t + 2, event: { kind: 'button_up', button: 'bumper' } });
    } else {
      sim.push({ tick: t, event: aim(target) });
    }
    while (sim.tick <= t) {
      sim.step();
    }
  }
  while (sim.tick < ticks) {
    sim.step();
  }
  sim.finish();
  sim.free();
  return Buffer.from(lines.join('\n') + '\n');
}

/** The module's replay of `bytes`, in a fresh instance: the first run, then warm runs. */
async function moduleReplay(bytes, warmRuns) {
  const grove = await loadGrove(readFileSync(wasmFile));
  const runs = [];
  let report;
  for (let i = 0; i <= warmRuns; i++) {
    const start = performance.now();
    report = grove.replay(bytes, { file: 'five-minutes.jsonl' }).report;
    runs.push((performance.now() - start) / 1000);
  }
  if (report.status !== 'verified') {
    throw new Error(`the 5-minute session did not verify in the module: ${report.status}`);
  }
  const warm = median(runs.slice(1));
  return {
    sim_seconds: report.sim_seconds,
    first_run_ms: round(runs[0] * 1e3, 2),
    first_run_speedup: Math.round(report.sim_seconds / runs[0]),
    wall_ms_median: round(warm * 1e3, 2),
    speedup_median: Math.round(report.sim_seconds / warm),
    verified: true,
  };
}

function nativeReplay(bin, file) {
  const r = spawnSync(bin, [file, '7'], { encoding: 'utf8' });
  if (r.status !== 0) {
    throw new Error(`${bin}: ${r.stderr || r.error}`);
  }
  return JSON.parse(r.stdout);
}

/** One tick of the study scene with 9 trees, a new controller pose every tick. */
function tickFigure(grove) {
  const sim = grove.createSim({ scene: 'study', seed: 7 });
  sim.push({ tick: 0, event: { kind: 'start_task', task: 'ray-casting-7' } });
  sim.step();
  let t = 10;
  for (const target of sim.snapshot().task.targets) {
    sim.push({ tick: t, event: { kind: 'choose_model', model: target.model } });
    const [x, y, z] = target.position;
    const from = [x, y + 2.5, z + 2];
    sim.push({
      tick: t + 1,
      event: {
        kind: 'controller_pose',
        pose: { position: from, rotation: lookRotation([x - from[0], y - from[1], z - from[2]]) },
      },
    });
    sim.push({ tick: t + 5, event: { kind: 'button_down', button: 'trigger' } });
    sim.push({ tick: t + 8, event: { kind: 'button_up', button: 'trigger' } });
    t += 30;
  }
  while (sim.tick < t) {
    sim.step();
  }
  const trees = sim.snapshot().trees.length;
  // The controller sweeps across the task area, over the trees and the ground.
  const batches = [];
  const snapshots = [];
  const kinds = [];
  for (let b = 0; b < 40; b++) {
    const start = performance.now();
    for (let i = 0; i < 100; i++) {
      const a = (b * 100 + i) * 0.01;
      sim.push(aim([8 * Math.sin(a), 0.5 + 0.5 * Math.sin(3 * a), -6 + 5 * Math.cos(0.7 * a)]));
      sim.step();
    }
    batches.push((performance.now() - start) / 100);
    const s = performance.now();
    const hit = sim.snapshot().controller.hit;
    snapshots.push(performance.now() - s);
    kinds.push(hit ? hit.kind : 'nothing');
  }
  sim.free();
  // The first 10 batches warm the engine up.
  return {
    trees,
    ms_per_tick_median: round(median(batches.slice(10)), 4),
    goal_ms: 0.2,
    snapshot_ms_median: round(median(snapshots.slice(10)), 4),
    ray_hits_tree_share: round(kinds.filter((k) => k === 'tree').length / kinds.length, 2),
    ray_hits_ground_share: round(kinds.filter((k) => k === 'plane').length / kinds.length, 2),
  };
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  const bytes = readFileSync(wasmFile);
  const result = {
    machine: `${cpus()[0]?.model ?? 'unknown CPU'}, ${cpus().length} cores`,
    command: `node web/bench.mjs${args.native ? ' --native target/release/examples/replay_speed' : ''} --pairs ${args.pairs}`,
    date: new Date().toISOString().slice(0, 10),
    build: `release, wasm32-unknown-unknown, Node ${process.versions.node}`,
    threads: 1,
    ...(args.note ? { note: args.note } : {}),
    wasm_module: {
      bytes: bytes.length,
      gzipped_bytes: gzipSync(bytes, { level: 9 }).length,
      goal_gzipped_bytes: 1.5e6,
    },
  };
  const grove = await loadGrove(bytes);
  const session = fiveMinuteSession(grove);
  const dir = mkdtempSync(path.join(tmpdir(), 'grove-bench-'));
  try {
    const file = path.join(dir, 'five-minutes.jsonl');
    writeFileSync(file, session);
    const replay = {};
    for (let p = 1; p <= args.pairs; p++) {
      replay[`module_${p}`] = await moduleReplay(session, 7);
      if (args.native) {
        replay[`native_${p}`] = nativeReplay(args.native, file);
      }
    }
    if (args.native) {
      replay.ratios = {
        module_over_native_wall: Array.from({ length: args.pairs }, (_, i) =>
          round(replay[`module_${i + 1}`].wall_ms_median / replay[`native_${i + 1}`].wall_ms_median, 2),
        ),
      };
    }
    result.wasm_replay = replay;
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
  result.wasm_tick = tickFigure(grove);
  const text = JSON.stringify(result, null, 2) + '\n';
  if (args.out) {
    writeFileSync(args.out, text);
  } else {
    process.stdout.write(text);
  }
}

if (process.argv[1] && import.meta.url === pathToFileURL(path.resolve(process.argv[1])).href) {
  main().catch((e) => {
    process.stderr.write(`error: ${String(e?.message ?? e).replace(/\n/g, ' ')}\n`);
    process.exitCode = 2;
  });
}
