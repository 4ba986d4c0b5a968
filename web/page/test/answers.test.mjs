// What the pages send for a questionnaire, written out for the server's rules to be tested on
// in Rust (tests/integration/questionnaire_rules.rs): the instruments as the server describes
// them (tests/fixtures/questionnaires/forms.json, which that Rust test holds to what the server
// sends) answered through the headset's panel logic (choose, build, typedAnswers) and the form
// page's (formAnswers, from the values its inputs hold), every option of every item in turn.
// The bodies made must be tests/fixtures/questionnaires/answers.json; GROVE_WRITE_FIXTURES=1
// writes them there instead (after a change to what the pages send or to the fixture protocols).

import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { test } from 'node:test';
import { LATER, SKIP, build, choose, formAnswers, rowOf, typedAnswers } from '../form.mjs';

const dir = new URL('../../../tests/fixtures/questionnaires/', import.meta.url);
const forms = JSON.parse(readFileSync(new URL('forms.json', dir), 'utf8'));

/**
 * The k-th text a participant types for `row`: some with spaces around, one at the item's limit,
 * none for an optional one; cut where the textarea's maxlength (the item's `max_chars`, on both
 * pages) stops the typing.
 */
function typedText(row, k) {
  if (k === 2 && !row.required) return '';
  const text = k === 1 ? 'x'.repeat(row.maxChars + 5) : `  answer ${k} to "${row.id}", with a comma  `;
  return text.slice(0, row.maxChars);
}

/** The k-th way through `rows`: option k of each item (cycling), a multiple-choice item's options whose bit of k is set. */
function pick(row, k) {
  if (row.multi) return row.options.filter((_, i) => (k >> i) & 1);
  return [row.options[k % row.options.length]];
}

/** What the headset sends for its k-th participant: the panel's answers, then the ones typed on the page. */
function headset(rows, k) {
  let choices = {};
  for (const row of rows) {
    if (row.typed) {
      if (!row.required) choices = choose(choices, row, k % 2 ? LATER : SKIP);
      continue;
    }
    for (const o of pick(row, k)) choices = choose(choices, row, o.value);
  }
  const sent = build(rows, choices);
  assert.deepEqual(sent.missing, [], 'every required item answered');
  const out = [{ page: 'headset', answers: sent.answers }];
  const texts = Object.fromEntries(sent.typed.map((row) => [row.id, typedText(row, k)]));
  const typed = typedAnswers(sent.typed, texts);
  if (Object.keys(typed.answers).length) out.push({ page: 'headset-typed', answers: typed.answers });
  return out;
}

/** What the form page sends for its k-th participant: the values of its checked inputs (as strings) and its texts. */
function formPage(rows, k) {
  const picked = Object.fromEntries(rows.map((row) => [row.id, row.typed ? typedText(row, k) : pick(row, k).map((o) => String(o.value))]));
  return [{ page: 'form', answers: formAnswers(rows, picked) }];
}

function made() {
  const out = [];
  for (const [id, instrument] of Object.entries(forms)) {
    const rows = instrument.items.map(rowOf);
    const ways = Math.max(...rows.map((r) => (r.multi ? 2 ** r.options.length : r.options.length)), 3);
    for (let k = 0; k < ways; k++) {
      for (const body of [...headset(rows, k), ...formPage(rows, k)]) out.push({ instrument: id, participant: k, ...body });
    }
  }
  return out;
}

test('the answers the headset and the form page send are the fixture the Rust rules are tested on', () => {
  const answers = made();
  const file = new URL('answers.json', dir);
  const text = JSON.stringify(answers, null, 1) + '\n';
  if (process.env.GROVE_WRITE_FIXTURES) writeFileSync(file, text);
  assert.equal(readFileSync(file, 'utf8'), text, 'the pages send otherwise: write the fixture again (GROVE_WRITE_FIXTURES=1) and run the Rust test');
  // Both pages answer every item they can, and send lists for multiple choices.
  const kinds = new Set(answers.map((a) => a.page));
  assert.deepEqual([...kinds].sort(), ['form', 'headset', 'headset-typed']);
  for (const a of answers.filter((x) => x.page !== 'headset-typed')) {
    for (const item of forms[a.instrument].items.filter((i) => i.multi)) assert.ok(Array.isArray(a.answers[item.id]), `${a.page} ${a.instrument} ${item.id}`);
  }
});
