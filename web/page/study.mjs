// The headset page led by a protocol (docs/protocol.md, "In the headset"): when `grove serve`
// runs one, the page follows the participant's steps as the server describes them, asking it
// for each (so that a reload resumes where the server says the participant is). The steps
// without the simulation are shown on a panel (draw/panel.mjs) and answered with the ray:
// instructions with a Continue button, a questionnaire one item at a time (form.mjs), the
// task's start, the end. Practice and tasks are the page's runs (flow/protocol.mjs, flow/task.mjs).

import { build, choicesFrom, choose, missingMessage, optionLines, rowOf, titleOf, typedAnswers } from './form.mjs';
import { itemLayout, textLayout } from './draw/questionnaire.mjs';
import { unreachable } from '../client/grove-client.mjs';

/** The server's protocol routes, with the token the page's URL carries. */
export class StudyApi {
  constructor(href) {
    const u = new URL(href);
    this.base = u.origin;
    this.token = u.searchParams.get('token');
  }

  async call(method, path, body) {
    const headers = { 'content-type': 'application/json' };
    if (this.token) headers.authorization = `Bearer ${this.token}`;
    let r;
    try {
      r = await fetch(this.base + path, { method, headers, cache: 'no-store', body: body === undefined ? undefined : JSON.stringify(body) });
    } catch (e) {
      throw Object.assign(new Error(unreachable(this.base, e, 0)), { status: 0 });
    }
    const v = await r.json().catch(() => ({}));
    if (!r.ok) throw Object.assign(new Error(v.error ?? `${r.status} ${r.statusText}`), { status: r.status, body: v });
    return v;
  }

  /** The protocol the server runs, or null when it runs none (its status says, without a 404 to log). */
  async protocol() {
    const status = await this.call('GET', '/api/status').catch(() => null);
    return status?.protocol ? this.call('GET', '/api/protocol') : null;
  }

  join(id) {
    return this.call('POST', '/api/protocol/participants', id ? { participant: id } : {});
  }

  get(id) {
    return this.call('GET', `/api/protocol/participants/${encodeURIComponent(id)}`);
  }

  answers(id, step, answers) {
    return this.call('POST', `/api/protocol/participants/${encodeURIComponent(id)}/answers`, { step, answers });
  }

  next(id, from) {
    return this.call('POST', `/api/protocol/participants/${encodeURIComponent(id)}/next`, { from });
  }
}

const draftKey = (p, step) => `grove-draft-${p}-${step}`;

function loadDraft(p, step) {
  try {
    return JSON.parse(localStorage.getItem(draftKey(p, step)) ?? 'null');
  } catch {
    return null;
  }
}

function saveDraft(p, step, v) {
  try {
    if (v) localStorage.setItem(draftKey(p, step), JSON.stringify(v));
    else localStorage.removeItem(draftKey(p, step));
  } catch {
    // No storage: a reload starts the questionnaire again.
  }
}

/** One participant's way through the protocol. */
export class Study {
  constructor(api, protocol, state) {
    this.api = api;
    this.protocol = protocol;
    this.set(state);
  }

  /** Takes the server's state of the participant. */
  set(state) {
    this.state = state;
    this.message = '';
    this.q = null;
    this.typing = null;
    const st = this.current;
    if (st?.kind === 'questionnaire') {
      const rows = st.instrument.items.map(rowOf);
      const draft = loadDraft(state.participant, state.step);
      const choices = { ...choicesFrom(rows, state.answers), ...(draft?.choices ?? {}) };
      this.q = { rows, choices, index: Math.min(draft?.index ?? 0, rows.length - 1) };
    }
  }

  get participant() {
    return this.state.participant;
  }

  /** The step the participant is at (null once done). */
  get current() {
    return this.state.done ? null : this.state.steps[this.state.step - 1];
  }

  /** What the page and the tests read: participant, step, kind, block, item. */
  summary() {
    const st = this.current;
    return {
      participant: this.participant,
      step: this.state.done ? null : this.state.step,
      steps: this.state.steps.length,
      kind: st?.kind ?? 'done',
      block: st?.block ?? null,
      item: this.q ? this.q.rows[this.q.index].id : null,
      typing: this.typing ? this.typing.map((r) => r.id) : null,
      message: this.message,
    };
  }

  /** The panel's boxes for the step (`size`: the canvas's pixels); `extra` for the task and practice steps. */
  layout(size, { image = null, seconds = null, taskText = '' } = {}) {
    const st = this.current;
    const message = this.message;
    if (!st) return textLayout(size, { title: 'Thank you', text: 'The session is over. You can take the headset off.' });
    if (this.typing) {
      const n = this.typing.length;
      const text = `Thank you. ${n === 1 ? 'One answer is' : `${n} answers are`} to be typed: leave the headset's view, take the headset off and type ${n === 1 ? 'it' : 'them'} on the page.`;
      return textLayout(size, { title: titleOf(st), text, message, buttons: [{ id: 'leave', label: 'Leave' }] });
    }
    if (st.kind === 'instructions') {
      return textLayout(size, { title: st.block, text: st.text, image, note: st.video ? 'Watch the video on the screen.' : '', message, buttons: [{ id: 'continue', label: 'Continue' }] });
    }
    if (st.kind === 'practice') {
      const left = seconds === null ? '' : `${Math.max(0, Math.ceil(seconds))} s left`;
      return textLayout(size, { title: 'Practice', text: st.text ?? 'Try the controls.', note: left, message, buttons: [{ id: 'end-practice', label: 'End practice' }] });
    }
    if (st.kind === 'task') {
      return textLayout(size, { title: `Task: ${st.task}`, text: taskText, message, buttons: [{ id: 'start-task', label: 'Start' }] });
    }
    const { rows, choices, index } = this.q;
    return itemLayout(size, { title: titleOf(st), index, count: rows.length, row: rows[index], lines: optionLines(rows[index], choices), message });
  }

  #save() {
    saveDraft(this.participant, this.state.step, { choices: this.q.choices, index: this.q.index });
  }

  /**
   * A panel button pressed. Resolves to what the page must do: 'step' (the step changed: show
   * it), 'start-task', 'end-practice', 'typing' (answers to type on the page), 'leave' (end the
   * immersive session for them), or null (redraw).
   */
  async press(id) {
    const st = this.current;
    if (!st) return null;
    if (id === 'continue') return this.next();
    if (id === 'start-task' || id === 'end-practice' || id === 'leave') return id;
    if (!this.q || this.typing) return null;
    const q = this.q;
    const row = q.rows[q.index];
    if (id.startsWith('opt:')) {
      const k = Number(id.slice(4));
      q.choices = choose(q.choices, row, row.options[k].value);
      this.message = '';
    } else if (id === 'back') {
      q.index = Math.max(0, q.index - 1);
      this.message = '';
    } else if (id === 'next') {
      q.index = Math.min(q.rows.length - 1, q.index + 1);
      this.message = '';
    } else if (id === 'send') {
      return this.send();
    }
    this.#save();
    return null;
  }

  /** Sends the questionnaire's answers; a refusal (the page's or the server's) stays on the panel. */
  async send() {
    const q = this.q;
    const { answers, typed, missing } = build(q.rows, q.choices);
    if (missing.length) {
      this.message = missingMessage(q.rows, missing);
      q.index = q.rows.indexOf(missing[0]);
      this.#save();
      return null;
    }
    try {
      if (Object.keys(answers).length) this.state = await this.api.answers(this.participant, this.state.step, answers);
    } catch (e) {
      this.message = e.message;
      return null;
    }
    if (typed.length) {
      this.typing = typed;
      this.message = '';
      return 'typing';
    }
    saveDraft(this.participant, this.state.step, null);
    return this.next();
  }

  /** The page's form for the answers typed after the headset: `texts` by item. */
  async sendTyped(texts) {
    const { answers, missing } = typedAnswers(this.typing, texts);
    if (missing.length) throw new Error(missingMessage(this.typing, missing));
    if (Object.keys(answers).length) this.state = await this.api.answers(this.participant, this.state.step, answers);
    saveDraft(this.participant, this.state.step, null);
    return this.next();
  }

  /** On to the next step (the server checks that this one is finished). */
  async next() {
    try {
      this.set(await this.api.next(this.participant, this.state.step));
      return 'step';
    } catch (e) {
      // The server says where the participant is; another step than this one is shown instead.
      const moved = e.body?.state && e.body.state.step !== this.state.step;
      if (moved) this.set(e.body.state);
      this.message = e.message;
      return moved ? 'step' : null;
    }
  }

  /** Asks the server where the participant is (after a task's session has ended). */
  async refresh() {
    this.set(await this.api.get(this.participant));
  }
}
