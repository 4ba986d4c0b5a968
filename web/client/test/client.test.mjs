// The session client against a real `grove serve` (built first: target/debug/grove, or
// GROVE_BIN). Run with `node --test web/client/test/`.

import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { openSession, resumeSession } from '../grove-client.mjs';
import { startProxy, startServer, studyLines } from './helpers.mjs';

let server;
before(async () => {
  server = await startServer(['--writer-lease', '0.5', '--read-timeout', '3']);
});
after(async () => {
  await server?.stop();
});

const fileOf = (s) => readFileSync(join(server.dir, s.file), 'utf8');

test('a recording opened by its header line and appended line by line comes out byte for byte and verified', async () => {
  const lines = studyLines('P03-ray-casting-7.jsonl');
  const s = await openSession(server.url, { header: lines[0] });
  assert.equal(s.header, lines[0]);
  assert.equal(s.file, 'P03-ray-casting-7-1.jsonl');
  for (const l of lines.slice(1)) s.append(l);
  assert.equal(await s.flush(), lines.length);
  const result = await s.end();
  assert.equal(result.verification.status, 'verified');
  assert.equal(fileOf(s), lines.join('\n') + '\n');
});

test("a session opened by its fields gets the server's header and verifies with the same events", async () => {
  const lines = studyLines('P01-manual-7.jsonl');
  const header = JSON.parse(lines[0]);
  const s = await openSession(server.url, { participant: 'P01', task: 'manual-7', scene: 'study', seed: header.seed });
  const written = JSON.parse(s.header);
  assert.equal(written.participant, 'P01');
  assert.equal(written.seed, header.seed);
  assert.equal(written.synthetic, false);
  assert.match(written.session_start, /^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ$/);
  for (const l of lines.slice(1)) s.append(l);
  const result = await s.end();
  assert.equal(result.verification.status, 'verified', JSON.stringify(result));
  assert.equal(fileOf(s), [s.header, ...lines.slice(1)].join('\n') + '\n');
});

test('a refused line is named, nothing after the last good line is written, and the session goes on', async () => {
  const lines = studyLines('P02-ray-casting-7.jsonl');
  const s = await openSession(server.url, { header: lines[0] });
  for (const l of lines.slice(1, 20)) s.append(l);
  await s.flush();
  const refusals = [];
  s.addEventListener('refused', (e) => refusals.push(e.reason));
  s.append(lines[20].replace(/"sum":"[0-9a-f]{8}"/, '"sum":"00000000"'));
  s.append(lines[21]);
  await assert.rejects(s.flush(), /line 21: checksum mismatch/);
  assert.equal(refusals.length, 1);
  assert.equal(s.acked, 20);
  assert.equal(fileOf(s), lines.slice(0, 20).join('\n') + '\n');
  assert.deepEqual(s.discardUnsent().length, 2);
  for (const l of lines.slice(20)) s.append(l);
  const result = await s.end();
  assert.equal(result.verification.status, 'verified');
  assert.equal(fileOf(s), lines.join('\n') + '\n');
});

test('while the network is gone the lines wait; afterwards they arrive once each, in order', async () => {
  const proxy = await startProxy(server.url);
  try {
    const lines = studyLines('P04-manual-7.jsonl');
    const s = await openSession(proxy.url, { header: lines[0] }, { timeoutMs: 500, retryMinMs: 50, retryMaxMs: 200 });
    const events = [];
    s.addEventListener('offline', () => events.push('offline'));
    s.addEventListener('online', () => events.push('online'));
    const third = Math.floor(lines.length / 3);
    for (const l of lines.slice(1, third)) s.append(l);
    await s.flush();
    proxy.drop();
    for (const l of lines.slice(third, 2 * third)) s.append(l);
    await new Promise((r) => setTimeout(r, 1500));
    assert.ok(s.offline, 'the client noticed the network was gone');
    assert.ok(s.pending > 0);
    const onDisk = fileOf(s).split('\n').length - 1;
    assert.ok(onDisk < 2 * third, `${onDisk} lines on disk while offline`);
    proxy.restore();
    for (const l of lines.slice(2 * third)) s.append(l);
    const result = await s.end();
    assert.deepEqual(events.slice(0, 2), ['offline', 'online']);
    assert.equal(result.verification.status, 'verified');
    assert.equal(fileOf(s), lines.join('\n') + '\n');
  } finally {
    await proxy.close();
  }
});

test('another client continues a session by its id once the first has gone quiet, never while it writes', async () => {
  const lines = studyLines('P05-ray-casting-7.jsonl');
  const first = await openSession(server.url, { header: lines[0] });
  for (const l of lines.slice(1, 100)) first.append(l);
  await first.flush();
  // At once: the first client still holds the session.
  const early = await resumeSession(server.url, first.id);
  early.append(lines[100]);
  await assert.rejects(early.flush(), /being written by another client/);
  first.close();
  await new Promise((r) => setTimeout(r, 700));
  const second = await resumeSession(server.url, first.id);
  assert.equal(second.acked, 100);
  for (const l of lines.slice(100)) second.append(l);
  const result = await second.end();
  assert.equal(result.verification.status, 'verified');
  assert.equal(readFileSync(join(server.dir, second.file), 'utf8'), lines.join('\n') + '\n');
});
