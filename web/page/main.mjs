// grove's page for a participant in a headset (docs/headset.md): the study's task in AR over the
// real floor where the browser offers it, else in VR, else an inline preview driven by the
// mouse; the simulation in the WebAssembly module, drawn with three.js; the recording streamed
// to `grove serve` through its client library.
//
// The page is a small state machine:
//   connecting -> instructions -> (starting) -> task -> done     (or error)
// and, when the server runs a protocol (study.mjs), the participant's steps:
//   connecting -> instructions -> step (a panel) | practice | task -> … -> step (the end)
// `window.grove` is its state for the people running a session and for the tests.

import * as THREE from 'three';
import { loadGrove } from '../sim/grove-sim.mjs';
import { ButtonMapper, lacksSqueeze, touchpadAxes } from './input.mjs';
import { MouseInput } from './mouse.mjs';
import { roomSceneText, horizontalPlanes, toSession, toSim } from './room.mjs';
import { Recorder, storedSession } from './recorder.mjs';
import { TaskRun, modeOfTask } from './run.mjs';
import { FloorFinder, offeredModes, offsetFor, requestSession } from './xr.mjs';
import { Models, WorldView } from './draw/world.mjs';
import { createRenderer, environmentFor } from './draw/renderer.mjs';
import { loadEnvironment } from './draw/sky.mjs';
import { Overlay } from './draw/overlay.mjs';
import { Menu } from './draw/menu.mjs';
import { Hud } from './draw/hud.mjs';
import { Controllers } from './draw/controllers.mjs';
import { Panel } from './draw/panel.mjs';
import { controlsFor, hudLines, nextTarget, taskText } from './text.mjs';
import { Study, StudyApi } from './study.mjs';
import { button, loadImage, panelFrame, poseArrays, rememberParticipant, studyView, typedForm } from './steps.mjs';

const params = new URLSearchParams(location.search);
const $ = (id) => document.getElementById(id);
const renderEvery = Math.max(1, Number(params.get('render_every') ?? 1) || 1);
const low = params.get('quality') === 'low';

/** The page's state, read by the tests and shown in the header. */
const page = {
  state: 'connecting',
  mode: null,
  participant: params.get('participant') ?? '',
  task: params.get('task') ?? 'ray-casting-7',
  seed: Number(params.get('seed') ?? 0) || 0,
  file: null,
  verification: null,
  error: null,
  noSqueeze: false,
  offset: null,
  floor: null,
  frameMs: [],
  /** The last frames of the task: { steps, step, snapshot, update } (ms), for the benchmark. */
  perf: [],
  frames: 0,
  resumed: false,
  get snapshot() {
    return run?.snapshot ?? null;
  },
  get connection() {
    return recorder.state;
  },
  /** Lines handed to the client library and not yet on the server's disk. */
  get pending() {
    return recorder.pending;
  },
  /** The anchor ball as drawn: 'hidden', 'white' or 'green'. */
  overlayBall() {
    return overlay.ballState();
  },
  /** The middle of the menu's item for `model` in the simulation's frame (the menu must be open). */
  menuItemPoint(model) {
    const i = model === 'finish' ? menu.models.length - 1 : menu.models.indexOf(model);
    return i < 0 || !menu.isOpen ? null : menu.itemPoint(i);
  },
  /** A point of the simulation's frame in the XR session's local-floor space. */
  toSession(p) {
    return page.offset ? toSession(page.offset, { x: p[0], y: p[1], z: p[2] }) : { x: p[0], y: p[1], z: p[2] };
  },
  /** Where a point of the simulation's frame is on the inline preview's canvas, CSS pixels. */
  screenPoint(p) {
    const v = new THREE.Vector3(p[0], p[1], p[2]).project(camera);
    const r = renderer.domElement.getBoundingClientRect();
    return { x: r.left + ((v.x + 1) / 2) * r.width, y: r.top + ((1 - v.y) / 2) * r.height };
  },
  profiles: () => controllers?.profiles() ?? [],
};
window.grove = Object.defineProperties(page, studyView(() => study, () => panel));

const recorder = new Recorder(location.href);
let grove = null;
let models = null;
let env = null; // the sky's cube and the ground's texture (draw/sky.mjs)
let run = null;
let stored = storedSession();
let renderer;
let scene;
let simRoot; // the simulation's frame, placed in the session's reference space by the offset
let camera;
let world = null;
let overlay;
let menu;
let hud;
let controllers = null;
let mouse = null;
let xr = null; // { session, base, space, finder, mapper, ar }
let menuRay = null; // [origin, dir] of this frame's controller
let study = null; // the participant's way through the server's protocol, if it runs one
let panel; // the protocol's panel
let modes = null;
let home = null; // the study scene's head and field of view (the inline preview between runs)
const steps = { placed: false, down: false, busy: false, image: null, until: null };

function setState(state, message = '') {
  page.state = state;
  $('state').textContent = state;
  $('message').textContent = message;
}

function fail(e) {
  page.error = String(e?.message ?? e);
  setState('error', page.error);
  console.error(e);
}

recorder.addEventListener('state', (e) => {
  const c = $('connection');
  c.dataset.state = e.state;
  c.textContent = `server: ${e.state}${e.reason ? ` (${e.reason})` : ''}`;
});

function setupRenderer() {
  const canvas = $('canvas');
  renderer = createRenderer(canvas, { low });
  renderer.setPixelRatio(low ? 1 : Math.min(window.devicePixelRatio, 2));
  renderer.setSize(window.innerWidth, window.innerHeight, false);
  renderer.xr.enabled = true;
  scene = new THREE.Scene();
  simRoot = new THREE.Group();
  simRoot.name = 'simulation';
  scene.add(simRoot);
  camera = new THREE.PerspectiveCamera(60, window.innerWidth / window.innerHeight, 0.05, 200);
  overlay = new Overlay(simRoot);
  menu = new Menu(simRoot);
  hud = new Hud(simRoot);
  hud.label.mesh.visible = false;
  panel = new Panel(simRoot);
  window.addEventListener('resize', () => {
    if (renderer.xr.isPresenting) return;
    renderer.setSize(window.innerWidth, window.innerHeight, false);
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
  });
}

/** The world of a run: its ground once, its trees every frame. */
function showWorld(sim, ar) {
  if (world) simRoot.remove(world.root);
  world = new WorldView(simRoot, models, { ar, shadows: !low, sky: env?.cube, groundTexture: env?.ground, environment: environmentFor(renderer, { ar, cube: env?.cube }) });
  world.setGround(sim.ground());
}

async function main() {
  setupRenderer();
  grove = await loadGrove(new URL('grove_sim.wasm', document.baseURI));
  const probe = grove.createSim({ scene: 'study' });
  const catalogue = probe.snapshot().menu.models;
  home = { head: probe.snapshot().head, fov_y: probe.snapshot().fov_y };
  models = new Models(new URL('models/shipped/', document.baseURI).href);
  const api = new StudyApi(location.href);
  const envLoad = loadEnvironment(new URL('env/', document.baseURI)).then((e) => (env = e)).catch(() => {});
  const [offered, , protocol] = await Promise.all([offeredModes(), models.load(catalogue).catch(() => {}), api.protocol(), envLoad]);
  modes = offered;
  showWorld(probe, false);
  world.update(probe.snapshot());
  probe.free();
  if (stored && (page.participant && stored.participant !== page.participant)) stored = null;
  if (stored && params.get('task') && stored.task !== page.task) stored = null;
  if (protocol) await studyIntro(api, protocol);
  else instructions(modes);
  renderer.setAnimationLoop(loop);
}

/** The instructions block: who, which task, the controls, and how to enter. */
function instructions(modes) {
  setState('instructions');
  const resume = stored;
  if (resume) {
    page.participant = resume.participant;
    page.task = resume.task;
  }
  $('title').textContent = resume ? `Continue ${resume.file}` : `Task ${page.task}`;
  const who = $('who');
  who.hidden = Boolean(resume || params.get('participant'));
  $('participant').value = page.participant;
  $('task').value = page.task;
  $('instructions').textContent = taskText(page.task);
  renderControls(false);
  enterButtons(resume ? 'Continue' : 'Start');
}

/** The buttons that enter each mode the browser offers. */
function enterButtons(verb) {
  const buttons = $('buttons');
  buttons.replaceChildren();
  const add = (label, mode) => {
    const b = document.createElement('button');
    b.textContent = label;
    b.id = `enter-${mode}`;
    b.addEventListener('click', () => enter(mode).catch(fail));
    buttons.append(b);
  };
  if (modes.ar) add(`${verb} in AR`, 'ar');
  if (modes.vr) add(`${verb} in VR`, 'vr');
  add(`${verb} the preview (mouse)`, 'inline');
}

/** A protocol's participant: named in the URL, else joined by the Start button; then the enter buttons. */
async function studyIntro(api, protocol) {
  setState('instructions');
  $('who').hidden = true;
  $('controls').replaceChildren();
  const join = async (id) => {
    study = new Study(api, protocol, await api.join(id));
    page.participant = study.participant;
    if (!id) rememberParticipant(page.participant);
    if (stored && stored.participant !== page.participant) stored = null;
    studyButtons();
  };
  if (page.participant) return join(page.participant);
  $('title').textContent = `Study: ${protocol.name}`;
  $('instructions').textContent = 'Press Start when the researcher asks you to.';
  $('buttons').replaceChildren(button('join', 'Start', () => join(null), fail));
}

function studyButtons(message = '') {
  const s = study.summary();
  $('panel').hidden = false;
  $('title').textContent = `Participant ${s.participant}`;
  $('instructions').textContent = s.kind === 'done' ? 'The session is over. Thank you.' : `Step ${s.step} of ${s.steps}: ${s.block}. Put the headset on and enter to go on.`;
  enterButtons('Continue');
  setState('instructions', message);
}

/** Shows the participant's step: a panel, the practice's free scene, or a task (a stored one continues). */
function showStep() {
  const st = study.current;
  Object.assign(steps, { placed: false, image: null });
  hud.label.mesh.visible = false;
  menu.close();
  $('panel').hidden = page.mode === 'inline'; // the mouse points at the panel in the scene
  if (st?.kind === 'practice') return startPractice(st);
  if (st?.kind === 'task') {
    page.task = st.task;
    if (stored && stored.participant === page.participant && stored.task === st.task) return startRun(null).catch(fail);
  }
  if (st?.kind === 'instructions' && st.image) steps.image = loadImage(st.image, () => (panel.key = null));
  setState('step');
}

function startPractice(st) {
  run = new TaskRun(grove.createSim({ scene: st.scene ?? 'study' }), null);
  showWorld(run.sim, Boolean(xr?.ar));
  steps.until = st.seconds ? performance.now() + st.seconds * 1000 : null;
  hud.label.mesh.visible = Boolean(xr);
  setState('practice');
}

/** Ends the practice's run (it records nothing). */
function dropPractice() {
  run?.sim.free();
  run = null;
}

async function endPractice() {
  dropPractice();
  await study.next();
  showStep();
}

/** A frame of a step's panel: placed in front of the head, the ray's button highlighted, the trigger pressing it. */
function stepFrame(frame) {
  if (xr && !frame) return;
  const source = xr ? primarySource(xr.session) : null;
  let [head, ray, down] = [run?.snapshot.head ?? home.head, null, false];
  if (xr) {
    const viewer = inSim(frame.getViewerPose(xr.base)?.transform);
    if (viewer) head = poseArrays(viewer);
    const c = source ? inSim(frame.getPose(source.targetRaySpace, xr.base)?.transform) : null;
    if (c) ray = [poseArrays(c).position, forward(c.orientation)];
    down = Boolean(source?.gamepad?.buttons?.[0]?.pressed);
    controllers ??= new Controllers(scene);
  } else if (mouse) {
    if (!run) placeInlineCamera(home);
    const p = mouse.pose(camera, THREE);
    ray = [poseArrays(p).position, forward(p.orientation)];
    down = mouse.buttons.trigger;
  }
  const practice = page.state === 'practice';
  const seconds = steps.until === null ? null : (steps.until - performance.now()) / 1000;
  const boxes = study.layout(panel.size, { image: steps.image, seconds, taskText: taskText(study.current?.task) });
  const pressed = panelFrame(panel, steps, { head, ray, down, boxes, practice });
  if (pressed && !steps.busy) press(pressed, frame);
  if (practice && seconds !== null && seconds <= 0 && !steps.busy) press('end-practice', frame);
}

async function press(id, frame) {
  steps.busy = true;
  try {
    if (id === 'start-task' || id === 'end-practice') return await (id === 'start-task' ? startRun(frame) : endPractice());
    const r = await study.press(id);
    if (r === 'step' || (r === 'typing' && !xr)) (r === 'step' ? showStep : showTyped)();
    else if (r === 'leave') await xr?.session.end();
  } catch (e) {
    fail(e);
  } finally {
    steps.busy = false;
  }
}

/** The immersive session ended: the typed answers' form, or the buttons to enter again. */
function studyPaused() {
  if (page.state === 'practice') dropPractice();
  panel.hide();
  if (study.typing) return showTyped();
  studyButtons('The headset\'s session ended: enter again to go on.');
}

/** The page's small form for the answers typed once the headset is off. */
function showTyped() {
  setState('typing');
  $('panel').hidden = false;
  [$('buttons'), $('controls')].forEach((e) => e.replaceChildren());
  $('title').textContent = 'Please type these answers';
  const send = async (texts) => {
    if ((await study.sendTyped(texts)) !== 'step') throw new Error(study.message);
    if (xr || page.mode === 'inline') showStep();
    else studyButtons();
  };
  typedForm($('instructions'), study.typing, send, (m) => ($('message').textContent = m));
}

function renderControls(noSqueeze) {
  const rows = controlsFor(modeOfTask(page.task), noSqueeze, xr === null && page.mode === 'inline');
  $('controls').replaceChildren(
    ...rows.map(([k, v]) => {
      const tr = document.createElement('tr');
      tr.innerHTML = '<td></td><td></td>';
      tr.children[0].textContent = k;
      tr.children[1].textContent = v;
      return tr;
    }),
  );
}

function readWho() {
  if (!stored) {
    page.participant = $('participant').value || page.participant;
    page.task = $('task').value || page.task;
  }
  if (!/^[A-Za-z0-9][A-Za-z0-9_-]{0,31}$/.test(page.participant)) throw new Error('a participant id is needed: 1 to 32 letters, digits, _ or -, starting with a letter or digit');
}

/** Enters a mode: the inline preview starts at once, an immersive session waits for the trigger. */
async function enter(mode) {
  if (!study) readWho();
  page.mode = mode;
  $('buttons').replaceChildren();
  if (mode === 'inline') {
    mouse = new MouseInput($('canvas'));
    renderControls(false);
    if (study) return showStep();
    await startRun(null);
    return;
  }
  const session = await requestSession(mode, $('overlay'));
  renderer.xr.setReferenceSpaceType('local-floor');
  await renderer.xr.setSession(session);
  const base = renderer.xr.getReferenceSpace();
  xr = { session, base, finder: mode === 'ar' ? new FloorFinder(session, base) : null, mapper: null, ar: mode === 'ar', started: false, pressed: false };
  if (mode === 'ar') {
    if (world) simRoot.remove(world.root);
    world = null;
  }
  session.addEventListener('end', () => {
    xr = null;
    if (study) return studyPaused();
    if (page.state === 'task' || page.state === 'instructions') setState('instructions', 'The immersive session ended; the recording stays open: start again to continue it.');
  });
  hud.label.mesh.visible = true;
  if (study) return showStep();
  setState('instructions', 'Press the trigger to start.');
  if (stored) await startRun(null);
}

/** The scene text of the room, built in the frame the task starts (AR). */
function roomText(frame) {
  const floor = xr.finder.found;
  const planes = horizontalPlanes(frame, xr.base)
    .map((p) => ({ ...p, points: p.points.map((q) => toSim(page.offset, q).position), y: p.y - page.offset.position.y }))
    .filter((p) => p.y > 0.3 && p.y < 2.2)
    .slice(0, 16);
  const text = roomSceneText({ source: floor.source, floorY: floor.y, planes });
  const probe = grove.createSim({ scene: 'room.ron', scene_text: text });
  probe.push({ kind: 'start_task', task: page.task });
  probe.step();
  const moved = (probe.snapshot().task?.targets ?? []).map((t, i) => ({ target: i, model: t.model, from: t.position, to: t.moved_to })).filter((m) => m.to);
  probe.free();
  return roomSceneText({ source: floor.source, floorY: floor.y, planes, moved });
}

/** Starts the task (a new session) or continues the stored one; `frame` is the XR frame it starts in. */
async function startRun(frame) {
  setState('starting');
  let sceneText;
  if (xr && !stored) {
    const viewer = frame.getViewerPose(xr.base);
    const floorY = xr.ar ? xr.finder.found.y : 0;
    page.offset = offsetFor(viewer.transform, floorY);
    page.floor = xr.ar ? xr.finder.found : null;
    placeSimRoot();
    if (xr.ar) sceneText = roomText(frame);
  } else if (xr && stored) {
    page.offset = stored.offset ?? page.offset;
    placeSimRoot();
  }
  if (stored) {
    const back = await recorder.resume(stored);
    run = TaskRun.resume(grove, recorder, { lines: back.lines, sceneText: back.scene_text });
    page.resumed = true;
    page.file = stored.file;
    sceneText = back.scene_text;
  } else {
    const fields = { participant: page.participant, task: page.task, seed: page.seed };
    if (sceneText) fields.scene_text = sceneText;
    const header = await recorder.open(fields, { offset: page.offset, mode: page.mode });
    run = TaskRun.start(grove, recorder, { header, sceneText, task: page.task });
    page.file = recorder.session.file;
  }
  stored = null;
  $('file').textContent = page.file;
  showWorld(run.sim, Boolean(xr?.ar));
  world.update(run.snapshot);
  $('panel').hidden = page.mode !== 'inline' ? false : true;
  hud.label.mesh.visible = Boolean(xr);
  panel.hide();
  setState('task');
}

async function finishRun() {
  setState('done', 'Saving…');
  try {
    const result = await run.finish();
    page.verification = result?.verification ?? null;
    setState('done', `Saved ${page.file}: ${page.verification?.status ?? 'sent'}.`);
    if (study) {
      await study.next();
      return showStep();
    }
    $('panel').hidden = false;
    $('title').textContent = 'Thank you: the task is done.';
  } catch (e) {
    fail(e);
  }
}

/** Places the simulation's frame in the session's reference space (identity without an offset). */
function placeSimRoot() {
  const o = page.offset;
  if (!o) return;
  simRoot.position.set(o.position.x, o.position.y, o.position.z);
  simRoot.quaternion.set(o.orientation.x, o.orientation.y, o.orientation.z, o.orientation.w);
  simRoot.updateMatrixWorld(true);
}

/** A pose of the session's reference space in the simulation's frame. */
function inSim(t) {
  if (!t) return null;
  return page.offset ? toSim(page.offset, t.position, t.orientation) : { position: t.position, orientation: t.orientation };
}

/** The primary controller of an XR frame: the right hand's pointer, else any pointer. */
function primarySource(session) {
  const pointers = [...session.inputSources].filter((s) => s.targetRayMode === 'tracked-pointer' && s.gamepad);
  return pointers.find((s) => s.handedness === 'right') ?? pointers[0] ?? null;
}

const forward = (o) => {
  const q = new THREE.Quaternion(o.x, o.y, o.z, o.w);
  const d = new THREE.Vector3(0, 0, -1).applyQuaternion(q);
  return [d.x, d.y, d.z];
};

/** This frame's input from the XR session, in the simulation's frame. */
function xrInput(frame) {
  const source = primarySource(xr.session);
  const viewer = frame.getViewerPose(xr.base);
  const pose = source ? frame.getPose(source.targetRaySpace, xr.base) : null;
  if (source && !xr.mapper) {
    page.noSqueeze = lacksSqueeze(source.profiles, source.gamepad);
    xr.mapper = new ButtonMapper({ noSqueeze: page.noSqueeze });
    renderControls(page.noSqueeze);
  }
  const controller = inSim(pose?.transform);
  menuRay = controller ? [[controller.position.x, controller.position.y, controller.position.z], forward(controller.orientation)] : null;
  return {
    controller,
    head: inSim(viewer?.transform),
    buttons: source && xr.mapper ? xr.mapper.read(source.gamepad, run ? run.ms() : performance.now()) : {},
    axes: source ? touchpadAxes(source.gamepad) : [0, 0],
  };
}

/** This frame's input from the mouse (inline preview). */
function mouseInput() {
  const p = mouse.pose(camera, THREE);
  menuRay = [[p.position.x, p.position.y, p.position.z], forward(p.orientation)];
  return { controller: p, head: null, buttons: { ...mouse.buttons }, axes: mouse.touchpad() };
}

function placeInlineCamera(snap) {
  const h = snap.head;
  camera.position.set(...h.position);
  camera.quaternion.set(...h.rotation);
  const fov = THREE.MathUtils.radToDeg(snap.fov_y);
  if (Math.abs(camera.fov - fov) > 1e-3) {
    camera.fov = fov;
    camera.updateProjectionMatrix();
  }
}

function loop(time, frame) {
  const t0 = performance.now();
  page.frames++;
  if (xr && frame && page.state === 'instructions') {
    xr.finder?.frame(frame);
    const source = primarySource(xr.session);
    const down = Boolean(source?.gamepad?.buttons?.[0]?.pressed);
    if (down && !xr.pressed && !xr.started) {
      xr.started = true;
      startRun(frame).catch(fail);
    }
    xr.pressed = down;
    const viewer = frame.getViewerPose(xr.base);
    const pose = source ? frame.getPose(source.targetRaySpace, xr.base) : null;
    if (pose) {
      const p = inSim(pose.transform).position;
      hud.place({ position: [p.x, p.y, p.z] }, viewer ? inSim(viewer.transform).position : null);
    }
    const f = xr.finder?.found;
    hud.set(['grove: ' + page.task, f ? `floor: ${f.source}` : 'VR: the study scene', '!Press the trigger to start', `server: ${recorder.state}`]);
  }
  if (study && (page.state === 'step' || page.state === 'practice')) stepFrame(frame);
  if (run && (page.state === 'task' || page.state === 'practice')) {
    if (!xr) placeInlineCamera(run.snapshot);
    const input = xr ? (frame ? xrInput(frame) : null) : mouseInput();
    if (input) {
      input.frame = page.frames;
      input.menuPick = () => (menuRay ? menu.itemAt(menuRay[0], menuRay[1]) : -1);
      // In practice the trigger presses the panel's button when the ray is on the panel.
      if (page.state === 'practice' && menuRay && panel.meets(menuRay[0], menuRay[1])) input.buttons.trigger = run.buttons.trigger;
      run.frame(time, input);
    }
    if (page.state === 'task' && run.snapshot.task?.done) finishRun();
  }
  const snap = run?.snapshot;
  const t1 = performance.now();
  overlay.root.visible = page.state !== 'step' && page.state !== 'typing'; // the ray, box and targets of a run
  if (snap && page.state !== 'step') draw(snap, frame);
  else if (snap) world?.update(snap);
  if (run?.timing && page.state === 'task') {
    page.perf.push({ ...run.timing, update: performance.now() - t1 });
    if (page.perf.length > 2000) page.perf.shift();
  }
  if (page.state !== 'task' && xr && frame) controllers?.update(frame, xr.base);
  const ms = performance.now() - t0;
  page.frameMs.push(ms);
  if (page.frameMs.length > 600) page.frameMs.shift();
  if (page.frames % renderEvery === 0 || !run) renderer.render(scene, camera);
}

function draw(snap, frame) {
  const eye = xr ? null : camera.position;
  world?.update(snap);
  overlay.update(snap, eye ?? (snap.head ? { x: snap.head.position[0], y: snap.head.position[1], z: snap.head.position[2] } : null));
  if (snap.menu.open && !menu.isOpen) menu.open([...snap.menu.models, 'Finish task'], snap.head);
  if (!snap.menu.open && menu.isOpen) menu.close();
  if (menu.isOpen) menu.update(menuRay ? menu.itemAt(menuRay[0], menuRay[1]) : -1, snap.menu.current_model, 'Choose a model (trigger)');
  if (xr && frame) {
    if (!controllers) controllers = new Controllers(scene);
    controllers.update(frame, xr.base);
    const c = snap.controller.pose;
    hud.place(c, { x: snap.head.position[0], y: snap.head.position[1], z: snap.head.position[2] });
    hud.set(hudLines(snap, { noSqueeze: page.noSqueeze, connection: recorder.state, pending: recorder.pending, state: page.state, verification: page.verification }));
  } else {
    const next = nextTarget(snap);
    $('message').textContent = page.state === 'task' ? (next ? `Next: ${next.model}` : '') : $('message').textContent;
  }
}

main().catch(fail);
