// The page's own HTML (index.html) beside the 3D view: the header (the page's state, the
// connection, the file), and the panel with its title, text, the participant's form, the
// controls of the device in use, the buttons and a message line. What it shows is decided by
// the flow (flow/); this module only fills the elements in. On a phone in AR it is the DOM
// overlay over the camera's view.

import { typedForm } from './steps.mjs';

const ID = /^[A-Za-z0-9][A-Za-z0-9_-]{0,31}$/;

export class Screen {
  constructor(doc = document) {
    this.$ = (id) => doc.getElementById(id);
    this.doc = doc;
    this.enter = () => {};
  }

  /** What an enter button does: `enter(mode)` ('ar', 'vr' or 'inline'). */
  onEnter(enter) {
    this.enter = enter;
  }

  /** The canvas the view draws on, and the DOM overlay's root. */
  get canvas() {
    return this.$('canvas');
  }

  get overlay() {
    return this.$('overlay');
  }

  /** The phone's touch bar's element (input/touchbar.mjs), inside the overlay. */
  get touch() {
    return this.$('touch');
  }

  /** The header's state and the panel's message line. */
  state(state, message = '') {
    this.$('state').textContent = state;
    this.say(message);
  }

  say(message) {
    this.$('message').textContent = message;
  }

  /** The header's connection: its state and, when refused, the reason. */
  connection(state, reason) {
    const c = this.$('connection');
    c.dataset.state = state;
    c.textContent = `server: ${state}${reason ? ` (${reason})` : ''}`;
  }

  file(name) {
    this.$('file').textContent = name;
  }

  /** The header's line of the task's progress (a phone's, whose task panel is this line). */
  progress(text) {
    const p = this.$('progress');
    if (p.textContent !== text) p.textContent = text;
  }

  /** Shows or hides the panel (it hides while the preview shows a run or a step in the scene). */
  panel(visible) {
    this.$('panel').hidden = !visible;
  }

  /** The panel's title and text. */
  text(title, text) {
    this.$('title').textContent = title;
    this.$('instructions').textContent = text;
  }

  title(title) {
    this.$('title').textContent = title;
  }

  /** The participant's form: hidden or not, holding `participant` and `task` where given. */
  who({ hidden, participant, task }) {
    this.$('who').hidden = hidden;
    if (participant !== undefined) this.$('participant').value = participant;
    if (task !== undefined) this.$('task').value = task;
  }

  /** The participant and task the form holds (`fallback`'s where empty). */
  readWho(fallback) {
    const participant = this.$('participant').value || fallback.participant;
    const task = this.$('task').value || fallback.task;
    return { participant, task };
  }

  /** The controls table: rows [control, what it does]. */
  controls(rows) {
    this.$('controls').replaceChildren(
      ...rows.map(([k, v]) => {
        const tr = this.doc.createElement('tr');
        tr.innerHTML = '<td></td><td></td>';
        tr.children[0].textContent = k;
        tr.children[1].textContent = v;
        return tr;
      }),
    );
  }

  /** The panel's buttons (elements). */
  buttons(...elements) {
    this.$('buttons').replaceChildren(...elements);
  }

  /** A button to enter each mode the browser offers (`modes`: { ar, vr }), and the preview. */
  enterButtons(verb, modes) {
    const add = (label, mode) => {
      const b = this.doc.createElement('button');
      b.textContent = label;
      b.id = `enter-${mode}`;
      b.addEventListener('click', () => this.enter(mode));
      return b;
    };
    const list = [];
    if (modes.ar) list.push(add(`${verb} in AR`, 'ar'));
    if (modes.vr) list.push(add(`${verb} in VR`, 'vr'));
    list.push(add(`${verb} the preview (mouse)`, 'inline'));
    this.buttons(...list);
  }

  /** The form for answers typed once the headset is off: a textarea per row; `send(texts)`, its error shown. */
  typed(rows, send) {
    this.panel(true);
    this.buttons();
    this.controls([]);
    this.title('Please type these answers');
    typedForm(this.$('instructions'), rows, send, (m) => this.say(m));
  }
}

/** Throws unless `id` is a participant id: 1 to 32 letters, digits, _ or -, starting with a letter or digit. */
export function checkParticipant(id) {
  if (!ID.test(id)) throw new Error('a participant id is needed: 1 to 32 letters, digits, _ or -, starting with a letter or digit');
}
