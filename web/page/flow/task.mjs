// A task's run, from its start to its verification (docs/headset.md, "The page"): the
// simulation's frame placed where the participant stands (in AR on the floor the session found,
// with the room's scene built from its planes), the session opened on the server (or a stored one
// continued), the run stepped from each frame's input, and its recording ended and verified.
//
// `app` is the page's context (main.mjs): its flow, view, screen, recorder, the module (`grove`),
// the run, the XR session and the page's record (`page`, which window.grove shows).

import { State } from './flow.mjs';
import { TaskRun, modeOfTask } from '../run.mjs';
import { floorOf, horizontalPlanes, toSim } from '../room.mjs';
import { offsetFor } from '../xr.mjs';

/** The world a sim shows (the view's `s.world`): its ground, its first snapshot's trees, whether over a room (AR). */
export function worldOf(sim, snapshot, ar) {
  return { ar, ground: sim.ground(), snapshot };
}

/** Shows the run's world (a new one each run: its ground, its trees). */
export function showWorld(app, run) {
  app.world = worldOf(run.sim, run.snapshot, Boolean(app.xr?.ar));
}

/** The room's horizontal planes in the simulation's frame (AR): its floor plane, if any, the others (tables, shelves) and all of them. */
function roomPlanes(app, frame) {
  const { xr, page } = app;
  const found = horizontalPlanes(frame, xr.base);
  const sim = (p) => ({
    ...p,
    points: p.points.map((q) => toSim(page.offset, q).position),
    y: p.y - page.offset.position.y,
  });
  const floor = floorOf(found);
  const all = found.map(sim);
  return { floor: floor ? sim(floor) : null, others: all.filter((p) => p.y > 0.3 && p.y < 2.2).slice(0, 16), all };
}

/**
 * The task's layout in the room (AR, `layout=room` by default): the floor plane's outline, and
 * the outlines of the planes over it (kept out), in the simulation's frame, [x, z] as f32
 * (systems/src/room_layout.rs); null without a floor plane (a hit test or local-floor:
 * outdoors, the task file's layout) or with `layout=file`.
 */
function roomLayout(app, { floor, others }) {
  if (app.params.get('layout') === 'file' || !floor) return null;
  const outline = (p) => p.points.slice(0, 256).map((q) => [Math.fround(q.x), Math.fround(q.z)]);
  // At most 256 points in all (systems/src/room_layout.rs): the floor's, then the planes' that fit.
  let room = 256 - Math.min(256, floor.points.length);
  const keep = others.map(outline).filter((o) => (o.length <= room ? ((room -= o.length), true) : false));
  return { room: { floor: outline(floor), ...(keep.length ? { keep_out: keep } : {}) } };
}

/**
 * The scene text of the room, built by the module from the floor and `planes` of the frame the
 * task starts in (AR), for the task laid out as `layout` says (the targets it moves named).
 */
function roomText(app, planes, layout) {
  const { xr, page } = app;
  const found = planes.map((p) => ({ label: p.label, points: p.points }));
  return app.grove.roomScene({
    source: xr.finder.found.source,
    floor_y: xr.finder.found.y,
    planes: found,
    task: page.task || null,
    ...(layout ? { layout } : {}),
  });
}

/** Starts the task (a new session) or continues the stored one; `frame` is the XR frame it starts in. */
export async function startRun(app, frame) {
  const { flow, page, xr, view, recorder, screen } = app;
  // The device that started the task is the recording's; one that cannot do the task's mode is
  // refused here, with the reason (input/xr.mjs, `refuses`).
  const refusal = app.input?.refuses?.(modeOfTask(app.grove, page.task));
  if (refusal) throw new Error(`this device cannot do the ${modeOfTask(app.grove, page.task)} task: ${refusal}`);
  page.device = app.input?.device?.() ?? null;
  flow.go(State.STARTING);
  let sceneText;
  let layout = null;
  if (xr && !app.stored) {
    const viewer = frame.getViewerPose(xr.base);
    const floorY = xr.ar ? xr.finder.found.y : 0;
    page.offset = offsetFor(viewer.transform, floorY);
    page.floor = xr.ar ? xr.finder.found : null;
    view.placeSimRoot(page.offset);
    if (xr.ar) {
      const planes = roomPlanes(app, frame);
      layout = roomLayout(app, planes);
      sceneText = roomText(app, planes.all, layout);
    }
    page.floorOutline = layout?.room.floor ?? null;
  } else if (xr && app.stored) {
    page.offset = app.stored.offset ?? page.offset;
    if (page.offset) view.placeSimRoot(page.offset);
  }
  if (app.stored) {
    const back = await recorder.resume(app.stored);
    app.run = TaskRun.resume(app.grove, recorder, { lines: back.lines, sceneText: back.scene_text });
    page.resumed = true;
    page.file = app.stored.file;
  } else {
    const fields = { participant: page.participant, task: page.task, seed: page.seed };
    if (sceneText) fields.scene_text = sceneText;
    if (page.device) fields.device = page.device;
    const header = await recorder.open(fields, { offset: page.offset, mode: page.mode });
    app.run = TaskRun.start(app.grove, recorder, { header, sceneText, task: page.task, layout });
    page.file = recorder.session.file;
  }
  app.stored = null;
  screen.file(page.file);
  showWorld(app, app.run);
  // A phone's panel would cover the camera's view: its touch bar and header stay.
  screen.panel(page.mode !== 'inline' && page.device?.mapping !== 'screen');
  flow.go(State.TASK);
}

/**
 * One frame of the run (a task's or the practice's): this frame's input (input/sources.mjs,
 * input/mouse.mjs) as the run's events, the trigger choosing in the open menu through the item
 * under the ray.
 */
export function runFrame(app, { time, input, ray }) {
  const { run, flow, view } = app;
  if (!input) return;
  const buttons = { ...input.buttons };
  // In practice the trigger presses the panel's button when the ray is on the panel.
  if (flow.is(State.PRACTICE) && ray && view.features.panel.meets(ray[0], ray[1]))
    buttons.trigger = run.buttons.trigger;
  const menuPick = () => (ray ? view.features.menu.itemAt(ray[0], ray[1]) : -1);
  run.frame(time, {
    controller: input.pose,
    head: input.head,
    buttons,
    axes: input.axes,
    scale: input.scale,
    frame: app.page.frames,
    menuPick,
  });
}

/** Ends the task's recording; resolves once the server has verified it (window.grove.verification). */
export async function finishRun(app) {
  const { flow, page } = app;
  flow.go(State.DONE, 'Saving…');
  const result = await app.run.finish();
  page.verification = result?.verification ?? null;
  flow.go(State.DONE, `Saved ${page.file}: ${page.verification?.status ?? 'sent'}.`);
}

/** The end of a task on its own: the page's panel thanks the participant. */
export function thank(app) {
  app.screen.panel(true);
  app.screen.title('Thank you: the task is done.');
}
