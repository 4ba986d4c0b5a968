// What the Node tests of the WebAssembly module share: the repository's paths, the native
// `grove` binary they compare with, the module, temporary folders and a scripted run.
//
// GROVE_BIN names the native binary (default target/debug/grove, which `cargo test` builds),
// GROVE_WASM the module (default target/wasm/grove_sim.wasm, which `bash web/build.sh` builds),
// GROVE_EXAMPLES the folder of grove-systems' examples (default target/debug/examples).

import { spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import { loadGrove } from '../grove-sim.mjs';

export const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../../..');
const target = process.env.CARGO_TARGET_DIR ? path.resolve(process.env.CARGO_TARGET_DIR) : path.join(root, 'target');
export const groveBin = process.env.GROVE_BIN ?? path.join(target, 'debug', 'grove');
export const examples = process.env.GROVE_EXAMPLES ?? path.join(target, 'debug', 'examples');
const wasm = process.env.GROVE_WASM ?? path.join(target, 'wasm', 'grove_sim.wasm');

for (const [what, file, how] of [
  ['the native grove binary', groveBin, 'cargo build'],
  ['the WebAssembly module', wasm, 'bash web/build.sh'],
]) {
  if (!existsSync(file)) {
    throw new Error(`${what} is missing at ${file}: run \`${how}\` first`);
  }
}

/** The module, loaded once per test file. */
export const grove = await loadGrove(readFileSync(wasm));

/** Runs native grove with `args` in the repository root; returns { status, stdout, stderr }. */
export function native(args, options = {}) {
  const r = spawnSync(groveBin, args, { cwd: root, encoding: 'utf8', maxBuffer: 64 << 20, ...options });
  if (r.error) {
    throw r.error;
  }
  return r;
}

/** Runs `node web/replay.mjs` with `args`. */
export function nodeReplay(args) {
  return spawnSync(process.execPath, [path.join(root, 'web', 'replay.mjs'), ...args], {
    cwd: root,
    encoding: 'utf8',
    env: { ...process.env, GROVE_WASM: wasm },
  });
}

/** A temporary folder, removed when the process ends. */
export function tempDir(t) {
  const dir = mkdtempSync(path.join(tmpdir(), 'grove-wasm-'));
  t.after(() => rmSync(dir, { recursive: true, force: true }));
  return dir;
}

/** A recording's lines, parsed. */
export function parseLines(text) {
  return text
    .split('\n')
    .filter((l) => l !== '')
    .map((l) => JSON.parse(l));
}

/**
 * Re-simulates a recording's events through the Sim API (push and step, as a page does) and
 * returns the world hash at each of its checkpoints and at its footer's tick.
 */
export function driveThrough(text) {
  const lines = text.split('\n').filter((l) => l !== '');
  const sim = grove.createSim({ header: lines[0] });
  const hashes = [];
  try {
    for (const line of lines.slice(1)) {
      const l = JSON.parse(line);
      const tick = l.type === 'footer' ? l.final_tick : l.tick;
      while (sim.tick < tick) {
        sim.step();
      }
      if (l.type === 'event') {
        sim.push(line);
      } else {
        hashes.push({ tick, expected: l.type === 'footer' ? l.final_hash : l.hash, actual: sim.hash() });
      }
    }
  } finally {
    sim.free();
  }
  return hashes;
}

/** A unit quaternion [x, y, z, w] turning −Z towards `dir` with no roll (yaw, then pitch). */
export function lookRotation([dx, dy, dz]) {
  const n = Math.hypot(dx, dy, dz);
  const yaw = Math.atan2(-dx / n, -dz / n);
  const pitch = Math.asin(dy / n);
  const [sy, cy, sp, cp] = [Math.sin(yaw / 2), Math.cos(yaw / 2), Math.sin(pitch / 2), Math.cos(pitch / 2)];
  return [cy * sp, sy * cp, -sy * sp, cy * cp];
}

/**
 * A scripted participant doing the ray-casting-7 task in a module simulation: for each target
 * from the snapshot, choose its model, aim from 2 m behind and 2.5 m above it, press and release
 * Trigger; then end the task. Returns the lines recorded (header first, footer last).
 */
export function scriptedTask(options = {}) {
  const lines = [];
  const sim = grove.createSim({
    scene: 'study',
    seed: 7,
    record: true,
    task: 'ray-casting-7',
    participant: 'W01',
    ...options,
    onLine: (l) => lines.push(l),
  });
  const stepTo = (tick) => {
    while (sim.tick < tick) {
      sim.step();
    }
  };
  sim.push({ tick: 0, event: { kind: 'start_task', task: 'ray-casting-7' } });
  stepTo(1);
  const targets = sim.snapshot().task.targets;
  let t = 30;
  for (const target of targets) {
    const [x, y, z] = target.position;
    const from = [x, y + 2.5, z + 2.0];
    sim.push({ tick: t, event: { kind: 'choose_model', model: target.model } });
    sim.push({
      tick: t + 1,
      event: {
        kind: 'controller_pose',
        pose: { position: from, rotation: lookRotation([x - from[0], y - from[1], z - from[2]]) },
      },
    });
    sim.push({ tick: t + 20, event: { kind: 'button_down', button: 'trigger' } });
    sim.push({ tick: t + 26, event: { kind: 'button_up', button: 'trigger' } });
    t += 70;
  }
  stepTo(t);
  const snapshot = sim.snapshot();
  sim.finish();
  sim.free();
  return { lines, snapshot };
}
