#!/usr/bin/env node
// node web/page/try.mjs --to URL [--participant ID] [--task ray-casting-7|manual-7] [--mode vr|ar]
//                       [--seed N] [--trees N] [--ca CERT.pem] [--timeout SECONDS] [--json]
//
// A researcher's dry run (docs/headset.md, "A dry run"): one scripted participant in an emulated
// headset (IWER's Quest 3 in headless Chromium, as the page's tests use it) plays the task, or,
// when the server runs a protocol, the whole protocol (instructions, practice, each task, each
// questionnaire answered on the panel, the typed answers on the page), against a server that is
// already running, through the page that server ships. It prints each recording the server wrote
// with the server's verification, and exits 0 when every one verified, 1 when one did not, 2 when
// the dry run could not be run (a bad argument, no server, the page failed or the participant
// could not be played, each said in one line on stderr).
//
// It is a Node script rather than a grove subcommand because the headset is the page in a
// browser: Chromium, IWER and Playwright are the web folder's (npm ci in web/), as are the moves
// of the scripted participant it shares with the page's tests (test/participant.mjs).

import { X509Certificate, createHash } from 'node:crypto';
import { readFileSync } from 'node:fs';
import { browse, until } from './test/harness.mjs';
import { enterAndStart, playTask, throughProtocol } from './test/participant.mjs';

const USAGE = 'usage: node web/page/try.mjs --to URL [--participant ID] [--task ray-casting-7|manual-7] [--mode vr|ar] [--seed N] [--trees N] [--ca CERT.pem] [--timeout SECONDS] [--json]';

/** Why the dry run could not be run: one line, exit 2. */
class CannotRun extends Error {}

function parse(argv) {
  const a = { to: null, participant: null, task: null, mode: 'vr', seed: 1, trees: Infinity, ca: null, timeout: 900, json: false };
  const bad = (m) => {
    throw new CannotRun(`${m}; ${USAGE}`);
  };
  for (let i = 0; i < argv.length; i++) {
    const [k, v] = [argv[i], argv[i + 1]];
    const value = () => (v === undefined || v.startsWith('--') ? bad(`${k} needs a value`) : (i++, v));
    if (k === '--json') a.json = true;
    else if (k === '--to') a.to = value();
    else if (k === '--participant') a.participant = value();
    else if (k === '--task') a.task = value();
    else if (k === '--mode') a.mode = value();
    else if (k === '--seed') a.seed = value();
    else if (k === '--trees') a.trees = value();
    else if (k === '--ca') a.ca = value();
    else if (k === '--timeout') a.timeout = value();
    else bad(`unknown argument ${k}`);
  }
  if (!a.to) bad('--to URL is needed (the URL grove serve printed)');
  let url;
  try {
    url = new URL(a.to);
  } catch {
    bad(`--to ${a.to}: not a URL such as http://127.0.0.1:8080/`);
  }
  if (!['http:', 'https:'].includes(url.protocol)) bad(`--to ${a.to}: the URL must start with http:// or https://`);
  if (url.protocol === 'https:' && !a.ca) bad('an https URL needs --ca CERT.pem, the server\'s certificate (grove serve --tls auto writes DIR/tls/cert.pem)');
  if (a.participant !== null && !/^[A-Za-z0-9][A-Za-z0-9_-]{0,31}$/.test(a.participant)) bad(`--participant ${a.participant}: 1 to 32 letters, digits, _ or -, starting with a letter or digit`);
  if (a.task !== null && !['ray-casting-7', 'manual-7'].includes(a.task)) bad(`--task ${a.task}: ray-casting-7 or manual-7`);
  if (!['vr', 'ar'].includes(a.mode)) bad(`--mode ${a.mode}: vr or ar`);
  if (!/^\d{1,15}$/.test(String(a.seed))) bad(`--seed ${a.seed}: a whole number`);
  if (a.trees !== Infinity && !/^[0-7]$/.test(a.trees)) bad(`--trees ${a.trees}: 0 to 7 (the targets to plant before Finish task; all by default)`);
  if (!/^\d+(\.\d+)?$/.test(String(a.timeout)) || Number(a.timeout) <= 0) bad(`--timeout ${a.timeout}: seconds above 0`);
  return { ...a, url, trees: Number(a.trees), timeout: Number(a.timeout) * 1000 };
}

/** Chromium's flag accepting the server's certificate of `path` (its public key pinned), nothing else. */
function pinned(path) {
  let cert;
  try {
    cert = new X509Certificate(readFileSync(path));
  } catch (e) {
    throw new CannotRun(`--ca ${path}: not a PEM certificate (${e.message})`);
  }
  const spki = cert.publicKey.export({ type: 'spki', format: 'der' });
  return [`--ignore-certificate-errors-spki-list=${createHash('sha256').update(spki).digest('base64')}`];
}

/** The server's status, asked from the page's origin (the browser has the token's cookie). */
async function status(page) {
  return page.evaluate(async () => (await fetch('/api/status', { cache: 'no-store' })).json());
}

/** One task without a protocol: entered, played, ended; resolves to its recording and verification. */
async function aTask(h, a) {
  const participant = a.participant ?? 'TRY';
  const task = a.task ?? 'ray-casting-7';
  const { page } = await h.open(`participant=${participant}&task=${task}&seed=${a.seed}&quality=low&render_every=4`, { xr: true, room: a.mode === 'ar' });
  await enterAndStart(page, a.mode);
  const session = await playTask(page, { trees: a.trees });
  return { protocol: null, participant, sessions: [session] };
}

/** The whole protocol: the participant named (or the next the server gives) through every step. */
async function aProtocol(h, a, protocol) {
  const query = `${a.participant ? `participant=${a.participant}&` : ''}quality=low&render_every=4`;
  const { page } = await h.open(query, { xr: true, room: a.mode === 'ar' });
  if (!a.participant) {
    await page.click('#join');
    await until(page, () => window.grove.study?.participant || window.grove.state === 'error');
  }
  const participant = await page.evaluate(() => window.grove.study?.participant ?? null);
  if (!participant) throw new CannotRun(`the page did not join a participant: ${await page.evaluate(() => window.grove.error)}`);
  const sessions = await throughProtocol(page, { mode: a.mode, trees: a.trees });
  return { protocol, participant, sessions };
}

async function dryRun(a) {
  const started = Date.now();
  const h = await browse(a.url.href, { chromiumArgs: a.ca ? pinned(a.ca) : [] }).catch((e) => {
    throw new CannotRun(`no headless Chromium with the emulator (npm ci in web/?): ${e.message}`);
  });
  try {
    const run = async () => {
      const probe = await h.open('quality=low', {}).catch((e) => {
        throw new CannotRun(`the page at ${a.url.origin} did not load: ${e.message.split('\n')[0]}`);
      });
      const { protocol } = await status(probe.page);
      await probe.context.close();
      if (protocol && a.task) throw new CannotRun(`the server runs the protocol ${protocol}, which says the tasks: leave out --task`);
      return protocol ? aProtocol(h, a, protocol) : aTask(h, a);
    };
    let timer;
    const late = new Promise((_, reject) => (timer = setTimeout(() => reject(new CannotRun(`the dry run did not end within ${a.timeout / 1000} s`)), a.timeout)));
    const result = await Promise.race([run(), late]).finally(() => clearTimeout(timer));
    const foreign = h.foreign();
    if (foreign.length) throw new CannotRun(`the page made requests outside the server: ${foreign.join(', ')}`);
    const verified = result.sessions.length > 0 && result.sessions.every((s) => s.verification?.status === 'verified');
    return { server: a.url.origin, mode: a.mode, ...result, verified, seconds: Math.round((Date.now() - started) / 100) / 10, page_errors: h.errors };
  } finally {
    await h.close();
  }
}

async function main() {
  let a;
  try {
    a = parse(process.argv.slice(2));
    const r = await dryRun(a);
    if (a.json) console.log(JSON.stringify(r, null, 2));
    else {
      for (const s of r.sessions) console.log(`${s.file}: ${s.task}, ${s.trees} trees planted, ${s.verification?.status ?? 'no verification'}${s.verification?.first_divergence ? ` (diverged at tick ${s.verification.first_divergence.tick})` : ''}`);
      console.log(`${r.participant}${r.protocol ? ` through ${r.protocol}` : ''} in ${r.mode} on ${r.server}: ${r.verified ? 'verified' : 'not verified'} (${r.seconds} s)`);
    }
    process.exit(r.verified ? 0 : 1);
  } catch (e) {
    const why = e instanceof CannotRun ? e.message : `the participant could not be played: ${String(e.message ?? e).split('\n')[0]}`;
    console.error(`error: ${why}`);
    process.exit(2);
  }
}

await main();
