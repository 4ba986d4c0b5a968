// A lab day that survives (docs/serve.md, "What a crash leaves"): a page in Chromium streaming a
// recording through the client library, its token in a cookie, goes on after the server is
// killed (SIGKILL) and started again on its folder, because the token is kept in the folder; the
// file equals the recording. And a server that cannot be reached is named as such, in Node and
// in the browser, never as a bare TypeError.

import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import net from 'node:net';
import { join } from 'node:path';
import { test } from 'node:test';

import { openSession, unreachable } from '../grove-client.mjs';
import { GROVE, ROOT, studyLines } from './helpers.mjs';

/** `grove serve --out DIR --port PORT ARGS…`; resolves to { child, url } once it listens. */
function serve(dir, port, extra) {
  const child = spawn(GROVE, ['serve', '--port', String(port), '--out', dir, ...extra], {
    cwd: ROOT,
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  let log = '';
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`grove serve did not start: ${log}`)), 30000);
    const seen = (d) => {
      log += d;
      const m = log.match(/listening on (\S+)/);
      if (m) {
        clearTimeout(timer);
        resolve({ child, url: m[1], log: () => log });
      }
    };
    child.stdout.on('data', seen);
    child.stderr.on('data', seen);
    child.on('exit', (code) => reject(new Error(`grove serve ended (${code}): ${log}`)));
  });
}

async function kill(server, signal) {
  if (server.child.exitCode !== null) return;
  const ended = new Promise((r) => server.child.once('exit', r));
  server.child.kill(signal);
  await ended;
}

const lineCount = (file) => {
  try {
    return readFileSync(file, 'utf8').split('\n').length - 1;
  } catch {
    return 0;
  }
};

/** A port nothing listens on: one the system gave and took back. */
async function closedPort() {
  const s = net.createServer();
  await new Promise((r) => s.listen(0, '127.0.0.1', r));
  const { port } = s.address();
  await new Promise((r) => s.close(r));
  return port;
}

test('an unreachable server is named as such', async () => {
  const port = await closedPort();
  await assert.rejects(
    openSession(`http://127.0.0.1:${port}/`, { participant: 'P01' }, { openAttempts: 0, timeoutMs: 2000 }),
    new RegExp(`the server http://127\\.0\\.0\\.1:${port} is unreachable \\(ECONNREFUSED\\)`),
  );
  // What a browser's fetch throws says nothing but TypeError.
  assert.equal(
    unreachable('http://192.168.1.5:8080', new TypeError('Failed to fetch'), 10000),
    'the server http://192.168.1.5:8080 is unreachable (no connection)',
  );
});

test('a page in Chromium goes on streaming after the server is killed and started again', async () => {
  const dir = mkdtempSync(join(tmpdir(), 'grove-client-restart-'));
  // Headless Chromium as every browser test starts it (web/page/headless.mjs, from web/'s npm packages).
  const { launchChromium } = await import('../../page/headless.mjs');
  let server = await serve(dir, 0, ['--require-token']);
  const browser = await launchChromium();
  try {
    const url = new URL(server.url);
    const token = url.searchParams.get('token');
    assert.ok(token, server.url);
    const page = await browser.newPage();
    // The token in the URL once, as the QR code has it; from then on the cookie carries it.
    await page.goto(`${url.origin}/api/status?token=${token}`);
    await page.goto(`${url.origin}/api/status`);
    const lines = studyLines('P07-ray-casting-7.jsonl');
    await page.evaluate(async (all) => {
      const { openSession } = await import('/client/grove-client.mjs');
      const s = await openSession(
        `${location.origin}/`,
        { header: all[0] },
        { timeoutMs: 1000, retryMinMs: 50, retryMaxMs: 300 },
      );
      window.events = [];
      s.addEventListener('offline', (e) => window.events.push(`offline: ${e.reason}`));
      s.addEventListener('online', () => window.events.push('online'));
      s.addEventListener('refused', (e) => window.events.push(`refused: ${e.reason}`));
      window.done = (async () => {
        for (const l of all.slice(1)) {
          s.append(l);
          await new Promise((r) => setTimeout(r, 4));
        }
        return s.end();
      })();
    }, lines);
    const file = join(dir, 'P07-ray-casting-7-1.jsonl');
    const quarter = Math.floor(lines.length / 4);
    for (let t = 0; lineCount(file) < quarter; t++) {
      assert.ok(t < 600, `${lineCount(file)} lines after 30 s`);
      await new Promise((r) => setTimeout(r, 50));
    }
    await kill(server, 'SIGKILL');
    const atKill = lineCount(file);
    assert.ok(atKill < lines.length, `killed mid-stream: ${atKill} lines`);
    await new Promise((r) => setTimeout(r, 700));
    server = await serve(dir, Number(url.port), ['--require-token']);
    assert.equal(new URL(server.url).searchParams.get('token'), token, 'the same token after the restart');
    const result = await page.evaluate(() => window.done);
    const events = await page.evaluate(() => window.events);
    assert.equal(result.verification.status, 'verified', JSON.stringify({ result, events }));
    assert.ok(
      events.some((e) => /^offline: the server http:\/\/127\.0\.0\.1:\d+ is unreachable \(no connection\)$/.test(e)),
      events.join(' / '),
    );
    assert.ok(events.includes('online'), events.join(' / '));
    assert.ok(!events.some((e) => e.startsWith('refused')), events.join(' / '));
    assert.equal(
      readFileSync(file, 'utf8'),
      lines.join('\n') + '\n',
      'the file is the recording: nothing lost, nothing twice',
    );
  } finally {
    await browser.close();
    await kill(server, 'SIGTERM');
    rmSync(dir, { recursive: true, force: true });
  }
});
