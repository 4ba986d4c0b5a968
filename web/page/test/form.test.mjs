// The questionnaire panel's logic (web/page/form.mjs), on the instruments as the server
// describes them (tests/fixtures/questionnaires/forms.json, held to what the server sends by
// tests/integration/questionnaire_rules.rs, where what each kind of item takes is tested): the
// rows of buttons, choosing and toggling, the answers sent, what a missing answer says, and the
// text typed on the page.

import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { LATER, SKIP, build, buttonRows, choicesFrom, choose, isChosen, missingMessage, optionLines, rowOf, titleOf, typedAnswers } from '../form.mjs';

// The instruments of assets/protocols/tree-planting.ron (and every kind of item) as GET /api/protocol/participants/ID lists them.
const forms = JSON.parse(readFileSync(new URL('../../../tests/fixtures/questionnaires/forms.json', import.meta.url), 'utf8'));
const items = forms['tree-planting'].items.filter((i) => ['guidance', 'more_instructions', 'uses', 'would_use'].includes(i.id));
const rows = items.map(rowOf);
const tlx = rowOf(forms['nasa-tlx'].items[0]);

test('each item becomes its buttons as the server describes them, with the anchors at the ends', () => {
  assert.deepEqual(rows[0].options.map((o) => o.value), [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10]);
  assert.deepEqual(rows[0].anchors, ['Not at all', 'Very well']);
  assert.equal(rows[1].multi, true);
  assert.deepEqual(rows[1].options.map((o) => o.label), ['Ray-casting', 'Mode changing', 'Bounding box', 'Attaching to the ground']);
  assert.deepEqual(rows[3].options, [{ value: true, label: 'Yes' }, { value: false, label: 'No' }]);
  assert.equal(rows[2].typed, true);
  assert.equal(rows[2].maxChars, 2000);
  assert.deepEqual(rows[2].options.map((o) => o.value), [LATER, SKIP], 'an optional text item offers typing it later or skipping it');
  assert.deepEqual(rowOf({ ...items[2], required: true }).options, [], 'a required text item is always typed later');
  assert.equal(tlx.options.length, 21);
  assert.equal(tlx.options[20].value, 100);
  assert.deepEqual(buttonRows(tlx.options).map((r) => r.length), [11, 10], 'two balanced rows of at most 11');
  const words = rowOf(forms['every-kind'].items.find((i) => i.id === 'likert_words'));
  assert.deepEqual(words.options.map((o) => [o.value, o.label]), [[1, 'Strongly disagree'], [2, 'Disagree'], [3, 'Neutral'], [4, 'Agree'], [5, 'Strongly agree']]);
  assert.equal(words.anchors, null, 'a word on every point needs no anchors');
  assert.throws(() => rowOf({ id: 'x', text: 'X', kind: { Slider: {} } }), /'x' comes without its options/);
});

test('choosing replaces a single answer and toggles a multiple one, in the item\'s order', () => {
  let c = choose({}, rows[0], 3);
  c = choose(c, rows[0], 8);
  assert.equal(c.guidance, 8);
  c = choose(c, rows[1], 'Bounding box');
  c = choose(c, rows[1], 'Ray-casting');
  c = choose(c, rows[1], 'Mode changing');
  c = choose(c, rows[1], 'Mode changing');
  assert.deepEqual(c.more_instructions, ['Ray-casting', 'Bounding box']);
  assert.ok(isChosen(c, rows[1], 'Bounding box'));
  assert.ok(!isChosen(c, rows[1], 'Mode changing'));
  c = choose(c, rows[3], false);
  assert.ok(isChosen(c, rows[3], false));
  assert.ok(!isChosen(c, rows[3], true));
});

test('the answers sent hold every item answered in the headset, none of the typed ones', () => {
  let c = choose({}, rows[0], 8);
  c = choose(c, rows[3], true);
  let out = build(rows, c);
  assert.deepEqual(out.answers, { guidance: 8, more_instructions: [], would_use: true }, 'no choice of a multiple item is the answer "none"');
  assert.deepEqual(out.typed, [], 'an optional text item not chosen for typing is skipped');
  assert.deepEqual(out.missing, []);
  out = build(rows, choose(c, rows[2], LATER));
  assert.deepEqual(out.typed.map((r) => r.id), ['uses']);
  assert.ok(!('uses' in out.answers));
});

test('a required item without an answer stops the sending, and the panel says which', () => {
  const c = choose({}, rows[1], 'Ray-casting');
  const out = build(rows, c);
  assert.deepEqual(out.missing.map((r) => r.id), ['guidance', 'would_use']);
  assert.equal(missingMessage(rows, out.missing), 'Questions 1, 4 need an answer before sending.');
  assert.equal(missingMessage(rows, out.missing.slice(1)), 'Question 4 needs an answer before sending.');
  assert.equal(missingMessage(rows, []), '');
});

test('answers the server holds come back as choices; text typed on the page is trimmed and checked', () => {
  assert.deepEqual(choicesFrom(rows, { guidance: 5, uses: 'teaching', would_use: false }), { guidance: 5, uses: LATER, would_use: false });
  const required = rowOf({ ...items[2], id: 'why', required: true });
  assert.deepEqual(typedAnswers([rows[2], required], { uses: '  teaching  ', why: 'because' }), { answers: { uses: 'teaching', why: 'because' }, missing: [] });
  const none = typedAnswers([rows[2], required], { uses: ' ' });
  assert.deepEqual(none.answers, {});
  assert.deepEqual(none.missing.map((r) => r.id), ['why']);
});

test('the title names the instrument and the condition it follows', () => {
  assert.equal(titleOf({ block: 'tasks', condition: 'manual', instrument: { title: 'NASA Task Load Index (raw)' } }), 'NASA Task Load Index (raw) (manual)');
  assert.equal(titleOf({ block: 'questions', condition: null, instrument: { title: 'About the application' } }), 'About the application');
});

test('every item the server describes gives a row: options to choose, or typed text', () => {
  for (const [id, instrument] of Object.entries(forms)) {
    for (const item of instrument.items) {
      const row = rowOf(item);
      assert.ok(row.typed ? row.maxChars > 0 : row.options.length > 0, `${id} ${item.id}`);
    }
  }
});

test("the panel's lines: numbers side by side, more than two words one per line, the chosen ones on", () => {
  const c = choose(choose({}, rows[0], 7), rows[1], 'Bounding box');
  const rating = optionLines(rows[0], c);
  assert.equal(rating.length, 1);
  assert.deepEqual(rating[0].filter((b) => b.on).map((b) => [b.k, b.label]), [[7, '7']]);
  const multi = optionLines(rows[1], c);
  assert.deepEqual(multi.map((l) => l.map((b) => [b.k, b.on])), [[[0, false]], [[1, false]], [[2, true]], [[3, false]]]);
  assert.deepEqual(optionLines(rows[3], {}).map((l) => l.map((b) => b.label)), [['Yes', 'No']]);
  assert.deepEqual(optionLines(rows[2], { uses: LATER }).map((l) => l.map((b) => [b.label, b.on])), [[['Type it on the page', true], ['Skip it', false]]]);
  assert.deepEqual(optionLines(tlx, { mental: 100 }).map((l) => l.length), [11, 10]);
  assert.deepEqual(optionLines(tlx, { mental: 100 })[1].at(-1), { k: 20, label: '100', on: true });
});
