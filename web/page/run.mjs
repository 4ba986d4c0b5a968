// One task being run and recorded: the simulation in the WebAssembly module stepped at the
// scene's fixed step from the frame loop's time, the input events of each tick pushed before it
// is stepped, and every recording line the module makes handed to the recorder (which sends it
// in the background). A run is started on a new session, or continued from the lines a session
// already has (a page closed in the middle of the task and opened again).

import { FixedStep } from './clock.mjs';
import { edges, statesOf } from './input/buttons.mjs';
import { f32Pose, poseKey } from './input/pose.mjs';

/** The mode a task is done in, as the module's definition of it says; 'ray-casting' without a known task. */
export function modeOfTask(grove, task) {
  if (!task) return 'ray-casting';
  try {
    return grove.task(task).mode;
  } catch {
    return 'ray-casting'; // not a built-in task: the server refuses the session
  }
}

export class TaskRun {
  /** Use TaskRun.start or TaskRun.resume. */
  constructor(sim, recorder, { msAtStart = 0 } = {}) {
    this.sim = sim;
    this.recorder = recorder;
    this.clock = new FixedStep(sim.snapshot().dt);
    this.snapshot = sim.snapshot();
    this.models = this.snapshot.menu.models;
    const c = this.snapshot.controller;
    this.buttons = statesOf(c.buttons);
    this.axes = c.touchpad.map(Math.fround);
    this.scale = 0; // the Scale pad's value as last sent
    this.controllerKey = poseKey(c.pose);
    this.headKey = poseKey(this.snapshot.head);
    this.triggerToMenu = false;
    this.msAtStart = msAtStart;
    this.t0 = performance.now();
    this.lastTime = null;
    this.held = null; // buttons already down when the run's first frame came (the press that started it)
    this.finished = false;
    this.timing = null;
  }

  /**
   * A new run: the session's header line (as the server wrote it), the scene's text when it is
   * not built in, and the task to start at tick 0 (after switching to its mode), laid out as
   * `layout` says (`{ room: { floor } }`, systems/src/room_layout.rs) or as its file.
   */
  static start(grove, recorder, { header, sceneText, task, layout }) {
    const sim = grove.createSim({ header, scene_text: sceneText, onLine: (l) => recorder.append(l) });
    const run = new TaskRun(sim, recorder);
    if (task) {
      if (modeOfTask(grove, task) === 'manual')
        sim.push({ tick: 0, ms: 0, frame: 0, event: { kind: 'switch_mode', mode: 'manual' } });
      sim.push({ tick: 0, ms: 0, frame: 0, event: { kind: 'start_task', task, ...(layout ? { layout } : {}) } });
    }
    return run;
  }

  /**
   * Continues a session from its lines: re-simulates them (checking that the module makes the
   * same lines the file has) up to where the file ends; the lines made from then on are sent.
   */
  static resume(grove, recorder, { lines, sceneText }) {
    const sim = grove.createSim({ header: lines[0], scene_text: sceneText });
    const parsed = lines.slice(1).map((l) => JSON.parse(l));
    let end = 0;
    let lastMs = 0;
    const made = [];
    for (const line of parsed) {
      if (line.type === 'event') {
        while (sim.tick < line.tick) made.push(...sim.step());
        sim.push(line);
        end = Math.max(end, line.tick + 1);
        lastMs = Math.max(lastMs, line.ms);
      } else if (line.type === 'checkpoint') {
        end = Math.max(end, line.tick);
      } else if (line.type === 'footer') {
        throw new Error('the session has its footer already');
      }
    }
    while (sim.tick < end) made.push(...sim.step());
    const expected = lines.slice(1);
    for (let i = 0; i < expected.length; i++) {
      if (made[i] !== expected[i])
        throw new Error(`line ${i + 2} of the session does not re-simulate to the same line`);
    }
    sim.onLine = (l) => recorder.append(l);
    return new TaskRun(sim, recorder, { msAtStart: lastMs + 1 });
  }

  /** Milliseconds since the recording started (for the events' `ms`). */
  ms() {
    return Math.round(this.msAtStart + performance.now() - this.t0);
  }

  /**
   * One frame: runs the steps its time calls for. `input`: { controller, head } poses (position
   * [x, y, z], rotation [x, y, z, w]: input/pose.mjs) or null, `buttons` (grove's four, by name),
   * `axes` ([x, y]), `scale` (the Scale pad's value, a phone's; 0 or absent elsewhere), `frame`
   * (the frame's number), and `menuPick(origin, dir)` (the menu item the ray points at: a model's
   * index, `models.length` for "finish the task", or -1). Returns the
   * number of steps run; `this.snapshot` is the world after them.
   */
  frame(time, input) {
    if (this.finished) return 0;
    const elapsed = this.lastTime === null ? 0 : (time - this.lastTime) / 1000;
    this.lastTime = time;
    const steps = this.clock.advance(elapsed);
    const t0 = performance.now();
    for (let k = 0; k < steps; k++) {
      const events = k === 0 ? this.#events(input) : [];
      const stamp = { tick: this.sim.tick, ms: this.ms(), frame: input.frame ?? 0 };
      for (const event of events) this.sim.push({ ...stamp, event });
      this.sim.step();
    }
    const t1 = performance.now();
    if (steps > 0) this.snapshot = this.sim.snapshot();
    // What this frame's JavaScript spent (ms): the steps with their events, and the snapshot.
    this.timing = { steps, step: t1 - t0, snapshot: performance.now() - t1 };
    return steps;
  }

  /** The input events of the coming tick, in the order they apply: poses, axes, buttons. */
  #events(input) {
    const out = [];
    if (input.controller) {
      const pose = f32Pose(input.controller);
      const key = poseKey(pose);
      if (key !== this.controllerKey) {
        this.controllerKey = key;
        out.push({ kind: 'controller_pose', pose });
      }
    }
    if (input.head) {
      const pose = f32Pose(input.head);
      const key = poseKey(pose);
      if (key !== this.headKey) {
        this.headKey = key;
        out.push({ kind: 'head_pose', pose });
      }
    }
    const axes = (input.axes ?? [0, 0]).map(Math.fround);
    if (axes[0] !== this.axes[0] || axes[1] !== this.axes[1]) {
      this.axes = axes;
      out.push({ kind: 'touchpad_axes', axes });
    }
    const scale = Math.fround(input.scale ?? 0);
    if (scale !== this.scale) {
      this.scale = scale;
      out.push({ kind: 'scale_axis', value: scale });
    }
    const pressed = { ...(input.buttons ?? {}) };
    // A button already down in the run's first frame (the trigger or tap that started the task)
    // counts only once it has been let go: it plants nothing where the ray happens to be.
    this.held ??= new Set(Object.keys(pressed).filter((b) => pressed[b]));
    for (const b of [...this.held]) {
      if (pressed[b]) pressed[b] = false;
      else this.held.delete(b);
    }
    const now = { ...this.buttons, ...pressed };
    for (const e of edges(this.buttons, now)) {
      if (e.button === 'trigger' && e.kind === 'button_down' && this.snapshot.menu.open) {
        // The trigger chooses in the open menu; its press and release do not reach the world.
        this.triggerToMenu = true;
        const item = input.menuPick ? input.menuPick() : -1;
        if (item >= 0 && item < this.models.length) out.push({ kind: 'choose_model', model: this.models[item] });
        else if (item === this.models.length) out.push({ kind: 'end_task' }, { kind: 'close_menu' });
        else out.push({ kind: 'close_menu' });
        continue;
      }
      if (e.button === 'trigger' && e.kind === 'button_up' && this.triggerToMenu) {
        this.triggerToMenu = false;
        continue;
      }
      out.push(e);
    }
    this.buttons = now;
    return out;
  }

  /** Ends the recording (its footer) and the session; resolves to the server's verification. */
  async finish() {
    if (this.finished) return null;
    this.finished = true;
    this.sim.finish();
    return this.recorder.end();
  }
}
