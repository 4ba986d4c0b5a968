// grove serve --protocol end to end (docs/protocol.md): two participants through
// assets/protocols/tree-planting.ron, their tasks pushed through the session client from the
// study's recordings; the server killed in the second participant's second task and started
// again on the folder, the participant resuming there; the dashboard and a questionnaire form
// in Chromium; answers that do not fit refused with nothing written; then `grove study` on the
// folder. Run with `node --test web/protocol/test/` after `cargo build` (GROVE_BIN).

import assert from 'node:assert/strict';
import { spawn, execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, test } from 'node:test';

import { openSession, resumeSession } from '../../client/grove-client.mjs';
import { GROVE, ROOT, studyLines } from '../../client/test/helpers.mjs';

const PROTOCOL = 'assets/protocols/tree-planting.ron';
const dir = mkdtempSync(join(tmpdir(), 'grove-protocol-test-'));
let server = null;
let browser = null;

async function start() {
  const child = spawn(GROVE, ['serve', '--port', '0', '--out', dir, '--protocol', PROTOCOL, '--writer-lease', '0.5'], {
    cwd: ROOT,
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  let log = '';
  const url = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`grove serve did not start: ${log}`)), 30000);
    const seen = (d) => {
      log += d;
      const m = log.match(/listening on (\S+)/);
      if (m) {
        clearTimeout(timer);
        resolve(m[1]);
      }
    };
    child.stdout.on('data', seen);
    child.stderr.on('data', seen);
    child.on('exit', (code) => reject(new Error(`grove serve ended (${code}): ${log}`)));
  });
  return { child, url, log: () => log };
}

async function stop(signal = 'SIGTERM') {
  if (server && server.child.exitCode === null) {
    const ended = new Promise((r) => server.child.once('exit', r));
    server.child.kill(signal);
    await ended;
  }
  server = null;
}

after(async () => {
  await browser?.close();
  await stop();
  // GROVE_KEEP=1 keeps the folder (the sessions, answers, reports and screenshots) to look at.
  if (process.env.GROVE_KEEP) console.log(`kept ${dir}`);
  else rmSync(dir, { recursive: true, force: true });
});

async function api(method, path, body) {
  const r = await fetch(new URL(path, server.url), {
    method,
    headers: { 'content-type': 'application/json' },
    body: body === undefined ? undefined : JSON.stringify(body),
  });
  return { status: r.status, json: await r.json() };
}

async function ok(method, path, body) {
  const r = await api(method, path, body);
  assert.ok(r.status < 300, `${method} ${path}: ${r.status} ${JSON.stringify(r.json.error ?? r.json)}`);
  return r.json;
}

const here = (s) => s.steps[s.step - 1];
const answersFile = (p) => readFileSync(join(dir, `${p}.answers.jsonl`), 'utf8');

// What each participant answers; the long CSV must hold exactly these.
const given = {
  P01: {
    'nasa-tlx.ray-casting': { mental: 35, physical: 20, temporal: 40, performance: 15, effort: 45, frustration: 10 },
    'nasa-tlx.manual': { mental: 60, physical: 55, temporal: 50, performance: 30, effort: 70, frustration: 40 },
    'tree-planting': {
      guidance: 8,
      more_instructions: ['Bounding box'],
      realism_billboard: 7,
      realism_lowpoly: 4,
      more_realistic: ["Leaves' animation", 'Shadow'],
      uses: 'teaching urban planning, with "quotes", commas',
      would_use: true,
    },
    sus: { sus1: 4, sus2: 2, sus3: 4, sus4: 1, sus5: 4, sus6: 2, sus7: 5, sus8: 2, sus9: 4, sus10: 1 },
  },
  P02: {
    'nasa-tlx.manual': { mental: 25, physical: 30, temporal: 20, performance: 10, effort: 35, frustration: 5 },
    'nasa-tlx.ray-casting': { mental: 15, physical: 10, temporal: 20, performance: 5, effort: 20, frustration: 0 },
    'tree-planting': {
      guidance: 6,
      more_instructions: [],
      realism_billboard: 9,
      realism_lowpoly: 5,
      more_realistic: ['Light'],
      would_use: false,
    },
    sus: { sus1: 3, sus2: 3, sus3: 4, sus4: 2, sus5: 3, sus6: 3, sus7: 4, sus8: 2, sus9: 3, sus10: 2 },
  },
};

// The published SUS rule (Brooke 1996), computed here: odd items score − 1, even items 5 − score, × 2.5.
const susOf = (a) =>
  2.5 *
  Array.from({ length: 10 }, (_, i) => (i % 2 === 0 ? a[`sus${i + 1}`] - 1 : 5 - a[`sus${i + 1}`])).reduce(
    (x, y) => x + y,
    0,
  );

function recordingOf(participant, task) {
  return studyLines(`${participant}-${task}.jsonl`);
}

async function doTask(p, cut = null) {
  const s0 = await ok('GET', `/api/protocol/participants/${p}`);
  const step = here(s0);
  assert.equal(step.kind, 'task');
  const lines = recordingOf(p, step.task);
  const session = await openSession(server.url, { header: lines[0] });
  const upTo = cut ?? lines.length;
  for (const l of lines.slice(1, upTo)) session.append(l);
  await session.flush();
  if (cut !== null) return { session, lines, step };
  const ended = await session.end();
  assert.equal(ended.verification.status, 'verified', JSON.stringify(ended));
  return ok('POST', `/api/protocol/participants/${p}/next`, { from: s0.step });
}

async function answer(p, key) {
  const s = await ok('GET', `/api/protocol/participants/${p}`);
  const st = here(s);
  assert.equal(st.kind, 'questionnaire');
  assert.equal(st.condition ? `${st.instrument.id}.${st.condition}` : st.instrument.id, key);
  await ok('POST', `/api/protocol/participants/${p}/answers`, { step: s.step, answers: given[p][key] });
  return ok('POST', `/api/protocol/participants/${p}/next`, { from: s.step });
}

/** Headless Chromium as every browser test here starts it (web/page/headless.mjs). */
async function chromium() {
  const { launchChromium } = await import('../../page/headless.mjs');
  return launchChromium();
}

test('two participants through tree-planting.ron, one resuming after the server was killed in their second task', async (t) => {
  server = await start();
  const p1 = await ok('POST', '/api/protocol/participants', {});
  const p2 = await ok('POST', '/api/protocol/participants', {});
  assert.deepEqual([p1.participant, p2.participant], ['P01', 'P02']);
  // The balanced Latin square of two conditions: the orders alternate.
  assert.deepEqual(p1.order, ['ray-casting', 'manual']);
  assert.deepEqual(p2.order, ['manual', 'ray-casting']);
  assert.deepEqual(
    p1.steps.map((s) => s.kind),
    ['instructions', 'practice', 'task', 'questionnaire', 'task', 'questionnaire', 'questionnaire', 'questionnaire'],
  );

  for (const p of ['P01', 'P02']) {
    await ok('POST', `/api/protocol/participants/${p}/next`, { from: 1 });
    await ok('POST', `/api/protocol/participants/${p}/next`, { from: 2 });
    // A task's step is left only once its session has ended.
    const early = await api('POST', `/api/protocol/participants/${p}/next`, { from: 3 });
    assert.equal(early.status, 409);
    assert.match(early.json.error, /has not ended/);
  }
  await doTask('P01');
  await answer('P01', 'nasa-tlx.ray-casting');
  await doTask('P01');
  await answer('P01', 'nasa-tlx.manual');
  await doTask('P02');
  await answer('P02', 'nasa-tlx.manual');

  // P02's second task: half the recording, then the dashboard, then the server is killed.
  const { session, lines } = await doTask('P02', 300);
  const pushed = lines
    .slice(1, 300)
    .map((l) => JSON.parse(l))
    .filter((l) => l.type === 'event');
  const lastTick = pushed[pushed.length - 1].tick + 1;
  const sofar = JSON.parse(
    execFileSync(
      GROVE,
      ['replay', join(ROOT, 'replays/study/P02-ray-casting-7.jsonl'), '--until', String(lastTick), '--json'],
      { cwd: ROOT, encoding: 'utf8' },
    ),
  );
  browser = await chromium();
  const page = await browser.newPage({ viewport: { width: 1000, height: 800 } });
  await page.goto(new URL('/dashboard', server.url).href);
  const p02row = page.locator('#participants tr[data-participant="P02"]');
  await p02row.locator('td.block').filter({ hasText: 'tasks' }).waitFor({ timeout: 20000 });
  assert.match(await p02row.locator('td.kind').innerText(), /task \(ray-casting\)/);
  const live = page.locator(`#sessions tr[data-file="${session.file}"]`);
  await live.locator('td.targets').filter({ hasText: /\d/ }).waitFor({ timeout: 30000 });
  assert.equal(
    Number(await live.locator('td.targets').innerText()),
    sofar.task.trees.length,
    'targets met so far, as grove replay --until counts them',
  );
  assert.ok(sofar.task.trees.length > 0, 'the cut is after the first tree');
  assert.equal(await live.locator('td.state').innerText(), 'open');
  assert.ok(
    (await page.locator(`svg.map[data-file="${session.file}"] circle.tree`).count()) > 0,
    'the live map shows the trees',
  );
  await page.screenshot({ path: join(dir, 'dashboard.png'), fullPage: true });

  await stop('SIGKILL');
  session.close();
  server = await start();
  const back = await ok('GET', '/api/protocol/participants/P02');
  assert.equal(back.step, 5, 'P02 resumes at their second task');
  assert.equal(here(back).task, 'ray-casting-7');
  const resumed = await resumeSession(server.url, session.id);
  assert.equal(resumed.acked, 300);
  for (const l of lines.slice(300)) resumed.append(l);
  const ended = await resumed.end();
  assert.equal(ended.verification.status, 'verified');
  await ok('POST', '/api/protocol/participants/P02/next', { from: 5 });
  await answer('P02', 'nasa-tlx.ray-casting');

  // The dashboard, loaded again, shows the session verified.
  await page.goto(new URL('/dashboard', server.url).href);
  await page
    .locator(`#sessions tr[data-file="${session.file}"] td.verification`)
    .filter({ hasText: 'verified' })
    .waitFor({ timeout: 20000 });

  await t.test('answers that do not fit their item are refused with a reason and nothing is written', async () => {
    const before = answersFile('P02');
    const step = (await ok('GET', '/api/protocol/participants/P02')).step;
    for (const [answers, reason] of [
      [{ guidance: 11 }, /from 0 to 10; 11 is out of range/],
      [{ realism_lowpoly: 2.5 }, /whole number/],
      [{ more_instructions: ['Teleporting'] }, /no choice 'Teleporting'/],
      [{ uses: 'x'.repeat(2001) }, /at most 2000 characters/],
      [{ would_use: 'maybe' }, /yes or no/],
      [{ guidance: 5, nope: 1 }, /no item 'nope'/],
    ]) {
      const r = await api('POST', '/api/protocol/participants/P02/answers', { step, answers });
      assert.equal(r.status, 422, JSON.stringify(r.json));
      assert.match(r.json.error, reason);
      assert.equal(answersFile('P02'), before, 'nothing written for a refused answer');
    }
    const missing = await api('POST', '/api/protocol/participants/P02/next', { from: step });
    assert.equal(missing.status, 409);
    assert.match(missing.json.error, /not answered yet: guidance/);
  });

  await answer('P02', 'tree-planting');
  await answer('P02', 'sus');

  await t.test("P01 answers the paper's questionnaire in the form page", async () => {
    const form = await browser.newPage({ viewport: { width: 900, height: 1400 } });
    await form.goto(new URL('/protocol?participant=P01', server.url).href);
    await form.locator("form#questionnaire[data-instrument='tree-planting']").waitFor();
    const a = given.P01['tree-planting'];
    for (const id of ['guidance', 'realism_billboard', 'realism_lowpoly'])
      await form.check(`fieldset[data-item=${id}] input[value="${a[id]}"]`);
    for (const id of ['more_instructions', 'more_realistic'])
      for (const c of a[id]) await form.check(`fieldset[data-item=${id}] input[value="${c}"]`);
    await form.fill('fieldset[data-item=uses] textarea', a.uses);
    await form.check(`fieldset[data-item=would_use] input[value="true"]`);
    await form.click('#submit');
    await form.locator("form#questionnaire[data-instrument='sus']").waitFor();
    await form.screenshot({ path: join(dir, 'form.png') });
    await form.close();
  });
  await answer('P01', 'sus');
  for (const p of ['P01', 'P02']) assert.equal((await ok('GET', `/api/protocol/participants/${p}`)).done, true);
  await stop();

  await t.test(
    'grove study on the folder: exactly the answers given, SUS by the published rule, task times as the recordings alone',
    () => {
      const out = join(dir, 'study');
      execFileSync(GROVE, ['study', '--replays', dir, '--out', out], { cwd: ROOT, encoding: 'utf8' });
      const csv = (name) => {
        const rows = [];
        const text = readFileSync(join(out, name), 'utf8');
        // RFC 4180: fields quoted when they hold a comma, a quote or a newline.
        let row = [],
          field = '',
          quoted = false;
        for (let i = 0; i < text.length; i++) {
          const c = text[i];
          if (quoted) {
            if (c === '"' && text[i + 1] === '"') {
              field += '"';
              i++;
            } else if (c === '"') quoted = false;
            else field += c;
          } else if (c === '"') quoted = true;
          else if (c === ',') {
            row.push(field);
            field = '';
          } else if (c === '\n') {
            row.push(field);
            rows.push(row);
            row = [];
            field = '';
          } else field += c;
        }
        const [head, ...body] = rows;
        return body.map((r) => Object.fromEntries(head.map((h, i) => [h, r[i]])));
      };
      const long = csv('questionnaire_long.csv');
      const cellOf = (v) => (typeof v === 'boolean' ? (v ? 'yes' : 'no') : Array.isArray(v) ? v.join(';') : String(v));
      const expected = [];
      for (const [p, sets] of Object.entries(given)) {
        for (const [key, answers] of Object.entries(sets)) {
          const [instrument, condition = ''] = key.split('.');
          for (const [item, v] of Object.entries(answers))
            expected.push(`${p}|${instrument}|${condition}|${item}|${cellOf(v)}`);
        }
      }
      const got = long.map((r) => `${r.participant}|${r.instrument}|${r.condition}|${r.item}|${r.answer}`);
      assert.deepEqual([...got].sort(), [...expected].sort());
      const scores = csv('questionnaire_scores.csv');
      for (const p of ['P01', 'P02']) {
        const sus = scores.find((s) => s.participant === p && s.instrument === 'sus');
        assert.equal(Number(sus.score), susOf(given[p].sus), `${p} SUS`);
        for (const c of ['ray-casting', 'manual']) {
          const tlx = scores.find((s) => s.participant === p && s.instrument === 'nasa-tlx' && s.condition === c);
          const v = Object.values(given[p][`nasa-tlx.${c}`]);
          assert.equal(Number(tlx.score), v.reduce((x, y) => x + y, 0) / 6, `${p} TLX ${c}`);
        }
      }
      const wide = csv('questionnaire_wide.csv');
      assert.equal(wide.length, 2);
      assert.equal(wide.find((r) => r.participant === 'P02')['tree-planting.realism_billboard'], '9');
      const trials = csv('trial_results.csv');
      assert.equal(trials.length, 4);
      for (const tr of trials) {
        const original = tr.file.replace(/-\d+\.jsonl$/, '.jsonl');
        const alone = JSON.parse(
          execFileSync(GROVE, ['replay', join(ROOT, 'replays/study', original), '--json'], {
            cwd: ROOT,
            encoding: 'utf8',
          }),
        );
        assert.equal(Number(tr.time_s), Number(alone.task.time_s.toFixed(4)), tr.file);
        assert.equal(tr.status, 'verified');
      }
      const summary = JSON.parse(readFileSync(join(out, 'summary.json'), 'utf8'));
      const cmp = summary.questionnaires.comparisons[0];
      assert.equal(cmp.n, 2);
      assert.equal(cmp.b_higher, 2, 'both rated the billboards above the low-poly trees');
    },
  );
});
