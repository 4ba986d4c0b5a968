// One frame of the page: the input polled once (input/: the pose, grove's buttons and the
// touchpad of the participant's pointer, and the head), the current state's work (WORK: the
// headset waiting for the trigger, a step's panel, the practice, the task), and the frame's
// state that the view draws (view/features.mjs lists its fields).

import { State } from './flow.mjs';
import { instructionsFrame } from './entry.mjs';
import { nextStep, stepFrame } from './protocol.mjs';
import { finishRun, runFrame, thank } from './task.mjs';
import { pointOf, rayOf } from '../input/pose.mjs';
import { hudLines, nextTarget } from '../text.mjs';

const { INSTRUCTIONS, STARTING, TASK, STEP, PRACTICE, TYPING } = State;

/** The task's frame: the run stepped; the task's end verified and followed by the next step or the thanks. */
function task(app, f) {
  runFrame(app, f);
  const snap = app.run.snapshot;
  if (snap.task?.done) {
    finishRun(app)
      .then(() => (app.study ? nextStep(app) : thank(app)))
      .catch((e) => app.flow.fail(e));
  } else if (!app.xr) {
    const next = nextTarget(snap);
    app.screen.say(next ? `Next: ${next.model}` : '');
  }
}

/** The practice's frame: its panel, then its run (unless the panel ended it). */
function practice(app, f) {
  stepFrame(app, f);
  if (app.run && app.flow.is(PRACTICE)) runFrame(app, f);
}

/** What each state does in a frame (the others only draw). */
const WORK = { [INSTRUCTIONS]: instructionsFrame, [STEP]: stepFrame, [PRACTICE]: practice, [TASK]: task };

/** Runs one frame of the page (`xrFrame`: the XR frame, if any); returns what the view draws. */
export function frame(app, time, xrFrame) {
  if (!app.xr && app.input) app.view.placeCamera(app.run?.snapshot ?? app.home);
  const input = app.input?.poll(xrFrame) ?? null;
  const f = { time, frame: xrFrame, input, ray: input?.pose ? rayOf(input.pose) : null };
  WORK[app.flow.state]?.(app, f);
  return drawn(app, f);
}

/** The frame's state for the view (`s`, view/features.mjs). */
function drawn(app, f) {
  const { flow, xr } = app;
  const snap = app.run?.snapshot ?? null;
  const live = flow.is(STEP, TYPING) ? null : snap;
  return {
    state: flow.state,
    world: app.world,
    snap,
    live,
    xr: xr && f.frame ? { frame: f.frame, space: xr.base } : null,
    ray: f.ray,
    eye: xr ? (live ? pointOf(live.head) : null) : app.view.camera.position,
    hud: hud(app, f, live),
    panel: flow.is(STEP, PRACTICE),
  };
}

/** The hud's lines and place: before the task what to press, then the task's; none off the headset or on a panel. */
function hud(app, { frame, input }, live) {
  const { xr, flow, page, recorder } = app;
  if (!xr || flow.is(STEP, TYPING, STARTING)) return null;
  if (!frame) return { lines: null, at: null, eye: null };
  if (flow.is(INSTRUCTIONS)) {
    const floor = xr.finder?.found;
    const lines = ['grove: ' + page.task, floor ? `floor: ${floor.source}` : 'VR: the study scene', '!Press the trigger to start', `server: ${recorder.state}`];
    return { lines, at: input?.pose ?? null, eye: input?.head ? pointOf(input.head) : null };
  }
  if (!live) return { lines: null, at: null, eye: null };
  const state = { noSqueeze: page.noSqueeze, mapping: page.device?.mapping, connection: recorder.state, pending: recorder.pending, state: flow.state, verification: page.verification };
  if (page.device?.mapping === 'screen') {
    // A phone's ray leaves its camera: the panel would stand in front of the lens; its first lines go in the header.
    app.screen.progress(hudLines(live, state).slice(0, 2).map((l) => l.replace(/^!/, '')).join(' · '));
    return null;
  }
  return { lines: hudLines(live, state), at: live.controller.pose, eye: pointOf(live.head) };
}
