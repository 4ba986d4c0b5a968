// The page's recording: a session of `grove serve` (docs/serve.md) opened with the task's fields
// (and, in AR, the room's scene), the simulation's lines handed to the client library as they
// are made (it sends them in the background: the frame loop never waits on the network), and
// the session kept in the page's storage, so that a page closed in the middle of a task and
// opened again continues the same file.

import { openSession, resumeSession } from '../client/grove-client.mjs';

const KEY = 'grove-session';

/** The session this page (or an earlier load of it) left open, if any. */
export function storedSession() {
  try {
    return JSON.parse(localStorage.getItem(KEY) ?? 'null');
  } catch {
    return null;
  }
}

function store(value) {
  try {
    if (value) localStorage.setItem(KEY, JSON.stringify(value));
    else localStorage.removeItem(KEY);
  } catch {
    // Private browsing without storage: the session cannot be continued after a reload.
  }
}

/** A client id kept with the session, so that a reloaded page writes on at once (no writer lease). */
function newWriter() {
  const b = new Uint8Array(12);
  crypto.getRandomValues(b);
  return 'page-' + Array.from(b, (x) => x.toString(16).padStart(2, '0')).join('');
}

/** Lines of a recording's text (without newlines). */
export function splitLines(text) {
  return text.split('\n').filter((l) => l.length > 0);
}

/**
 * The connection to the server, with its state for the page: `connecting`, `online`,
 * `offline` (lines wait in memory and are sent when it is back), `refused` (a line was refused:
 * its reason), `ended`. Fires `state` events.
 */
export class Recorder extends EventTarget {
  constructor(url) {
    super();
    this.url = url;
    this.session = null;
    this.state = 'connecting';
    this.reason = '';
    this.sent = 0;
  }

  #set(state, reason = '') {
    this.state = state;
    this.reason = reason;
    this.dispatchEvent(Object.assign(new Event('state'), { state, reason }));
  }

  #watch(s, keep) {
    this.session = s;
    s.addEventListener('offline', (e) => this.#set('offline', e.reason));
    s.addEventListener('online', () => this.#set('online'));
    s.addEventListener('refused', (e) => this.#set('refused', e.reason));
    s.addEventListener('ack', () => {
      if (this.state === 'connecting') this.#set('online');
    });
    store(keep);
    this.#set('online');
  }

  /** Opens a session: `fields` as docs/serve.md lists them (participant, task, seed, scene_text). */
  async open(fields, extra = {}) {
    const writer = newWriter();
    const s = await openSession(this.url, fields, { writer });
    this.#watch(s, {
      id: s.id,
      writer,
      file: s.file,
      participant: fields.participant,
      task: fields.task ?? null,
      ...extra,
    });
    return s.header;
  }

  /**
   * Continues the stored session: resolves to { header, lines, scene_text, stored } with the
   * lines the server has (the header first) and the scene's text when the header names a file.
   */
  async resume(stored) {
    const s = await resumeSession(this.url, stored.id, { writer: stored.writer });
    const base = new URL(this.url);
    const headers = { 'grove-writer': stored.writer };
    const token = base.searchParams.get('token');
    if (token) headers.authorization = `Bearer ${token}`;
    const get = async (what) => {
      const r = await fetch(new URL(`/api/sessions/${stored.id}/${what}`, base), { headers, cache: 'no-store' });
      if (!r.ok) throw new Error(`${what}: ${(await r.json().catch(() => ({}))).error ?? r.status}`);
      return r.text();
    };
    const lines = splitLines(await get('lines'));
    const header = JSON.parse(lines[0]);
    const builtin = !header.scene.endsWith('.ron');
    const scene_text = builtin ? undefined : await get('scene');
    this.#watch(s, stored);
    return { header: lines[0], lines, scene_text, stored };
  }

  /** Hands a line to the client library (sent in the background). */
  append(line) {
    if (!this.session || this.state === 'refused' || this.state === 'ended') return;
    try {
      this.session.append(line);
      this.sent++;
    } catch (e) {
      this.#set('refused', e.message);
    }
  }

  /** Lines appended and not yet on the server's disk. */
  get pending() {
    return this.session?.pending ?? 0;
  }

  /** Ends the session: resolves to the server's verification. */
  async end() {
    const result = await this.session.end();
    store(null);
    this.#set('ended', result?.verification?.status ?? '');
    return result;
  }

  /** Forgets the stored session (a new participant). */
  static forget() {
    store(null);
  }
}
