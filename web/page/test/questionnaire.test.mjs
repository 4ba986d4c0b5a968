// The headset page led by a protocol (docs/protocol.md, "In the headset"): `grove serve
// --protocol assets/protocols/tree-planting.ron` and IWER's Quest 3 in immersive-vr. P01 goes
// through the instructions, the practice and a task from the panel with the controller's ray;
// P02, brought to the seven questions through the server's routes and the study's recordings,
// answers them in the headset by aiming the ray and pulling the trigger: a Send with a required
// answer missing says so on the panel and writes nothing, a reload in the middle comes back to
// the same question, the answers written are those chosen, and the free text is typed on the
// page once the headset is off.

import assert from 'node:assert/strict';
import { readdirSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { fileLines, start, until } from './harness.mjs';
import { aimAt, click, enterStudy as enter, frames, pressPanel, toTheQuestions } from './participant.mjs';

let h;
before(async () => {
  h = await start(['--protocol', 'assets/protocols/tree-planting.ron']);
});
after(async () => {
  await h?.close();
});

const lines = (p) => fileLines(join(h.server.dir, `${p}.answers.jsonl`)).map((l) => JSON.parse(l));
const study = (page) => page.evaluate(() => window.grove.study);

test('P01 goes through the instructions, the practice and a task with the panel, as the server leads', async () => {
  const { page } = await h.open('participant=P01&quality=low&render_every=4', { xr: true, room: false });
  assert.match(await page.textContent('#instructions'), /Step 1 of 8: instructions/);
  await enter(page);
  let s = await study(page);
  assert.deepEqual([s.participant, s.step, s.kind], ['P01', 1, 'instructions']);
  assert.match((await page.evaluate(() => window.grove.panel.texts)).join(' '), /You will plant trees in a park/);
  await pressPanel(page, 'continue');
  await until(page, () => window.grove.state === 'practice');
  assert.equal((await study(page)).kind, 'practice');
  assert.ok(await page.evaluate(() => window.grove.snapshot.task === null), 'the practice is the free scene, no task');
  await pressPanel(page, 'end-practice');
  await until(page, () => window.grove.study.kind === 'task' && window.grove.state === 'step');
  // P01 is the square's first row: ray-casting first.
  assert.match((await page.evaluate(() => window.grove.panel.texts)).join(' '), /Task: ray-casting-7/);
  await pressPanel(page, 'start-task');
  await until(page, () => window.grove.state === 'task');
  assert.equal(await page.evaluate(() => window.grove.snapshot.task.id), 'ray-casting-7');
  // "Finish task" in the model menu ends it; the server ends the session and the page goes on.
  await click(page, 'b-button');
  await until(page, () => window.grove.snapshot.menu.open);
  await aimAt(page, await page.evaluate(() => window.grove.menuItemPoint('finish')));
  await click(page, 'trigger');
  await until(page, () => window.grove.study?.kind === 'questionnaire' && window.grove.state === 'step', null, 60000);
  s = await study(page);
  assert.deepEqual([s.step, s.block, s.item], [4, 'tasks', 'mental']);
  assert.match(
    (await page.evaluate(() => window.grove.panel.texts))[0],
    /NASA Task Load Index \(raw\) \(ray-casting\)/,
  );
  const file = await page.evaluate(() => window.grove.file);
  assert.match(file, /^P01-ray-casting-7/);
  const header = JSON.parse(fileLines(join(h.server.dir, file))[0]);
  assert.deepEqual([header.participant, header.task], ['P01', 'ray-casting-7']);
  assert.deepEqual(
    lines('P01')
      .filter((l) => l.line === 'step')
      .map((l) => [l.step, l.block]),
    [
      [1, 'instructions'],
      [2, 'practice'],
      [3, 'tasks'],
      [4, 'tasks'],
    ],
  );
  assert.deepEqual(h.foreign(), []);
  assert.deepEqual(h.errors, []);
  await page.close();
});

test('P02 answers the seven questions in the headset with the ray and the trigger', async () => {
  const at = await toTheQuestions(h.server.url, 'P02');
  assert.equal(at.step, 7);
  const first = await h.open('participant=P02&quality=low&render_every=4', { xr: true, room: false });
  let page = first.page;
  await enter(page);
  let s = await study(page);
  assert.deepEqual([s.step, s.kind, s.item], [7, 'questionnaire', 'guidance']);
  const texts = await page.evaluate(() => window.grove.panel.texts);
  assert.equal(texts[0], 'About the application');
  assert.ok(texts.includes('Not at all') && texts.includes('Very well'), `the anchors at the ends: ${texts}`);
  assert.deepEqual(
    (await page.evaluate(() => window.grove.panel.buttons)).map((b) => b.label),
    ['0', '1', '2', '3', '4', '5', '6', '7', '8', '9', '10', 'Next'],
  );
  await pressPanel(page, 'opt:8');
  assert.deepEqual(
    (await page.evaluate(() => window.grove.panel.buttons)).filter((b) => b.on).map((b) => b.label),
    ['8'],
  );
  await pressPanel(page, 'next');
  await pressPanel(page, 'opt:2'); // Bounding box
  await pressPanel(page, 'next');
  await pressPanel(page, 'opt:7');
  await pressPanel(page, 'next');
  assert.equal((await study(page)).item, 'realism_lowpoly');

  // A reload in the middle: the same step, the same question, the choices kept.
  await page.close();
  page = (await h.open('participant=P02&quality=low&render_every=4', { xr: true, room: false, context: first.context }))
    .page;
  await enter(page);
  s = await study(page);
  assert.deepEqual([s.step, s.kind, s.item], [7, 'questionnaire', 'realism_lowpoly']);
  await pressPanel(page, 'back');
  assert.deepEqual(
    (await page.evaluate(() => window.grove.panel.buttons)).filter((b) => b.on).map((b) => b.label),
    ['7'],
  );
  await pressPanel(page, 'next');

  await pressPanel(page, 'opt:4');
  await pressPanel(page, 'next');
  await pressPanel(page, 'opt:1'); // Leaves' animation
  await pressPanel(page, 'opt:4'); // Shadow
  await pressPanel(page, 'opt:0'); // Trunk and branches, chosen …
  await pressPanel(page, 'opt:0'); // … and taken back
  await pressPanel(page, 'next');
  assert.equal((await study(page)).item, 'uses');
  assert.match(
    (await page.evaluate(() => window.grove.panel.texts)).join(' '),
    /type this answer on the page after you take the headset off/,
  );
  await pressPanel(page, 'opt:0'); // Type it on the page
  await pressPanel(page, 'next');
  assert.equal((await study(page)).item, 'would_use');

  // Send without the last answer: the panel says so, nothing is written.
  const before = lines('P02').length;
  await pressPanel(page, 'send');
  await until(page, () => window.grove.study.message !== '');
  s = await study(page);
  assert.equal(s.message, 'Question 7 needs an answer before sending.');
  assert.ok((await page.evaluate(() => window.grove.panel.texts)).includes(s.message), 'the reason is on the panel');
  assert.equal(lines('P02').length, before, 'nothing written');

  await pressPanel(page, 'opt:0'); // Yes
  await pressPanel(page, 'send');
  await until(page, () => window.grove.study.typing !== null);
  assert.match(
    (await page.evaluate(() => window.grove.panel.texts)).join(' '),
    /take the headset off and type it on the page/,
  );
  assert.equal(
    await page.evaluate(() => window.grove.state),
    'step',
    'the immersive view stays until the participant leaves it',
  );
  const answers = Object.fromEntries(
    lines('P02')
      .filter((l) => l.line === 'answer' && l.step === 7)
      .map((l) => [l.item, l.answer]),
  );
  assert.deepEqual(answers, {
    guidance: 8,
    more_instructions: ['Bounding box'],
    realism_billboard: 7,
    realism_lowpoly: 4,
    more_realistic: ["Leaves' animation", 'Shadow'],
    would_use: true,
  });

  // The headset's view left: the page asks for the typed answer, then the next step.
  await pressPanel(page, 'leave');
  await until(page, () => window.grove.state === 'typing');
  await page.fill('#typed textarea[name="uses"]', '  teaching urban planning ');
  await page.click('#typed-send');
  await until(page, () => window.grove.study.step === 8 && window.grove.state === 'instructions');
  assert.match(await page.textContent('#instructions'), /Step 8 of 8: usability/);
  const all = lines('P02');
  assert.deepEqual(
    all.filter((l) => l.line === 'answer' && l.step === 7 && l.item === 'uses').map((l) => l.answer),
    ['teaching urban planning'],
  );
  assert.deepEqual(all.at(-1).line === 'step' && all.at(-1).step, 8);
  assert.deepEqual(
    readdirSync(h.server.dir).filter((f) => f.startsWith('P02-')).length,
    2,
    "the two tasks' recordings, none from the page",
  );
  await frames(page, 2);
  assert.deepEqual(h.foreign(), []);
  assert.deepEqual(h.errors, []);
});

test('the inline preview: the same panel, pressed with the mouse', async () => {
  const { page } = await h.open('participant=P04&quality=low&render_every=2');
  // The page joins the participant once it has asked the server: wait for it, not only the load.
  await until(page, () => window.grove.study?.participant === 'P04');
  await page.click('#enter-inline');
  await until(page, () => window.grove.state === 'step' && window.grove.panel);
  const at = await page.evaluate(() => window.grove.screenPoint(window.grove.panelPoint('continue')));
  await page.mouse.move(at.x, at.y);
  await until(page, () => window.grove.panel.hover === 'continue');
  await page.mouse.down();
  await frames(page, 2);
  await page.mouse.up();
  await until(page, () => window.grove.state === 'practice' && window.grove.panel);
  assert.equal((await study(page)).step, 2);
  // The practice's small panel is in the preview's view too.
  const end = await page.evaluate(() => window.grove.screenPoint(window.grove.panelPoint('end-practice')));
  assert.ok(end.x > 0 && end.x < 480 && end.y > 0 && end.y < 360, `End practice in view: ${JSON.stringify(end)}`);
  await page.mouse.move(end.x, end.y);
  await until(page, () => window.grove.panel.hover === 'end-practice');
  await page.mouse.down();
  await frames(page, 2);
  await page.mouse.up();
  await until(page, () => window.grove.study.kind === 'task' && window.grove.state === 'step');
  assert.deepEqual(
    lines('P04')
      .filter((l) => l.line === 'step')
      .map((l) => l.block),
    ['instructions', 'practice', 'tasks'],
  );
  assert.deepEqual(h.errors, []);
  await page.close();
});
