// The client of a grove session server (`grove serve`, docs/serve.md): a plain ES module with no
// dependency, for a browser page and for Node 18 or later (fetch, AbortSignal.timeout,
// EventTarget and crypto.getRandomValues are all it uses).
//
//   import { openSession } from "./grove-client.mjs";
//   const s = await openSession("http://192.168.1.5:8080/?token=…", { participant: "P01", task: "ray-casting-7" });
//   s.append(line);          // a recording line (without "\n"), as the recorder makes it
//   await s.flush();         // every line so far is on the server's disk
//   const result = await s.end();   // { acked, file, state, verification }
//
// Lines are sent as they are appended, one request at a time, each batch starting at the line
// after the last one the server acknowledged. While the server cannot be reached the lines
// wait in memory (up to `maxBufferedBytes`); the client retries, asks the server how many lines
// it has, and goes on from there: nothing is lost or sent twice. A line the server refuses
// (its reason in the `refused` event and in the rejected `flush`) stops the sending until the
// page calls `discardUnsent()` and appends again from the last good line.

const DEFAULTS = {
  timeoutMs: 10000,
  maxBatchBytes: 256 * 1024,
  maxBufferedBytes: 64 * 1024 * 1024,
  retryMinMs: 200,
  retryMaxMs: 2000,
};

/** A client name for the server's check that one client writes a session at a time. */
function newWriterId() {
  const bytes = new Uint8Array(12);
  globalThis.crypto.getRandomValues(bytes);
  return "js-" + Array.from(bytes, (b) => b.toString(16).padStart(2, "0")).join("");
}

/** The server's base URL (without query) and the token its URL carries, if any. */
function splitUrl(url) {
  const u = new URL(url);
  const token = u.searchParams.get("token");
  u.search = "";
  u.hash = "";
  const base = u.toString().replace(/\/+$/, "");
  return { base, token };
}

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/**
 * Why a request got no answer, in words: the server named as unreachable, with what is known of
 * why (Node names the socket's error, such as ECONNREFUSED; a browser says only that the fetch
 * failed, as a TypeError, which is no reason to show).
 */
export function unreachable(base, e, timeoutMs) {
  const late = e?.name === 'TimeoutError' || e?.name === 'AbortError';
  const why = late ? `no answer within ${(timeoutMs / 1000).toFixed(0)} s` : e?.cause?.code ?? e?.cause?.message ?? (e?.name === 'TypeError' ? 'no connection' : e?.message ?? String(e));
  return `the server ${base} is unreachable (${why})`;
}

/** An error the server answered with (a refusal), or a network failure (`status` 0). */
export class SessionError extends Error {
  constructor(message, status, body) {
    super(message);
    this.name = "SessionError";
    this.status = status;
    this.body = body;
  }
}

class Connection {
  constructor(url, options) {
    const { base, token } = splitUrl(url);
    this.base = base;
    this.token = options.token ?? token;
    this.writer = options.writer ?? newWriterId();
    this.fetch = options.fetch ?? globalThis.fetch.bind(globalThis);
    this.timeoutMs = options.timeoutMs;
  }

  /** One request; resolves to { status, json } or throws a SessionError with status 0. */
  async request(method, path, body) {
    const headers = { "grove-writer": this.writer };
    if (this.token) headers.authorization = `Bearer ${this.token}`;
    if (body !== undefined) headers["content-type"] = typeof body === "string" && body.startsWith("{") ? "application/json" : "text/plain";
    let response;
    try {
      response = await this.fetch(this.base + path, { method, headers, body, signal: AbortSignal.timeout(this.timeoutMs) });
    } catch (e) {
      throw new SessionError(unreachable(this.base, e, this.timeoutMs), 0, null);
    }
    let json = null;
    try {
      json = await response.json();
    } catch {
      // A body that is not JSON (a proxy's error page) stays null.
    }
    return { status: response.status, json };
  }
}

/**
 * A session being written. Events: `ack` ({ acked }), `offline` ({ reason }), `online`,
 * `refused` ({ reason, status }).
 */
export class Session extends EventTarget {
  #conn;
  #options;
  #queue = []; // { number, text, bytes } not yet acknowledged, in order
  #queuedBytes = 0;
  #acked;
  #next;
  #pumping = false;
  #waiters = [];
  #refusal = null;
  #closed = false;
  #offline = false;

  constructor(conn, options, { id, file, header, acked }) {
    super();
    this.#conn = conn;
    this.#options = options;
    this.id = id;
    this.file = file;
    this.header = header;
    this.#acked = acked;
    this.#next = acked + 1;
  }

  /** Lines the server has on disk (its header is line 1). */
  get acked() {
    return this.#acked;
  }

  /** Lines appended and not yet acknowledged. */
  get pending() {
    return this.#queue.length;
  }

  /** Whether the last request failed to reach the server. */
  get offline() {
    return this.#offline;
  }

  /** The refusal that stopped the sending, if any. */
  get refusal() {
    return this.#refusal;
  }

  /** Appends a line (one recording line, without its newline) and starts sending it. */
  append(line) {
    if (this.#closed) throw new SessionError("the session is closed", 0, null);
    const text = line.endsWith("\n") ? line.slice(0, -1) : line;
    if (text.includes("\n")) throw new SessionError("append takes one line at a time", 0, null);
    const bytes = new TextEncoder().encode(text).length + 1;
    if (this.#queuedBytes + bytes > this.#options.maxBufferedBytes) {
      throw new SessionError(`more than ${this.#options.maxBufferedBytes} bytes wait to be sent; the server has been unreachable too long`, 0, null);
    }
    this.#queue.push({ number: this.#next++, text, bytes });
    this.#queuedBytes += bytes;
    this.#pump();
  }

  /** Resolves once every line appended so far is acknowledged; rejects on a refusal. */
  flush() {
    if (this.#refusal) return Promise.reject(this.#refusal);
    const target = this.#next - 1;
    if (this.#acked >= target) return Promise.resolve(this.#acked);
    return new Promise((resolve, reject) => {
      this.#waiters.push({ target, resolve, reject });
      this.#pump();
    });
  }

  /**
   * Drops the lines not yet acknowledged (after a refusal) and sends again: the next line
   * appended is the one after the last acknowledged. Returns the dropped lines.
   */
  discardUnsent() {
    const dropped = this.#queue.map((q) => q.text);
    this.#queue = [];
    this.#queuedBytes = 0;
    this.#next = this.#acked + 1;
    this.#refusal = null;
    return dropped;
  }

  /** Flushes, then ends the session; resolves to the server's verification of the file. */
  async end() {
    await this.flush();
    for (let attempt = 0; ; attempt++) {
      let r;
      try {
        r = await this.#conn.request("POST", `/api/sessions/${this.id}/end`);
      } catch (e) {
        await this.#wait(e, attempt);
        continue;
      }
      if (r.status === 409 && r.json?.code === "busy") {
        await sleep(this.#options.retryMinMs);
        continue;
      }
      if (r.status === 410) {
        // Ended by an earlier try whose answer was lost: its entry has the verification.
        const s = await this.#conn.request("GET", `/api/sessions/${this.id}`);
        this.#closed = true;
        return s.json;
      }
      if (r.status !== 200) throw new SessionError(r.json?.error ?? `end refused (${r.status})`, r.status, r.json);
      this.#closed = true;
      return r.json;
    }
  }

  /** Stops sending (a page being left); the server keeps what it acknowledged. */
  close() {
    this.#closed = true;
    for (const w of this.#waiters.splice(0)) w.reject(new SessionError("the session was closed", 0, null));
  }

  #ackTo(acked) {
    if (typeof acked !== "number") return;
    if (acked + 1 < (this.#queue[0]?.number ?? this.#next)) {
      this.#refuse(new SessionError(`the server has ${acked} lines, fewer than it acknowledged`, 0, null));
      return;
    }
    this.#acked = acked;
    while (this.#queue.length && this.#queue[0].number <= acked) this.#queuedBytes -= this.#queue.shift().bytes;
    this.dispatchEvent(Object.assign(new Event("ack"), { acked }));
    this.#waiters = this.#waiters.filter((w) => {
      if (w.target <= acked) w.resolve(acked);
      return w.target > acked;
    });
  }

  #refuse(error) {
    this.#refusal = error;
    this.dispatchEvent(Object.assign(new Event("refused"), { reason: error.message, status: error.status }));
    for (const w of this.#waiters.splice(0)) w.reject(error);
  }

  async #wait(error, attempt) {
    if (!this.#offline) {
      this.#offline = true;
      this.dispatchEvent(Object.assign(new Event("offline"), { reason: error.message }));
    }
    const o = this.#options;
    await sleep(Math.min(o.retryMaxMs, o.retryMinMs * 2 ** Math.min(attempt, 6)));
  }

  #online() {
    if (this.#offline) {
      this.#offline = false;
      this.dispatchEvent(new Event("online"));
    }
  }

  /** Asks the server how many lines it has, until it answers. */
  async #resync() {
    for (let attempt = 0; !this.#closed; attempt++) {
      try {
        const r = await this.#conn.request("GET", `/api/sessions/${this.id}`);
        if (r.status === 200 && r.json?.state === "open") {
          this.#online();
          this.#ackTo(r.json.acked);
          return;
        }
        if (r.status === 200 || r.status === 404) {
          this.#refuse(new SessionError(`the session is no longer open on the server (${r.json?.state ?? r.json?.error})`, r.status, r.json));
          return;
        }
        await sleep(this.#options.retryMinMs);
      } catch (e) {
        await this.#wait(e, attempt);
      }
    }
  }

  async #pump() {
    if (this.#pumping) return;
    this.#pumping = true;
    try {
      let attempt = 0;
      while (this.#queue.length && !this.#closed && !this.#refusal) {
        const from = this.#queue[0].number;
        let body = "";
        let size = 0;
        for (const q of this.#queue) {
          if (size && size + q.bytes > this.#options.maxBatchBytes) break;
          body += q.text + "\n";
          size += q.bytes;
        }
        let r;
        try {
          r = await this.#conn.request("POST", `/api/sessions/${this.id}/lines?from=${from}`, body);
        } catch (e) {
          await this.#wait(e, attempt++);
          await this.#resync();
          continue;
        }
        attempt = 0;
        this.#online();
        if (r.status === 200 || (r.status === 409 && r.json?.code === "gap")) {
          this.#ackTo(r.json?.acked);
        } else if (r.status === 409 && r.json?.code === "busy") {
          await sleep(this.#options.retryMinMs);
        } else {
          if (typeof r.json?.acked === "number") this.#ackTo(r.json.acked);
          this.#refuse(new SessionError(r.json?.error ?? `lines refused (${r.status})`, r.status, r.json));
        }
      }
    } finally {
      this.#pumping = false;
    }
  }
}

function withDefaults(options) {
  return { ...DEFAULTS, ...options };
}

/**
 * Opens a session: `what` is either the fields a client may set ({ participant, task, scene,
 * seed, technique, block }) or { header } with a whole header line (a recording pushed as it
 * is). Retries while the server cannot be reached; rejects on a refusal.
 */
export async function openSession(url, what, options = {}) {
  const o = withDefaults(options);
  const conn = new Connection(url, o);
  for (let attempt = 0; ; attempt++) {
    let r;
    try {
      r = await conn.request("POST", "/api/sessions", JSON.stringify(what));
    } catch (e) {
      if (attempt >= (o.openAttempts ?? 20)) throw e;
      await sleep(Math.min(o.retryMaxMs, o.retryMinMs * 2 ** Math.min(attempt, 6)));
      continue;
    }
    if (r.status !== 201) throw new SessionError(r.json?.error ?? `open refused (${r.status})`, r.status, r.json);
    return new Session(conn, o, { id: r.json.session, file: r.json.file, header: r.json.header, acked: r.json.acked });
  }
}

/**
 * Continues a session by its id (after the page was reloaded, or from another device once the
 * first has been silent for the server's writer lease): the next line appended is the one after
 * the last the server has (`session.acked`).
 */
export async function resumeSession(url, id, options = {}) {
  const o = withDefaults(options);
  const conn = new Connection(url, o);
  const r = await conn.request("GET", `/api/sessions/${id}`);
  if (r.status !== 200 || r.json?.state !== "open") throw new SessionError(r.json?.error ?? `the session is not open (${r.json?.state ?? r.status})`, r.status, r.json);
  return new Session(conn, o, { id, file: r.json.file, header: null, acked: r.json.acked });
}
