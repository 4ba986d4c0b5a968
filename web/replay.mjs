#!/usr/bin/env node
// node web/replay.mjs FILE [--json] [--until TICK]
//
// Re-simulates a recording with grove's WebAssembly module (built by `bash web/build.sh`) and
// prints what `grove replay FILE` prints: its status, the checkpoints checked, the first
// divergence and the final hash, with the same exit codes: 0 verified or unverified (no
// checkpoints), 1 diverged, 2 unreadable or invalid input (one line on stderr). A scene file the
// header names is read as `grove replay` finds it: a .ron file inside the recording's folder or
// the working directory. GROVE_WASM names another module file.

import { realpath, readFile, stat } from 'node:fs/promises';
import path from 'node:path';
import { performance } from 'node:perf_hooks';

import { loadGrove } from './sim/grove-sim.mjs';

const USAGE = 'usage: node web/replay.mjs FILE [--json] [--until TICK]';
// systems/src/limits.rs: MAX_SCENE_BYTES.
const MAX_SCENE_BYTES = 8 << 20;

class BadInput extends Error {}

function parseArgs(argv) {
  const args = { file: null, json: false, until: undefined };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === '--json') {
      args.json = true;
    } else if (a === '--until') {
      const v = argv[++i];
      if (v === undefined || !/^\d+$/.test(v) || !Number.isSafeInteger(Number(v))) {
        throw new BadInput(`--until takes a tick (a whole number), not ${JSON.stringify(v ?? '')}`);
      }
      args.until = Number(v);
    } else if (a === '-h' || a === '--help') {
      console.log(USAGE);
      process.exit(0);
    } else if (a.startsWith('-')) {
      throw new BadInput(`unknown option ${a}; ${USAGE}`);
    } else if (args.file === null) {
      args.file = a;
    } else {
      throw new BadInput(`one recording at a time; ${USAGE}`);
    }
  }
  if (args.file === null) {
    throw new BadInput(USAGE);
  }
  return args;
}

/** The text of the scene file a header names, found as `grove replay` finds it, or undefined. */
async function sceneText(name, recordingDir) {
  if (typeof name !== 'string' || !name.endsWith('.ron') || path.isAbsolute(name)) {
    return undefined; // a built-in name, or one the module refuses with its reason
  }
  for (const folder of [recordingDir, process.cwd()]) {
    let root;
    let file;
    try {
      root = await realpath(folder);
      file = await realpath(path.join(folder, name));
    } catch {
      continue;
    }
    if (file !== root && !file.startsWith(root + path.sep)) {
      throw new BadInput(`scene ${JSON.stringify(name)} leads outside the recording's folder and the working directory; a recording may only name a scene file inside them`);
    }
    const info = await stat(file);
    if (!info.isFile()) {
      throw new BadInput(`scene ${JSON.stringify(name)} is not a regular file`);
    }
    if (info.size > MAX_SCENE_BYTES) {
      throw new BadInput(`scene ${JSON.stringify(name)} is larger than the limit of ${MAX_SCENE_BYTES} bytes per scene file`);
    }
    return readFile(file, 'utf8');
  }
  throw new BadInput(`scene ${JSON.stringify(name)}: no such file in the recording's folder or the working directory`);
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  let info;
  try {
    info = await stat(args.file);
  } catch (e) {
    throw new BadInput(`${args.file}: ${e.code === 'ENOENT' ? 'no such file' : e.message}`);
  }
  if (!info.isFile()) {
    throw new BadInput(`${args.file}: not a regular file`);
  }
  const bytes = await readFile(args.file);
  // The header's scene, if the first line reads; the module checks the line itself.
  let scene;
  try {
    const first = bytes.subarray(0, Math.max(0, bytes.indexOf(10))).toString('utf8');
    scene = JSON.parse(first).scene;
  } catch {
    scene = undefined;
  }
  const options = { file: args.file, until: args.until, scene_text: await sceneText(scene, path.dirname(args.file)) };
  const grove = await loadGrove(process.env.GROVE_WASM);
  const start = performance.now();
  const { report, task_line: taskLine } = grove.replay(bytes, options);
  report.wall_seconds = (performance.now() - start) / 1000;
  report.speedup = report.wall_seconds > 0 ? report.sim_seconds / report.wall_seconds : Infinity;
  if (args.json) {
    console.log(JSON.stringify(report, null, 2));
  } else {
    const state = report.first_divergence ? 'DIVERGED' : report.verified ? 'verified' : 'unverified (no checkpoint to compare; `grove replay --seal` adds them)';
    console.log(
      `${report.file}: ${state}, ${report.complete ? 'complete' : 'incomplete'} (${report.ticks} ticks, ${report.sim_seconds.toFixed(1)} s simulated in ${report.wall_seconds.toFixed(3)} s, ${report.speedup.toFixed(0)}x), ${report.checkpoints_checked} checkpoints, final hash ${report.final_hash}`,
    );
    const d = report.first_divergence;
    if (d) {
      const what = d.differing.map((x) => `entity ${x.entity} ${x.component}`).join(', ');
      console.log(`  first divergence at tick ${d.tick}: expected ${d.expected_hash}, got ${d.actual_hash}; differs: ${what}`);
    }
    if (report.synthetic) {
      console.log("  note: a synthetic recording (generated by grove synth), not a person's session");
    }
    const dev = report.device;
    console.log(`  device: ${dev.mapping} (${dev.target_ray_mode}, ${dev.profile})`);
    if (taskLine) {
      console.log(`  ${taskLine}`);
      const p = report.task?.layout;
      if (p) {
        console.log(`  layout: room, the task file's spacing x${p.scale.toFixed(4)} in a floor of ${p.floor_size[0].toFixed(2)} x ${p.floor_size[1].toFixed(2)} m (${p.floor_m2.toFixed(1)} m²), every target at least ${p.edge_m.toFixed(2)} m from its edges`);
      }
    }
  }
  return report.first_divergence ? 1 : 0;
}

main().then(
  (code) => {
    process.exitCode = code;
  },
  (e) => {
    // Bad input, or a refusal by the module (a GroveError): one line, exit 2.
    const message = String(e?.message ?? e).replace(/[\r\n]+/g, ' ');
    process.stderr.write(`error: ${message}\n`);
    process.exitCode = 2;
  },
);
