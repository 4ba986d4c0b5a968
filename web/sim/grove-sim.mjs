// The JavaScript side of grove's simulation in WebAssembly (web/sim/README.md): loads the module
// that `bash web/build.sh` builds and wraps its C ABI (UTF-8 JSON strings in and out) as two
// classes, Grove and Sim. A plain ES module with no dependency, for Node and browsers alike.
//
//   import { loadGrove } from './grove-sim.mjs';
//   const grove = await loadGrove();                    // Node: target/wasm/grove_sim.wasm
//   const sim = grove.createSim({ scene: 'study', seed: 5, record: true, onLine: (l) => send(l) });
//   sim.push({ tick: 0, event: { kind: 'start_task', task: 'ray-casting-7' } });
//   sim.step();                                         // the lines it made, also given to onLine
//   const s = sim.snapshot();                           // trees, ray, anchor ball, box, menu, task, hash
//   sim.finish();                                       // the footer
//
// Every refusal (an unknown event kind, a value out of range, an event out of tick order, scene
// text that does not parse, a tick beyond the limit, …) throws a GroveError whose message names
// the problem; the simulation is then as it was before the call.

/** A call the module refused: its message is the module's one-line reason. */
export class GroveError extends Error {
  constructor(message) {
    super(message);
    this.name = 'GroveError';
  }
}

const encoder = new TextEncoder();
const decoder = new TextDecoder('utf-8', { fatal: false });

/** The module's bytes: a path or URL (read with node:fs in Node, fetched in a browser), or bytes. */
async function moduleBytes(source) {
  if (source instanceof WebAssembly.Module || source instanceof ArrayBuffer || ArrayBuffer.isView(source)) {
    return source;
  }
  const url = source ?? new URL('../../target/wasm/grove_sim.wasm', import.meta.url);
  const isNode = typeof process !== 'undefined' && process.versions?.node;
  if (isNode && (typeof url === 'string' || url.protocol === 'file:')) {
    const { readFile } = await import('node:fs/promises');
    return readFile(url);
  }
  const response = await fetch(url);
  if (!response.ok) {
    throw new GroveError(`cannot load the module from ${url}: HTTP ${response.status}`);
  }
  return response.arrayBuffer();
}

/** Loads the module (see moduleBytes) and returns a Grove. */
export async function loadGrove(source) {
  const bytes = await moduleBytes(source);
  const module = bytes instanceof WebAssembly.Module ? bytes : await WebAssembly.compile(bytes);
  const instance = await WebAssembly.instantiate(module, {});
  return new Grove(instance);
}

/** One instance of the module: makes simulations and replays recordings. */
export class Grove {
  constructor(instance) {
    this.exports = instance.exports;
  }

  /** Copies a string or bytes into the module's memory; returns [pointer, length]. */
  #put(data) {
    const bytes = typeof data === 'string' ? encoder.encode(data) : data;
    const ptr = this.exports.grove_alloc(bytes.length);
    new Uint8Array(this.exports.memory.buffer, ptr, bytes.length).set(bytes);
    return [ptr, bytes.length];
  }

  /** The last call's result as text. */
  #result() {
    const e = this.exports;
    return decoder.decode(new Uint8Array(e.memory.buffer, e.grove_result_ptr(), e.grove_result_len()));
  }

  /**
   * Calls `name` with the strings or bytes in `inputs` (each passed as pointer and length) after
   * the numbers in `numbers`; returns [status, result text]; throws a GroveError on a status
   * below 0.
   */
  call(name, numbers = [], inputs = []) {
    const held = inputs.map((d) => this.#put(d));
    let status;
    try {
      status = this.exports[name](...numbers, ...held.flat());
    } finally {
      for (const [ptr, len] of held) {
        this.exports.grove_free(ptr, len);
      }
    }
    const text = this.#result();
    if (status < 0) {
      throw new GroveError(text);
    }
    return [status, text];
  }

  /**
   * A new simulation. `options`: { scene, scene_text, seed, set: ['NAME=VALUE', …], record,
   * header (a header line made elsewhere), task, participant, synthetic, session_start, block,
   * technique }, or `stage: { min, max, aspect, wind, from }` (grove's model stage), as
   * web/sim/README.md describes, plus `onLine`, called with each recording line as it is made.
   */
  createSim(options = {}) {
    const { onLine, ...rest } = options;
    const [handle, made] = this.call('grove_sim_new', [], [JSON.stringify(rest)]);
    return new Sim(this, handle, splitLines(made), onLine);
  }

  /**
   * Replays a recording (its bytes or text) and verifies it as `grove replay` does. Returns
   * { report, task_line }: report has the fields of `grove replay --json` (wall_seconds and
   * speedup left to the caller). `options`: { file (its name in messages), scene_text (the scene
   * file's text when the header names one), until }. Throws a GroveError with the line `grove
   * replay` prints for bad input.
   */
  replay(recording, options = {}) {
    const bytes = typeof recording === 'string' ? encoder.encode(recording) : recording;
    const [, text] = this.call('grove_replay', [], [JSON.stringify(options), bytes]);
    return JSON.parse(text);
  }

  /**
   * The scene of a room a headset found in AR, as text (grove-systems' systems/src/room.rs):
   * `room` is { source (how the floor was found), floor_y, planes: [{ label, points: [{ x, y, z
   * }, …] }] (the horizontal planes found, in the simulation's frame), task }. The text is a
   * scene `grove serve` takes as `scene_text`.
   */
  roomScene(room) {
    return this.call('grove_room_scene', [], [JSON.stringify(room)])[1];
  }

  /** A built-in task: { id, mode ('ray-casting' or 'manual'), scene, tolerance, targets }. */
  task(id) {
    return JSON.parse(this.call('grove_task', [], [String(id)])[1]);
  }

  /**
   * Signs recording lines again as one checksum chain (version 2), as `grove replay --upgrade`
   * does: for tools that edit a recording's lines. `lines`: an array of lines.
   */
  rechain(lines) {
    return splitLines(this.call('grove_rechain', [], [lines.join('\n') + '\n'])[1]);
  }

  /**
   * The native renderer's wind displacement of a tree's vertices, by its CPU reference:
   * `{ wind (a snapshot's), tree (a snapshot's tree), points: [[x, y, z, height, trunk, branch,
   * phase], …] (model space and _WIND channels) }` → each vertex's world position [x, y, z].
   */
  windDisplace(input) {
    return JSON.parse(this.call('grove_wind_displace', [], [JSON.stringify(input)])[1]);
  }
}

function splitLines(text) {
  return text === '' ? [] : text.slice(0, -1).split('\n');
}

/** One simulation in the module. */
export class Sim {
  constructor(grove, handle, lines, onLine) {
    this.grove = grove;
    this.handle = handle;
    this.onLine = onLine;
    /** The lines made when it was created: a self-made recording's header line. */
    this.headerLines = lines;
    this.#hand(lines);
  }

  #hand(lines) {
    if (this.onLine) {
      for (const l of lines) {
        this.onLine(l);
      }
    }
    return lines;
  }

  /**
   * Queues an input event: an event line's object ({ tick, ms, frame, event: { kind, … } }) for
   * its tick, or an event alone ({ kind, … }) for the coming step. An object or its JSON text.
   */
  push(event) {
    this.grove.call('grove_sim_push', [this.handle], [typeof event === 'string' ? event : JSON.stringify(event)]);
  }

  /** Applies the coming tick's events and steps once; returns the recording lines made. */
  step() {
    return this.#hand(splitLines(this.grove.call('grove_sim_step', [this.handle])[1]));
  }

  /** The world: trees, controller ray and hit, anchor ball, bounding box, menu, task, tick, hash. */
  snapshot() {
    return JSON.parse(this.grove.call('grove_sim_snapshot', [this.handle])[1]);
  }

  /**
   * The ground planes, for drawing: [{ id, name, vertices: [x, y, z, …] (metres), triangles:
   * [i, j, k, …] (counter-clockwise seen from above) }], by entity id.
   */
  ground() {
    return JSON.parse(this.grove.call('grove_sim_ground', [this.handle])[1]);
  }

  /** The world hash, 16 hex digits. */
  hash() {
    return this.grove.call('grove_sim_hash', [this.handle])[1];
  }

  /** Completed steps. */
  get tick() {
    return this.grove.exports.grove_sim_tick(this.handle);
  }

  /** Applies what is still queued and writes the footer; returns the lines made. */
  finish() {
    return this.#hand(splitLines(this.grove.call('grove_sim_finish', [this.handle])[1]));
  }

  /** Frees the simulation in the module. */
  free() {
    this.grove.call('grove_sim_free', [this.handle]);
  }
}
