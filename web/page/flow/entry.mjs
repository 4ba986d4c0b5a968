// The way into a task: the instructions on the page (who, which task, the controls, a button per
// mode the browser offers), then a mode entered: the inline preview with the mouse at once, or an
// immersive session (AR over the room, else VR) whose input (input/sources.mjs) waits for the
// trigger; the session's end leaves the recording open. A protocol's participant goes on to
// their step instead (flow/protocol.mjs).

import { State } from './flow.mjs';
import { showStep, studyPaused } from './protocol.mjs';
import { startRun } from './task.mjs';
import { MouseInput } from '../input/mouse.mjs';
import { XrInput } from '../input/sources.mjs';
import { TouchBar } from '../input/touchbar.mjs';
import { controllerControls } from '../input/xr.mjs';
import { modeOfTask } from '../run.mjs';
import { checkParticipant } from '../screen.mjs';
import { taskText } from '../text.mjs';
import { FloorFinder, requestSession } from '../xr.mjs';

/** The instructions block: who, which task, the controls, and how to enter. */
export function instructions(app) {
  const { flow, screen, page } = app;
  flow.go(State.INSTRUCTIONS);
  const resume = app.stored;
  if (resume) {
    page.participant = resume.participant;
    page.task = resume.task;
  }
  screen.text(resume ? `Continue ${resume.file}` : `Task ${page.task}`, taskText(modeOfTask(app.grove, page.task)));
  screen.who({ hidden: Boolean(resume || app.params.get('participant')), participant: page.participant, task: page.task });
  screen.controls(controllerControls(modeOfTask(app.grove, page.task), false)); // until the device is known
  screen.enterButtons(resume ? 'Continue' : 'Start', app.modes);
}

/** Enters a mode: the inline preview starts at once, an immersive session waits for the trigger. */
export async function enter(app, mode) {
  const { page, screen, view, flow } = app;
  if (!app.study) {
    if (!app.stored) Object.assign(page, screen.readWho(page));
    checkParticipant(page.participant);
  }
  page.mode = mode;
  screen.buttons();
  if (mode === 'inline') {
    app.input = new MouseInput(screen.canvas, view.camera);
    screen.controls(app.input.controls(modeOfTask(app.grove, page.task)));
    if (app.study) return showStep(app);
    return startRun(app, null);
  }
  const session = await requestSession(mode, screen.overlay);
  const base = await view.present(session);
  const ar = mode === 'ar';
  app.xr = { session, base, ar, finder: ar ? new FloorFinder(session, base) : null, started: false, pressed: false };
  // A phone (a handheld AR session, 'screen-space') gets the touch bar over the camera's view.
  const phone = ar && session.interactionMode === 'screen-space';
  const bar = new TouchBar(screen.touch);
  bar.show(phone);
  const ctx = { space: base, offset: () => page.offset, now: () => (app.run ? app.run.ms() : performance.now()), session, bar, snapshot: () => app.run?.snapshot ?? null };
  app.input = new XrInput(ctx, {
    onSource: (source) => {
      page.noSqueeze = source.noSqueeze;
      screen.controls(source.controls(modeOfTask(app.grove, page.task)));
    },
  });
  if (ar) app.world = null; // the room is the world until the task starts
  session.addEventListener('end', () => ended(app));
  if (app.study) return showStep(app);
  flow.go(State.INSTRUCTIONS, phone ? 'Tap the scene to start.' : 'Press the trigger (or pinch) to start.');
  if (app.stored) await startRun(app, null);
}

/** The immersive session ended: the recording stays open. */
function ended(app) {
  app.xr = null;
  app.screen.touch.hidden = true;
  app.input = null;
  if (app.study) return studyPaused(app);
  if (app.flow.is(State.TASK, State.INSTRUCTIONS)) app.flow.go(State.INSTRUCTIONS, 'The immersive session ended; the recording stays open: start again to continue it.');
}

/** A frame before the task in a headset: the room's floor looked for, the trigger starting the task. */
export function instructionsFrame(app, { frame, input }) {
  const xr = app.xr;
  if (!xr || !frame) return;
  xr.finder?.frame(frame);
  const unusable = app.input?.unusable?.();
  if (unusable) app.screen.say(`This device's input (${unusable.join(', ')}) is not one grove takes: a controller, hands, gaze and pinch, or a phone's screen.`);
  const down = Boolean(input?.buttons.trigger);
  if (down && !xr.pressed && !xr.started) {
    xr.started = true;
    startRun(app, frame).catch((e) => app.flow.fail(e));
  }
  xr.pressed = down;
}
