// grove's page for a participant in a headset (docs/headset.md): the study's task in AR over the
// real floor where the browser offers it, else in VR, else an inline preview driven by the
// mouse; the simulation in the WebAssembly module, drawn with three.js; the recording streamed
// to `grove serve` through its client library.
//
// The page in rooms, after three.js's XR examples:
//   input/    the participant's input: one source per device, `poll(frame)` -> pose, buttons, axes
//   flow/     the page's states and transitions (flow.mjs), and what each does: entering a mode,
//             a task's run, a protocol's steps; frame.mjs runs one frame of them
//   view/     the renderer, the scene and the drawn features (draw/), each with `update(s)`
//   screen.mjs the page's HTML; scripting.mjs `window.grove`
// This file boots them and runs the frame loop.

import { loadGrove } from '../sim/grove-sim.mjs';
import { loadEnvironment } from './draw/sky.mjs';
import { Models } from './draw/world.mjs';
import { instructions, enter } from './flow/entry.mjs';
import { Flow, State } from './flow/flow.mjs';
import { frame } from './flow/frame.mjs';
import { studyIntro } from './flow/protocol.mjs';
import { worldOf } from './flow/task.mjs';
import { Recorder, storedSession } from './recorder.mjs';
import { Screen } from './screen.mjs';
import { install } from './scripting.mjs';
import { StudyApi } from './study.mjs';
import { View } from './view/view.mjs';
import { offeredModes } from './xr.mjs';

const params = new URLSearchParams(location.search);
const renderEvery = Math.max(1, Number(params.get('render_every') ?? 1) || 1);
const low = params.get('quality') === 'low';

/** The page's context: every module of flow/ acts on it. */
const app = {
  params,
  flow: new Flow(),
  screen: new Screen(document),
  recorder: new Recorder(location.href),
  view: null,
  grove: null, // the WebAssembly module
  run: null, // the task's or the practice's run (run.mjs)
  stored: storedSession(), // a session this browser left open, to continue
  study: null, // the participant's way through the server's protocol, if it runs one
  xr: null, // { session, base, ar, finder, started, pressed } while an immersive session runs
  input: null, // the participant's input (input/): the mouse's, or the XR session's
  world: null, // the world shown (flow/task.mjs's worldOf), null in AR before a run
  modes: null, // { ar, vr }: the immersive modes the browser offers
  home: null, // the study scene's head and field of view (the inline preview between runs)
  steps: { placed: false, down: false, busy: false, image: null, until: null }, // a step's panel
  /** The page's record, which window.grove shows (scripting.mjs). */
  page: {
    mode: null,
    participant: params.get('participant') ?? '',
    task: params.get('task') ?? 'ray-casting-7',
    seed: Number(params.get('seed') ?? 0) || 0,
    file: null,
    verification: null,
    noSqueeze: false,
    device: null,
    floorOutline: null,
    offset: null,
    floor: null,
    frameMs: [],
    /** The last frames of the task: { steps, step, snapshot, update } (ms), for the benchmark. */
    perf: [],
    frames: 0,
    resumed: false,
  },
};
const { flow, screen, page } = app;
install(app);
flow.onChange((state, message) => screen.state(state, message));
app.recorder.addEventListener('state', (e) => screen.connection(e.state, e.reason));
screen.onEnter((mode) => enter(app, mode).catch((e) => flow.fail(e)));

async function boot() {
  const models = new Models(new URL('models/shipped/', document.baseURI).href);
  app.view = new View(screen.canvas, { low, models });
  app.grove = await loadGrove(new URL('grove_sim.wasm', document.baseURI));
  const probe = app.grove.createSim({ scene: 'study' });
  const first = probe.snapshot();
  app.home = { head: first.head, fov_y: first.fov_y };
  const api = new StudyApi(location.href);
  const env = loadEnvironment(new URL('env/', document.baseURI)).catch(() => null); // grove's sky and ground
  const [modes, , protocol] = await Promise.all([offeredModes(), models.load(first.menu.models).catch(() => {}), api.protocol()]);
  app.modes = modes;
  app.view.setEnvironment(await env);
  app.world = worldOf(probe, probe.snapshot(), false);
  probe.free();
  const stored = app.stored;
  if (stored && ((page.participant && stored.participant !== page.participant) || (params.get('task') && stored.task !== page.task))) app.stored = null;
  if (protocol) await studyIntro(app, api, protocol);
  else instructions(app);
  app.view.loop(loop);
}

function loop(time, xrFrame) {
  const t0 = performance.now();
  page.frames++;
  const s = frame(app, time, xrFrame);
  const t1 = performance.now();
  app.view.update(s);
  if (app.run?.timing && flow.is(State.TASK)) {
    page.perf.push({ ...app.run.timing, update: performance.now() - t1 });
    if (page.perf.length > 2000) page.perf.shift();
  }
  page.frameMs.push(performance.now() - t0);
  if (page.frameMs.length > 600) page.frameMs.shift();
  if (page.frames % renderEvery === 0 || !app.run) app.view.render();
}

boot().catch((e) => flow.fail(e));
