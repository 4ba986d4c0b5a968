// The questionnaires' shared form code, without the page or three.js (docs/protocol.md): an
// instrument's items as the server describes them (src/protocol/form.rs works out what each item
// takes: its options and their labels, its anchors, several choices or typed text and its limit;
// src/protocol/answer.rs alone decides whether an answer fits) become rows of options; the
// participant's choices, the answers sent, and what is said when an answer is missing. The
// headset's panel (draw/questionnaire.mjs) draws these rows and hands back the button the ray
// chose; the form page (web/protocol/) lays them out as a form.
//
// Free text cannot be typed in a headset: a text item is answered on the page once the headset
// is off. A required one always is; an optional one is when the participant chooses "Type it on
// the page", and is skipped otherwise.

/** The most buttons in one row of the panel (a 0-100 scale in steps of 5 takes two rows). */
export const ROW_MAX = 11;

/** What a text item's buttons choose. */
export const LATER = 'later';
export const SKIP = 'skip';

/**
 * An item as the panel and the form show it, from the server's description of it: `{ id, text,
 * required, options: [{ value, label }], multi, anchors: [low, high] | null, typed, maxChars }`.
 * Options are the buttons (in order); `typed` is true for free text, whose panel buttons choose
 * LATER or SKIP (a required one has none: it is always typed later).
 */
export function rowOf(item) {
  if (!Array.isArray(item.options)) throw new Error(`item '${item.id}' comes without its options: the server describes every item with them`);
  const required = item.required !== false;
  const typed = Boolean(item.typed);
  const later = required ? [] : [{ value: LATER, label: 'Type it on the page' }, { value: SKIP, label: 'Skip it' }];
  return { id: item.id, text: item.text, required, options: typed ? later : item.options, multi: Boolean(item.multi), anchors: item.anchors ?? null, typed, maxChars: item.max_chars ?? null };
}

/** The rows of buttons an item's options are laid out in (at most ROW_MAX each, balanced). */
export function buttonRows(options) {
  if (options.length <= ROW_MAX) return options.length ? [options] : [];
  const n = Math.ceil(options.length / ROW_MAX);
  const per = Math.ceil(options.length / n);
  const rows = [];
  for (let i = 0; i < options.length; i += per) rows.push(options.slice(i, i + per));
  return rows;
}

/**
 * The panel's lines of buttons for `row`: [[{ k, label, on }]], `k` the option's index, `on`
 * whether it is chosen. Numbers side by side (two rows for a long scale); words one per line
 * when there are more than two of them.
 */
export function optionLines(row, choices) {
  const words = row.options.length > 2 && !row.typed && row.options.some((o) => String(o.label).length > 3);
  const lines = words ? row.options.map((o) => [o]) : buttonRows(row.options);
  return lines.map((line) => line.map((o) => ({ k: row.options.indexOf(o), label: o.label, on: isChosen(choices, row, o.value) })));
}

/**
 * The participant's choices so far: `{ [item]: value }` (a list for Multiple, LATER or SKIP for
 * free text). Returns new choices with `value` chosen for `row`: a multiple-choice option is
 * toggled, anything else replaces the earlier choice.
 */
export function choose(choices, row, value) {
  if (!row.multi) return { ...choices, [row.id]: value };
  const was = choices[row.id] ?? [];
  const now = was.includes(value) ? was.filter((v) => v !== value) : [...was, value];
  // In the order the item lists its choices, as the page's form sends them.
  return { ...choices, [row.id]: row.options.map((o) => o.value).filter((v) => now.includes(v)) };
}

/** Whether `value` is chosen for `row`. */
export function isChosen(choices, row, value) {
  const c = choices[row.id];
  return row.multi ? (c ?? []).includes(value) : c === value;
}

/**
 * The choices a participant would get back from the server: the answers it holds for the step
 * (after a reload, or answers sent before), text items already answered marked LATER.
 */
export function choicesFrom(rows, given = {}) {
  const out = {};
  for (const row of rows) {
    if (!(row.id in given)) continue;
    out[row.id] = row.typed ? LATER : given[row.id];
  }
  return out;
}

/** Whether `row` has an answer among `choices` (a multiple-choice item always has: none is one). */
export function answered(choices, row) {
  if (row.multi) return true;
  if (row.typed) return true; // typed on the page afterwards (a required one is checked there)
  return row.id in choices;
}

/** The rows of required items without an answer. */
export function missing(rows, choices) {
  return rows.filter((r) => r.required && !answered(choices, r));
}

/** What the panel says when `rows` (the missing ones) stop the answers from being sent. */
export function missingMessage(all, rows) {
  if (!rows.length) return '';
  const n = (r) => all.indexOf(r) + 1;
  if (rows.length === 1) return `Question ${n(rows[0])} needs an answer before sending.`;
  return `Questions ${rows.map(n).join(', ')} need an answer before sending.`;
}

/**
 * What the headset sends: `{ answers, typed, missing }`, where `answers` holds every item
 * answered in the headset (a multiple-choice item as the list of its chosen options, none
 * included), `typed` the text items to type on the page afterwards, `missing` the required
 * items not yet answered (nothing is sent while there are any).
 */
export function build(rows, choices) {
  const answers = {};
  const typed = [];
  for (const row of rows) {
    if (row.typed) {
      if (row.required || choices[row.id] === LATER) typed.push(row);
      continue;
    }
    if (row.multi) answers[row.id] = choices[row.id] ?? [];
    else if (row.id in choices) answers[row.id] = choices[row.id];
  }
  return { answers, typed, missing: missing(rows, choices) };
}

/**
 * The answers of the page's small form for the typed items: `texts` `{ [item]: string }`.
 * Empty optional answers are left out; returns `{ answers, missing }`.
 */
export function typedAnswers(typed, texts) {
  const answers = {};
  const absent = [];
  for (const row of typed) {
    const t = (texts[row.id] ?? '').trim();
    if (t) answers[row.id] = t;
    else if (row.required) absent.push(row);
  }
  return { answers, missing: absent };
}

/**
 * The answers of the form page (web/protocol/): `picked` holds, by item, the values of its
 * checked inputs as the page reads them (strings) or its text. Every item with something picked
 * is answered with its options' values (a multiple-choice item with the list of them, none
 * included); text as typed, left out when empty.
 */
export function formAnswers(rows, picked) {
  const answers = {};
  for (const row of rows) {
    const p = picked[row.id];
    if (row.typed) {
      if (typeof p === 'string' && p !== '') answers[row.id] = p;
      continue;
    }
    const chosen = row.options.filter((o) => (p ?? []).includes(String(o.value))).map((o) => o.value);
    if (row.multi) answers[row.id] = chosen;
    else if (chosen.length) answers[row.id] = chosen[0];
  }
  return answers;
}

/** The title line of a questionnaire step: the instrument's title and its condition, if any. */
export function titleOf(step) {
  const t = step.instrument?.title ?? step.block;
  return step.condition ? `${t} (${step.condition})` : t;
}
