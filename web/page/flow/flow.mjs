// The page's states and every transition between them (docs/headset.md, "The page"): the one
// place that says where the page may go from where it is. A task on its own:
//
//   connecting -> instructions -> starting -> task -> done                 (or error, from anywhere)
//
// and, when the server runs a protocol (flow/protocol.mjs), the participant's steps in turn:
//
//   connecting -> instructions -> step | practice | starting -> task -> done -> step … -> typing …
//
// The modules that act (flow/entry.mjs, flow/protocol.mjs, flow/task.mjs) ask the Flow to go;
// a transition not listed here is refused (an Error), so that a page never ends up in a state
// nobody meant. Pure: no DOM, tested by node --test (web/page/test/flow.test.mjs).

/** The page's states, as `window.grove.state` and the page's header show them. */
export const State = Object.freeze({
  CONNECTING: 'connecting',
  INSTRUCTIONS: 'instructions',
  STARTING: 'starting',
  TASK: 'task',
  DONE: 'done',
  STEP: 'step',
  PRACTICE: 'practice',
  TYPING: 'typing',
  ERROR: 'error',
});

const { CONNECTING, INSTRUCTIONS, STARTING, TASK, DONE, STEP, PRACTICE, TYPING, ERROR } = State;

/**
 * Every transition: [from, [to…], why]. ERROR is reachable from every state (Flow.fail) and is
 * not listed.
 */
export const TRANSITIONS = [
  [CONNECTING, [INSTRUCTIONS], 'the module, the models and the protocol (if any) are loaded'],
  [INSTRUCTIONS, [INSTRUCTIONS], 'an immersive mode entered (waiting for the trigger), a participant joined, a message'],
  [INSTRUCTIONS, [STARTING], 'the trigger in the headset, the preview entered, or a stored session continued'],
  [INSTRUCTIONS, [STEP, PRACTICE], "a protocol's participant entered a mode: their step"],
  [STARTING, [TASK], 'the session is open (or continued) and the run made'],
  [TASK, [DONE], "the task's targets are all planted, or Finish task was chosen"],
  [DONE, [DONE], 'the server verified the recording'],
  [DONE, [STEP, PRACTICE, STARTING], "a protocol's next step"],
  [STEP, [STEP, PRACTICE, STARTING], "a panel's button went on to the next step, or started the task"],
  [PRACTICE, [STEP, PRACTICE, STARTING], 'the practice ended: the next step'],
  [STEP, [TYPING], "the preview's questionnaire has answers to type"],
  [TYPING, [STEP, PRACTICE, STARTING], 'the typed answers sent: the next step'],
  [TYPING, [INSTRUCTIONS], 'the typed answers sent after the headset: enter again to go on'],
  [TASK, [INSTRUCTIONS], 'the immersive session ended during the task: start again to continue it'],
  [STARTING, [INSTRUCTIONS, TYPING], "the immersive session ended (a protocol's participant)"],
  [TASK, [TYPING], "the immersive session ended (a protocol's participant)"],
  [DONE, [INSTRUCTIONS, TYPING], "the immersive session ended (a protocol's participant)"],
  [STEP, [INSTRUCTIONS], "the immersive session ended (a protocol's participant)"],
  [PRACTICE, [INSTRUCTIONS, TYPING], "the immersive session ended (a protocol's participant)"],
  [INSTRUCTIONS, [TYPING], "the immersive session ended (a protocol's participant)"],
  [ERROR, [INSTRUCTIONS, TYPING], "the immersive session ended (a protocol's participant): back to the page's buttons"],
];

const NEXT = new Map(Object.values(State).map((s) => [s, new Set()]));
for (const [from, to] of TRANSITIONS) for (const t of to) NEXT.get(from).add(t);

export class Flow {
  /** `log(error)`: where a failure is logged (the console's by default). */
  constructor({ log = (e) => console.error(e) } = {}) {
    this.state = CONNECTING;
    this.message = '';
    this.error = null;
    this.log = log;
    this.listeners = [];
  }

  /** Whether the page is in one of `states`. */
  is(...states) {
    return states.includes(this.state);
  }

  /** Whether the page may go to `to` from where it is. */
  can(to) {
    return to === ERROR || Boolean(NEXT.get(this.state)?.has(to));
  }

  /** Goes to `to` with `message` (shown under the page's panel); a transition not listed throws. */
  go(to, message = '') {
    if (!this.can(to)) throw new Error(`the page cannot go from ${this.state} to ${to}`);
    this.state = to;
    this.message = message;
    for (const f of this.listeners) f(to, message);
  }

  /** Goes to ERROR with `e`'s message (from any state), and logs it. */
  fail(e) {
    this.error = String(e?.message ?? e);
    this.log(e);
    this.go(ERROR, this.error);
  }

  /** Calls `f(state, message)` on every transition. */
  onChange(f) {
    this.listeners.push(f);
  }
}
