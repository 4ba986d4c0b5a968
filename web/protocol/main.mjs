// The participant's form page of a protocol run by `grove serve --protocol` (`/protocol`,
// docs/protocol.md): each step in turn as the server describes it, the questionnaires as forms
// outside the headset. The items' rows come from the headset page's form code (web/page/form.mjs:
// the server works out what each item takes, this page lays it out and collects the input; the
// server decides whether an answer fits). Bundled into web/dist/protocol.js by
// web/page/build.mjs; the page's markup is web/protocol/index.html.

import { formAnswers, optionLines, rowOf } from '../page/form.mjs';

const $ = (s) => document.querySelector(s);
const main = $('#main');
const params = new URLSearchParams(location.search);
let pid = params.get('participant') || localStorage.getItem('grove-participant');
let state = null;
let timer = null;

async function call(method, url, body) {
  const r = await fetch(url, { method, headers: { 'content-type': 'application/json' }, body: body === undefined ? undefined : JSON.stringify(body) });
  const v = await r.json().catch(() => ({}));
  if (!r.ok) throw Object.assign(new Error(v.error || r.statusText), { status: r.status, body: v });
  return v;
}

function el(tag, attrs = {}, ...kids) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v !== undefined && v !== null && v !== false) e.setAttribute(k, v === true ? '' : v);
  }
  for (const k of kids) e.append(k);
  return e;
}

function say(msg) {
  $('#error').textContent = msg || '';
}

async function start() {
  if (!pid) {
    main.replaceChildren(el('p', {}, 'Welcome. Press Start when the researcher asks you to.'), el('button', { id: 'start' }, 'Start'));
    $('#start').onclick = async () => {
      try {
        const s = await call('POST', '/api/protocol/participants', {});
        pid = s.participant;
        localStorage.setItem('grove-participant', pid);
        show(s);
      } catch (e) {
        say(e.message);
      }
    };
    return;
  }
  try {
    show(await call('GET', `/api/protocol/participants/${encodeURIComponent(pid)}`));
  } catch (e) {
    if (e.status === 404) {
      localStorage.removeItem('grove-participant');
      pid = null;
      start();
    } else say(e.message);
  }
}

async function next() {
  try {
    show(await call('POST', `/api/protocol/participants/${pid}/next`, { from: state.step }));
    say('');
  } catch (e) {
    if (e.body && e.body.state) state = e.body.state;
    say(e.message);
  }
}

function show(s) {
  state = s;
  clearInterval(timer);
  timer = null;
  $('#who').textContent = `Participant ${s.participant}` + (s.done ? '' : ` · step ${s.step} of ${s.steps.length}`);
  main.dataset.step = s.done ? 'done' : s.step;
  if (s.done) {
    main.dataset.kind = 'done';
    main.replaceChildren(el('h2', { id: 'block' }, 'Thank you'), el('p', {}, 'The session is over.'));
    return;
  }
  const st = s.steps[s.step - 1];
  main.dataset.kind = st.kind;
  const head = el('h2', { id: 'block' }, st.block + (st.condition ? ` · ${st.condition}` : ''));
  if (st.kind === 'instructions') {
    const kids = [head];
    if (st.text) kids.push(el('p', { id: 'text' }, st.text));
    if (st.image) kids.push(el('img', { src: st.image, alt: 'instructions' }));
    if (st.video) kids.push(el('video', { src: st.video, controls: true }));
    kids.push(el('button', { id: 'next' }, 'Continue'));
    main.replaceChildren(...kids);
  } else if (st.kind === 'practice') {
    const left = el('p', { id: 'clock' });
    main.replaceChildren(head, el('p', {}, st.text || 'Practise in the free scene.'), left, el('button', { id: 'next' }, 'End practice'));
    if (st.seconds) {
      const until = Date.now() + st.seconds * 1000;
      timer = setInterval(() => {
        const sec = Math.max(0, (until - Date.now()) / 1000);
        left.textContent = `${sec.toFixed(0)} s left`;
        if (sec <= 0) next();
      }, 250);
    }
  } else if (st.kind === 'task') {
    main.replaceChildren(head, el('p', {}, `Put on the headset: task ${st.task} (${st.condition}) is next. This page goes on by itself once the task has ended.`), el('button', { id: 'next' }, 'The task is done'));
    timer = setInterval(async () => {
      try {
        show(await call('POST', `/api/protocol/participants/${pid}/next`, { from: state.step }));
      } catch {
        // Not ended yet.
      }
    }, 2000);
  } else if (st.kind === 'questionnaire') {
    main.replaceChildren(head, form(st.instrument, s.answers));
    return;
  }
  const b = $('#next');
  if (b) b.onclick = next;
}

/** One item's fieldset: its options in form.mjs's lines (numbers side by side), or a textarea. */
function fieldset(row, given) {
  const fs = el('fieldset', { 'data-item': row.id });
  fs.append(el('legend', {}, row.text + (row.required ? '' : ' (optional)')));
  if (row.typed) {
    const t = el('textarea', { name: row.id, maxlength: row.maxChars });
    t.value = given[row.id] || '';
    fs.append(t);
    return fs;
  }
  const numbers = row.options.every((o) => typeof o.value === 'number' && o.label === String(o.value));
  for (const line of optionLines(row, given)) {
    const div = el('div', { class: numbers ? 'scale' : 'choices' });
    for (const b of line) {
      const input = el('input', { type: row.multi ? 'checkbox' : 'radio', name: row.id, value: String(row.options[b.k].value), checked: b.on });
      div.append(el('label', {}, input, numbers ? b.label : ` ${b.label}`));
    }
    fs.append(div);
  }
  if (row.anchors) fs.append(el('div', { class: 'anchors' }, el('span', {}, row.anchors[0]), el('span', {}, row.anchors[1])));
  return fs;
}

function form(ins, given) {
  const rows = ins.items.map(rowOf);
  const f = el('form', { id: 'questionnaire', 'data-instrument': ins.id });
  f.append(el('h3', {}, ins.title));
  if (ins.intro) f.append(el('p', {}, ins.intro));
  for (const row of rows) f.append(fieldset(row, given));
  f.append(el('button', { id: 'submit', type: 'submit' }, 'Send'));
  f.onsubmit = async (ev) => {
    ev.preventDefault();
    const picked = {};
    for (const row of rows) {
      const fs = f.querySelector(`fieldset[data-item="${CSS.escape(row.id)}"]`);
      picked[row.id] = row.typed ? fs.querySelector('textarea').value : [...fs.querySelectorAll('input:checked')].map((i) => i.value);
    }
    const answers = formAnswers(rows, picked);
    try {
      if (Object.keys(answers).length) state = await call('POST', `/api/protocol/participants/${pid}/answers`, { step: state.step, answers });
      await next();
    } catch (e) {
      say(e.message);
    }
  };
  return f;
}

start();
