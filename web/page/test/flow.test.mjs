// The page's state machine (web/page/flow/flow.mjs), without a browser: the ways a task on its
// own and a protocol's participant go through the page are allowed, each step told to the
// page's header; a transition nobody listed is refused and changes nothing; a failure reaches the
// error state from anywhere; every state is reachable and none but the error is a dead end.

import assert from 'node:assert/strict';
import { test } from 'node:test';
import { Flow, State, TRANSITIONS } from '../flow/flow.mjs';

const { CONNECTING, INSTRUCTIONS, STARTING, TASK, DONE, STEP, PRACTICE, TYPING, ERROR } = State;

/** A Flow whose header is a list of [state, message] and whose log is a list of errors. */
function flow() {
  const logged = [];
  const f = new Flow({ log: (e) => logged.push(e) });
  const header = [];
  f.onChange((state, message) => header.push([state, message]));
  return { f, header, logged };
}

/** Goes through `states` in turn. */
const walk = (f, states) => states.forEach((s) => f.go(s));

test('the states are named constants, the strings window.grove.state shows', () => {
  assert.deepEqual(Object.values(State).sort(), ['connecting', 'done', 'error', 'instructions', 'practice', 'starting', 'step', 'task', 'typing']);
  assert.ok(Object.isFrozen(State));
  assert.throws(() => {
    State.TASK = 'other';
  }, TypeError);
  assert.equal(new Flow().state, CONNECTING, 'a page starts connecting');
});

test('a task on its own: connecting, instructions, the trigger, the task, saved; the header follows', () => {
  const { f, header } = flow();
  f.go(INSTRUCTIONS);
  f.go(INSTRUCTIONS, 'Press the trigger to start.');
  walk(f, [STARTING, TASK]);
  f.go(DONE, 'Saving…');
  f.go(DONE, 'Saved P01-ray-casting-7-1.jsonl: verified.');
  assert.equal(f.state, DONE);
  assert.equal(f.message, 'Saved P01-ray-casting-7-1.jsonl: verified.');
  assert.deepEqual(header, [
    [INSTRUCTIONS, ''],
    [INSTRUCTIONS, 'Press the trigger to start.'],
    [STARTING, ''],
    [TASK, ''],
    [DONE, 'Saving…'],
    [DONE, 'Saved P01-ray-casting-7-1.jsonl: verified.'],
  ]);
  assert.ok(f.is(DONE, ERROR) && !f.is(TASK));
});

test("a protocol's participant: instructions, practice, a task, questionnaires, typed answers, the headset taken off and put on again", () => {
  const { f } = flow();
  walk(f, [INSTRUCTIONS, INSTRUCTIONS, STEP, PRACTICE, STEP, STARTING, TASK, DONE, DONE, STEP, STEP]);
  // The headset's session ends on a step: back to the page's buttons, then in again.
  walk(f, [INSTRUCTIONS, STEP]);
  // The questionnaire's free text, typed on the page once the headset is off.
  walk(f, [TYPING, INSTRUCTIONS, STEP, TYPING, STEP]);
  // The session ends during a task and during the practice.
  walk(f, [STARTING, TASK, TYPING, STEP, PRACTICE, INSTRUCTIONS, PRACTICE, TYPING, PRACTICE, STARTING, TASK, DONE, PRACTICE]);
  assert.equal(f.state, PRACTICE);
});

test('a transition nobody listed is refused, and the page stays where it was', () => {
  const refused = [
    [[], TASK],
    [[], STEP],
    [[INSTRUCTIONS], DONE],
    [[INSTRUCTIONS, STARTING], STEP],
    [[INSTRUCTIONS, STARTING, TASK], STEP],
    [[INSTRUCTIONS, STARTING, TASK], STARTING],
    [[INSTRUCTIONS, STARTING, TASK, DONE], TASK],
    [[INSTRUCTIONS, STEP, TYPING], TYPING],
    [[INSTRUCTIONS], CONNECTING],
  ];
  for (const [path, to] of refused) {
    const { f, header } = flow();
    walk(f, path);
    const before = [f.state, header.length];
    assert.throws(() => f.go(to), new RegExp(`cannot go from ${f.state} to ${to}`), `${[CONNECTING, ...path].join(' -> ')} -> ${to}`);
    assert.deepEqual([f.state, header.length], before);
    assert.equal(f.can(to), false);
  }
});

test('a failure reaches the error state from every state, with its message, logged once', () => {
  const ways = { [CONNECTING]: [], [INSTRUCTIONS]: [INSTRUCTIONS], [STARTING]: [INSTRUCTIONS, STARTING], [TASK]: [INSTRUCTIONS, STARTING, TASK], [DONE]: [INSTRUCTIONS, STARTING, TASK, DONE], [STEP]: [INSTRUCTIONS, STEP], [PRACTICE]: [INSTRUCTIONS, PRACTICE], [TYPING]: [INSTRUCTIONS, STEP, TYPING], [ERROR]: [INSTRUCTIONS] };
  for (const [state, path] of Object.entries(ways)) {
    const { f, header, logged } = flow();
    walk(f, path);
    if (state === ERROR) f.fail('first');
    assert.equal(f.state, state);
    const e = new Error('the server refused the session');
    f.fail(e);
    assert.deepEqual([f.state, f.error, f.message], [ERROR, e.message, e.message], state);
    assert.deepEqual(header.at(-1), [ERROR, e.message]);
    assert.equal(logged.at(-1), e);
  }
  const { f } = flow();
  f.fail('no module');
  assert.equal(f.error, 'no module', 'a failure that is not an Error is its own message');
  assert.throws(() => f.go(TASK), /cannot go from error to task/, 'the error state is left only by the session ending');
  f.go(INSTRUCTIONS);
});

test('every state is reachable from connecting, and every state but error has a way on', () => {
  const next = new Map();
  for (const [from, to] of TRANSITIONS) {
    assert.ok(Object.values(State).includes(from), from);
    for (const t of to) assert.ok(Object.values(State).includes(t), t);
    next.set(from, [...(next.get(from) ?? []), ...to]);
  }
  const seen = new Set([CONNECTING]);
  const todo = [CONNECTING];
  while (todo.length) {
    for (const t of next.get(todo.pop()) ?? []) {
      if (seen.has(t)) continue;
      seen.add(t);
      todo.push(t);
    }
  }
  seen.add(ERROR); // Flow.fail, from any state
  assert.deepEqual([...seen].sort(), Object.values(State).sort());
  for (const s of Object.values(State)) assert.ok((next.get(s) ?? []).some((t) => t !== s), `${s} has a way on`);
  for (const [, , why] of TRANSITIONS) assert.ok(why.length > 10, 'each transition says why');
});
