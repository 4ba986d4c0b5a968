// A protocol's participant on the page (docs/protocol.md, "In the headset"): joined by the URL
// or the Start button, then each step as the server describes it (study.mjs): a panel answered
// with the ray (steps.mjs's panelFrame), the practice's free scene, a task (flow/task.mjs), the
// answers typed on the page once the headset is off; the immersive session's end brings the
// participant back to the page's buttons.

import { State } from './flow.mjs';
import { showWorld, startRun } from './task.mjs';
import { TaskRun } from '../run.mjs';
import { Study } from '../study.mjs';
import { button, loadImage, panelFrame, rememberParticipant } from '../steps.mjs';
import { modeOfTask } from '../run.mjs';
import { taskText } from '../text.mjs';

/** The participant named in the URL joins at once; else the page waits for the Start button. */
export async function studyIntro(app, api, protocol) {
  const { flow, screen, page } = app;
  flow.go(State.INSTRUCTIONS);
  screen.who({ hidden: true });
  screen.controls([]);
  const join = async (id) => {
    app.study = new Study(api, protocol, await api.join(id));
    page.participant = app.study.participant;
    if (!id) rememberParticipant(page.participant);
    if (app.stored && app.stored.participant !== page.participant) app.stored = null;
    studyButtons(app);
  };
  if (page.participant) return join(page.participant);
  screen.text(`Study: ${protocol.name}`, 'Press Start when the researcher asks you to.');
  screen.buttons(button('join', 'Start', () => join(null), (e) => flow.fail(e)));
}

/** Where the participant is, and the buttons to enter a mode and go on. */
function studyButtons(app, message = '') {
  const s = app.study.summary();
  app.screen.panel(true);
  app.screen.text(`Participant ${s.participant}`, s.kind === 'done' ? 'The session is over. Thank you.' : `Step ${s.step} of ${s.steps}: ${s.block}. Put the headset on and enter to go on.`);
  app.screen.enterButtons('Continue', app.modes);
  app.flow.go(State.INSTRUCTIONS, message);
}

/** Shows the participant's step: a panel, the practice's free scene, or a task (a stored one continues). */
export function showStep(app) {
  const { study, steps, page, flow } = app;
  const st = study.current;
  Object.assign(steps, { placed: false, image: null });
  app.screen.panel(page.mode !== 'inline'); // the mouse points at the panel in the scene
  if (st?.kind === 'practice') return startPractice(app, st);
  if (st?.kind === 'task') {
    page.task = st.task;
    const stored = app.stored;
    if (stored && stored.participant === page.participant && stored.task === st.task) return startRun(app, null).catch((e) => flow.fail(e));
  }
  if (st?.kind === 'instructions' && st.image) steps.image = loadImage(st.image, () => (app.view.features.panel.key = null));
  flow.go(State.STEP);
}

/** On to the participant's next step (the server says which). */
export async function nextStep(app) {
  await app.study.next();
  showStep(app);
}

function startPractice(app, st) {
  app.run = new TaskRun(app.grove.createSim({ scene: st.scene ?? 'study' }), null);
  showWorld(app, app.run);
  app.steps.until = st.seconds ? performance.now() + st.seconds * 1000 : null;
  app.flow.go(State.PRACTICE);
}

/** Ends the practice's run (it records nothing). */
function dropPractice(app) {
  app.run?.sim.free();
  app.run = null;
}

/** A frame of a step's panel: placed in front of the head, the ray's button highlighted, the trigger pressing it. */
export function stepFrame(app, { frame, input, ray }) {
  const { study, steps, flow, view } = app;
  if (app.xr && !frame) return;
  const head = input?.head ?? app.run?.snapshot.head ?? app.home.head;
  const down = Boolean(input?.buttons.trigger);
  const practice = flow.is(State.PRACTICE);
  const seconds = steps.until === null ? null : (steps.until - performance.now()) / 1000;
  const panel = view.features.panel;
  const boxes = study.layout(panel.size, { image: steps.image, seconds, taskText: taskText(modeOfTask(app.grove, study.current?.task)) });
  const pressed = panelFrame(panel, steps, { head, ray, down, boxes, practice });
  if (pressed && !steps.busy) press(app, pressed, frame);
  if (practice && seconds !== null && seconds <= 0 && !steps.busy) press(app, 'end-practice', frame);
}

async function press(app, id, frame) {
  const { steps, study } = app;
  steps.busy = true;
  try {
    if (id === 'start-task') return await startRun(app, frame);
    if (id === 'end-practice') {
      dropPractice(app);
      return await nextStep(app);
    }
    const r = await study.press(id);
    if (r === 'step') showStep(app);
    else if (r === 'typing' && !app.xr) showTyped(app);
    else if (r === 'leave') await app.xr?.session.end();
  } catch (e) {
    app.flow.fail(e);
  } finally {
    steps.busy = false;
  }
}

/** The immersive session ended: the typed answers' form, or the buttons to enter again. */
export function studyPaused(app) {
  if (app.flow.is(State.PRACTICE)) dropPractice(app);
  if (app.study.typing) return showTyped(app);
  studyButtons(app, "The headset's session ended: enter again to go on.");
}

/** The page's small form for the answers typed once the headset is off. */
function showTyped(app) {
  const { study, flow } = app;
  flow.go(State.TYPING);
  app.screen.typed(study.typing, async (texts) => {
    if ((await study.sendTyped(texts)) !== 'step') throw new Error(study.message);
    if (app.xr || app.page.mode === 'inline') showStep(app);
    else studyButtons(app);
  });
}
