// The participant's way through a protocol's steps (web/page/study.mjs) against a stand-in for
// the server's routes: a refusal of the server is shown on the panel and the panel stays; an
// accepted Send goes on to the next step; the typed items wait for the page.

import assert from 'node:assert/strict';
import { test } from 'node:test';
import { Study } from '../study.mjs';

const SIZE = { w: 880, h: 640 };
const instrument = {
  id: 'tree-planting',
  title: 'About the application',
  items: [
    // As the server describes them: with what each takes (src/protocol/form.rs).
    { id: 'guidance', text: 'How well did the application guide you?', kind: { Rating: { anchors: ['Not at all', 'Very well'] } }, required: true, options: Array.from({ length: 11 }, (_, v) => ({ value: v, label: String(v) })), anchors: ['Not at all', 'Very well'], multi: false, typed: false, max_chars: null },
    { id: 'uses', text: 'What could it be used for?', kind: { Text: { max_chars: 2000 } }, required: false, options: [], anchors: null, multi: false, typed: true, max_chars: 2000 },
  ],
};
const state = (step, answers = {}) => ({
  participant: 'P09',
  step,
  done: false,
  answers,
  steps: [
    { step: 1, block: 'questions', kind: 'questionnaire', instrument, condition: null },
    { step: 2, block: 'usability', kind: 'instructions', text: 'Next: a few more questions.' },
  ],
});

/** A stand-in for StudyApi: records the calls, answers with `reply(kind, args)` or throws what it returns as an Error. */
function api(reply) {
  const calls = [];
  const call = (kind) => async (...args) => {
    calls.push([kind, ...args.slice(1)]);
    const r = reply(kind, args);
    if (r instanceof Error) throw r;
    return r;
  };
  return { calls, answers: call('answers'), next: call('next'), get: call('get') };
}

const texts = (boxes) => boxes.filter((b) => b.type === 'text').map((b) => b.text);

test("the server's refusal is shown on the panel, which stays at its step", async () => {
  const refusal = Object.assign(new Error("item 'guidance' takes a whole number from 0 to 10; 11 is out of range"), { status: 422 });
  const server = api((kind) => (kind === 'answers' ? refusal : state(2)));
  const s = new Study(server, { name: 'tree-planting' }, state(1));
  assert.equal(await s.press('opt:8'), null);
  assert.equal(await s.press('next'), null);
  assert.equal(s.summary().item, 'uses');
  assert.equal(await s.press('send'), null);
  assert.deepEqual(server.calls, [['answers', 1, { guidance: 8 }]]);
  assert.equal(s.summary().step, 1);
  assert.ok(texts(s.layout(SIZE)).includes(refusal.message), 'the reason on the panel');
  assert.deepEqual(s.layout(SIZE).filter((b) => b.type === 'button').map((b) => b.id), ['opt:0', 'opt:1', 'back', 'send']);
});

test('an accepted Send goes on to the next step; a typed item waits for the page first', async () => {
  let server = api((kind, args) => (kind === 'answers' ? state(1, args[2]) : state(2)));
  let s = new Study(server, {}, state(1));
  await s.press('opt:3');
  assert.equal(await s.send(), 'step');
  assert.deepEqual(server.calls.map((c) => c[0]), ['answers', 'next']);
  assert.deepEqual([s.summary().step, s.summary().kind], [2, 'instructions']);
  assert.deepEqual(s.layout(SIZE).filter((b) => b.type === 'button').map((b) => b.id), ['continue']);

  server = api((kind, args) => (kind === 'answers' ? state(1, args[2]) : state(2)));
  s = new Study(server, {}, state(1));
  await s.press('opt:10');
  await s.press('next');
  await s.press('opt:0'); // Type it on the page
  assert.equal(await s.press('send'), 'typing');
  assert.deepEqual(s.summary().typing, ['uses']);
  assert.deepEqual(server.calls, [['answers', 1, { guidance: 10 }]]);
  assert.deepEqual(s.layout(SIZE).filter((b) => b.type === 'button').map((b) => b.id), ['leave']);
  assert.equal(await s.sendTyped({ uses: ' planning ' }), 'step');
  assert.deepEqual(server.calls.slice(1), [['answers', 1, { uses: 'planning' }], ['next', 1]]);
});

test('a step the server does not let the participant leave keeps them there, with its reason', async () => {
  const intro = { ...state(1), steps: [{ step: 1, block: 'intro', kind: 'instructions', text: 'Hello' }] };
  const server = api(() => Object.assign(new Error('step 1: items not answered yet: guidance'), { status: 409, body: { state: intro } }));
  const s = new Study(server, {}, intro);
  assert.equal(await s.press('continue'), null);
  assert.equal(s.summary().message, 'step 1: items not answered yet: guidance');
  assert.ok(texts(s.layout(SIZE)).includes('step 1: items not answered yet: guidance'));
});

test('a refusal from another step than the one shown brings the participant to the server\'s step', async () => {
  const intro = { ...state(1), steps: [{ step: 1, block: 'intro', kind: 'instructions', text: 'Hello' }, state(1).steps[0]] };
  const server = api(() => Object.assign(new Error('participant P09 is at step 2, not 1'), { status: 409, body: { state: { ...intro, step: 2 } } }));
  const s = new Study(server, {}, intro);
  assert.equal(await s.press('continue'), 'step', 'the page shows the step the server names');
  assert.deepEqual([s.summary().step, s.summary().kind, s.summary().item], [2, 'questionnaire', 'guidance']);
  assert.equal(s.summary().message, 'participant P09 is at step 2, not 1');
});
