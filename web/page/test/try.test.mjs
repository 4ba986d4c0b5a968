// The researcher's dry run, `node web/page/try.mjs` (docs/headset.md, "A dry run"), run as a
// researcher runs it, against a `grove serve` already running: the manual task on its own, and a
// whole protocol (tests/fixtures/protocols/dry-run.ron: every kind of step, one of each, its task
// the ray-casting one) with a participant the server names; each recording it reports is in the
// server's folder and verifies with `grove replay`; a bad argument and a server that is not there
// are refused with one line and exit 2.

import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { startServer } from '../../client/test/helpers.mjs';
import { WEB, grove, prepare } from './harness.mjs';

const servers = [];
before(async () => {
  await prepare();
});
after(async () => {
  for (const s of servers) await s.stop();
});

/** Runs the dry run with `args`; resolves to { status, stdout, stderr }. */
function dryRun(args) {
  return new Promise((resolve) => {
    const child = spawn(process.execPath, [join(WEB, 'page/try.mjs'), ...args], { stdio: ['ignore', 'pipe', 'pipe'] });
    let [stdout, stderr] = ['', ''];
    child.stdout.on('data', (d) => (stdout += d));
    child.stderr.on('data', (d) => (stderr += d));
    child.on('exit', (status) => resolve({ status, stdout, stderr }));
  });
}

/** `grove replay FILE --json` of a file in the server's folder. */
function replayed(dir, file) {
  const r = grove(['replay', join(dir, file), '--json']);
  assert.equal(r.status, 0, r.stderr);
  return JSON.parse(r.stdout);
}

test('a dry run of the manual task against grove serve: two trees, Finish task, verified, exit 0', async () => {
  const server = await startServer();
  servers.push(server);
  const r = await dryRun(['--to', server.url, '--participant', 'DRY1', '--task', 'manual-7', '--trees', '2', '--json']);
  assert.equal(r.status, 0, `${r.stderr}\n${r.stdout}`);
  const out = JSON.parse(r.stdout);
  assert.equal(out.protocol, null);
  assert.equal(out.participant, 'DRY1');
  assert.equal(out.verified, true);
  assert.equal(out.sessions.length, 1);
  const [s] = out.sessions;
  assert.deepEqual([s.task, s.trees, s.verification.status], ['manual-7', 2, 'verified']);
  assert.match(s.file, /^DRY1-manual-7-\d+\.jsonl$/);
  const report = replayed(server.dir, s.file);
  assert.equal(report.verified, true);
  assert.equal(report.complete, true, 'Finish task ended the recording with its footer');
  assert.equal(report.task.trees.length, 2, 'the two trees planted, as the replay counts them');
  assert.deepEqual(out.page_errors, []);
});

test('a dry run of a protocol: every step, its task verified, the answers written and the typed one', async () => {
  // The shortest protocol with every kind of step: instructions, a practice, one task, one
  // questionnaire with a free text typed on the page (the shipped one has more of each, and takes
  // minutes).
  const server = await startServer(['--protocol', 'tests/fixtures/protocols/dry-run.ron']);
  servers.push(server);
  const r = await dryRun(['--to', server.url, '--trees', '1']);
  assert.equal(r.status, 0, `${r.stderr}\n${r.stdout}`);
  const lines = r.stdout.trim().split('\n');
  assert.match(lines.at(-1), /^P01 through dry-run in vr on http:\/\/127\.0\.0\.1:\d+: verified/);
  const files = lines.slice(0, -1).map((l) => l.split(':')[0]);
  assert.deepEqual(files.map((f) => f.replace(/-\d+\.jsonl$/, '')), ['P01-ray-casting-7']);
  const report = replayed(server.dir, files[0]);
  assert.equal(report.verified, true, files[0]);
  assert.equal(report.task.trees.length, 1, `${files[0]}: one tree on its target`);
  const answers = readFileSync(join(server.dir, 'P01.answers.jsonl'), 'utf8').trim().split('\n').map((l) => JSON.parse(l));
  assert.deepEqual(answers.filter((l) => l.line === 'step').map((l) => l.step), [1, 2, 3, 4], 'every step begun');
  const answered = new Map(answers.filter((l) => l.line === 'answer').map((l) => [`${l.step}.${l.item}`, l.answer]));
  for (const item of ['4.guidance', '4.more_instructions', '4.would_use']) assert.ok(answered.has(item), `${item} answered on the panel: ${[...answered.keys()]}`);
  assert.equal(answered.get('4.uses'), 'dry run', 'the free text typed on the page');
  const p01 = await (await fetch(new URL('/api/protocol/participants/P01', server.url))).json();
  assert.equal(p01.done, true, JSON.stringify(p01));
});

test('a bad argument and a server that is not there: one line on stderr, exit 2', async () => {
  const bad = await dryRun(['--to', 'http://127.0.0.1:1/', '--trees', '9']);
  assert.equal(bad.status, 2);
  assert.match(bad.stderr, /^error: --trees 9: 0 to 7/);
  assert.equal(bad.stderr.trim().split('\n').length, 1);
  const none = await dryRun(['--to', 'http://127.0.0.1:1/']);
  assert.equal(none.status, 2, none.stderr);
  assert.match(none.stderr, /^error: the page at http:\/\/127\.0\.0\.1:1 did not load/);
  assert.equal(none.stderr.trim().split('\n').length, 1);
});
