// What the page's browser tests share (node --test web/page/test/): the page built into
// web/dist, a `grove serve` of the debug build on a free port in a scratch folder, headless
// Chromium started by playwright-core (Debian's /usr/bin/chromium, software WebGL through
// SwiftShader), the WebXR emulator bundled for the tests only, every request checked to stay on
// the server's origin, and the moves of a scripted participant.

import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { build } from 'esbuild';
import { startServer } from '../../client/test/helpers.mjs';
import { launchChromium } from '../headless.mjs';

export const WEB = resolve(dirname(fileURLToPath(import.meta.url)), '../..');
export const ROOT = resolve(WEB, '..');
export const GROVE = process.env.GROVE_BIN ?? join(ROOT, 'target/debug/grove');

let emulator = null;

/** The page built once per test process (web/dist), and the emulator bundled. */
export async function prepare() {
  if (!process.env.GROVE_PAGE_BUILT) {
    const r = spawnSync(process.execPath, [join(WEB, 'page/build.mjs')], { encoding: 'utf8' });
    if (r.status !== 0) throw new Error(`the page did not build: ${r.stderr}`);
    process.env.GROVE_PAGE_BUILT = '1';
  }
  return emulatorScript();
}

/** The emulator bundled into one script for the tests' pages (once per process). */
async function emulatorScript() {
  if (!emulator) {
    const out = await build({
      entryPoints: [join(WEB, 'page/test/emulator.mjs')],
      bundle: true,
      format: 'iife',
      write: false,
      logLevel: 'error',
      target: 'es2022',
    });
    emulator = out.outputFiles[0].text;
  }
  return emulator;
}

/**
 * A server (`grove serve` with the arguments `serve` added) and a browser: resolves to { server, browser, open(query, { xr, room, device }), requests,
 * close }. `open` makes a page (a new browser context, or `context` to keep its storage) at the
 * server's URL with `query`, the emulator installed when `xr` is set (`device`: emulator.mjs's
 * `quest`, `quest2`, `pico4`, `magicleap`, `phone` or `visionpro`; `room`: @iwer/sem's office;
 * `depth`: the headset offers depth sensing; `light`: a light estimate, emulator.mjs).
 */
export async function start(serve = []) {
  await prepare();
  const server = await startServer(serve);
  const b = await browse(server.url);
  return {
    ...b,
    server,
    close: async () => {
      await b.close();
      await server.stop();
    },
  };
}

/**
 * Headless Chromium with the emulator bundled, for the server at `url` (its `?token=`, if any, is
 * added to the first page's query, as the printed URL carries it): resolves to { browser,
 * open(query, { xr, room }), requests, errors, foreign, origin, close }. `chromiumArgs` are added
 * to the browser's (an https server's certificate to accept).
 */
export async function browse(url, { chromiumArgs = [] } = {}) {
  const script = await emulatorScript();
  const browser = await launchChromium(chromiumArgs);
  const origin = new URL(url).origin;
  const token = new URL(url).searchParams.get('token');
  const requests = [];
  const errors = [];
  async function open(
    query,
    {
      xr = false,
      room = true,
      device = 'quest',
      depth = true,
      light = null,
      context = null,
      width = 480,
      height = 360,
    } = {},
  ) {
    const ctx = context ?? (await browser.newContext({ viewport: { width, height } }));
    const page = await ctx.newPage();
    page.on('request', (r) => requests.push(r.url()));
    page.on('pageerror', (e) => errors.push(String(e.stack ?? e)));
    page.on('response', (r) => {
      if (r.status() >= 400) errors.push(`${r.status()} ${r.url()}`);
    });
    page.on('console', (m) => {
      if (m.type() === 'error') errors.push(m.text());
    });
    if (xr) {
      await page.addInitScript(`window.__groveXR = ${JSON.stringify({ room, device, depth, light })};`);
      await page.addInitScript(script);
    }
    await page.goto(`${origin}/?${token ? `token=${encodeURIComponent(token)}&` : ''}${query}`);
    await page.waitForFunction(() => window.grove && ['instructions', 'error'].includes(window.grove.state), null, {
      timeout: 60000,
    });
    const state = await page.evaluate(() => window.grove.state);
    if (state === 'error')
      throw new Error(`the page failed: ${await page.evaluate(() => window.grove.error)}; ${errors.join(' / ')}`);
    return { page, context: ctx };
  }
  /** Requests that left the server's origin (must be none). */
  const foreign = () =>
    requests.filter((u) => !u.startsWith(origin + '/') && !u.startsWith('data:') && !u.startsWith('blob:'));
  const close = () => browser.close();
  return { browser, open, requests, errors, foreign, origin, close };
}

/** Runs `grove ARGS…` in `cwd` (the repository root by default); returns { status, stdout, stderr }. */
export function grove(args, cwd = ROOT) {
  const r = spawnSync(GROVE, args, { cwd, encoding: 'utf8' });
  return { status: r.status, stdout: r.stdout, stderr: r.stderr };
}

/** `grove study` over `replays` into a scratch folder: trial_results.csv's rows by column name. */
export function studyRows(replays) {
  const out = mkdtempSync(join(tmpdir(), 'grove-page-study-'));
  try {
    const r = grove(['study', '--replays', replays, '--out', out, '--force']);
    if (r.status !== 0) throw new Error(`grove study: ${r.stderr}`);
    return trialRows(out);
  } finally {
    rmSync(out, { recursive: true, force: true });
  }
}

/** trial_results.csv of a study's folder, its rows by column name. */
export function trialRows(dir) {
  const csv = readFileSync(join(dir, 'trial_results.csv'), 'utf8')
    .trim()
    .split('\n')
    .map((l) => l.split(','));
  return csv.slice(1).map((r) => Object.fromEntries(csv[0].map((c, i) => [c, r[i]])));
}

/** The lines of a file (without newlines). */
export function fileLines(path) {
  return readFileSync(path, 'utf8')
    .split('\n')
    .filter((l) => l.length > 0);
}

export { existsSync };

/** Waits in the page until `fn(arg)` is true (polling each animation frame). */
export function until(page, fn, arg, timeout = 60000) {
  return page.waitForFunction(fn, arg, { timeout, polling: 'raf' });
}

/**
 * Waits until the simulation has run `n` more ticks, or the task has ended (no more ticks; a
 * protocol's page may already be at its next step).
 */
export async function ticks(page, n) {
  const start = await page.evaluate(() => window.grove.snapshot?.tick ?? 0);
  await until(
    page,
    (t) => (window.grove.snapshot?.tick ?? 0) >= t || ['done', 'error', 'step'].includes(window.grove.state),
    start + n,
  );
}

/**
 * Waits for the page's task to end and the server's verification of its file, and holds that it
 * verified, that its header names `device`, and that `grove replay` takes it; returns the replay's
 * report with the file's `name` and `path`.
 */
export async function verified(page, dir, device) {
  await until(page, () => window.grove.state === 'done' && window.grove.verification, null, 60000);
  const done = await page.evaluate(() => ({ v: window.grove.verification, file: window.grove.file }));
  assert.equal(done.v.status, 'verified', JSON.stringify(done.v));
  const path = join(dir, done.file);
  assert.deepEqual(JSON.parse(fileLines(path)[0]).device, device);
  const replay = grove(['replay', path, '--json']);
  assert.equal(replay.status, 0, replay.stderr);
  return { ...JSON.parse(replay.stdout), name: done.file, path };
}
