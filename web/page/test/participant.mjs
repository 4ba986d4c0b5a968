// A scripted participant for the browser tests: poses the emulated controller (IWER's right
// Touch Plus) or hand and presses its buttons or pinches (emulator.mjs's `xrParticipant`), frame
// by frame, as a person in the headset would.

import assert from 'node:assert/strict';
import { lookRotation } from '../input/pose.mjs';
import { openSession } from '../../client/grove-client.mjs';
import { studyLines } from '../../client/test/helpers.mjs';
import { ticks, until } from './harness.mjs';

/** Where the controller is held, relative to the head, metres (local-floor). */
const HAND = { x: 0.15, y: -0.3, z: -0.25 };

/** Waits until the page has drawn `n` more frames (whether a simulation runs or not). */
export async function frames(page, n) {
  const start = await page.evaluate(() => window.grove.frames);
  await until(page, (t) => window.grove.frames >= t, start + n);
}

/**
 * Points the controller, held at `hand` from the head, at `simPoint` ([x, y, z] in the
 * simulation's frame); `wait` lets the page see it (three ticks of the task by default).
 */
export async function aimAt(page, simPoint, hand = HAND, wait = (page) => ticks(page, 3)) {
  await page.evaluate(
    ({ p, hand }) => {
      const d = window.xrDevice;
      const target = window.grove.toSession(p);
      const from = { x: d.position.x + hand.x, y: d.position.y + hand.y, z: d.position.z + hand.z };
      window.__aim = { from, target };
      window.xrParticipant.pointer().position.set(from.x, from.y, from.z);
    },
    { p: simPoint, hand },
  );
  const { from, target } = await page.evaluate(() => window.__aim);
  const dir = [target.x - from.x, target.y - from.y, target.z - from.z];
  const n = Math.hypot(...dir);
  const q = lookRotation(dir.map((v) => v / n));
  await page.evaluate((q) => window.xrParticipant.pointer().quaternion.set(q[0], q[1], q[2], q[3]), q);
  await wait(page);
}

/**
 * Presses the protocol's panel button `id` (docs/protocol.md) as a participant does: aims the
 * ray at it, checks that the panel highlights it, and pulls the trigger.
 */
export async function pressPanel(page, id) {
  const point = await page.evaluate((id) => window.grove.panelPoint(id), id);
  assert.ok(point, `the panel has a button ${id}: ${JSON.stringify(await page.evaluate(() => window.grove.panel))}`);
  await aimAt(page, point, HAND, (page) => frames(page, 3));
  await until(page, (id) => window.grove.panel?.hover === id, id, 10000);
  await page.evaluate(() => window.xrParticipant.press('trigger', 1));
  await frames(page, 3);
  await page.evaluate(() => window.xrParticipant.press('trigger', 0));
  await frames(page, 3);
}

/** Presses and releases an IWER button ('trigger', 'squeeze', 'b-button', …), a few ticks each. */
export async function click(page, button, hold = 4) {
  await page.evaluate((b) => window.xrParticipant.press(b, 1), button);
  await ticks(page, hold);
  await page.evaluate((b) => window.xrParticipant.press(b, 0), button);
  await ticks(page, hold);
}

/**
 * Opens the menu with `menu` held 40 ticks (B; with hands the left hand's pinch held 0.5 s; on a
 * controller without a squeeze, 'touchpad') and chooses `model` with the trigger.
 */
export async function choose(page, model, menu = 'b-button') {
  await click(page, menu, 40);
  await until(page, () => window.grove.snapshot.menu.open);
  await aimAt(page, await page.evaluate((m) => window.grove.menuItemPoint(m), model));
  await click(page, 'trigger');
  await until(page, (m) => !window.grove.snapshot.menu.open && window.grove.snapshot.menu.current_model === m, model);
}

/** Plants the model of every target not yet satisfied at it (ray-casting): menu, aim, trigger. */
export async function plantAll(page, { limit = Infinity, menu = 'b-button' } = {}) {
  let planted = 0;
  for (;;) {
    const targets = await page.evaluate(() => window.grove.snapshot.task.targets);
    // The farthest first, so that no planted crown stands between the hand and a target.
    const far = (t) => Math.hypot(t.position[0], t.position[2] - 6);
    const open = targets
      .map((t, i) => [t, i])
      .filter(([t]) => !t.satisfied)
      .sort((a, b) => far(b[0]) - far(a[0]));
    if (open.length === 0 || planted >= limit) return planted;
    const i = open[0][1];
    const t = targets[i];
    await choose(page, t.model, menu);
    await aimAt(page, t.moved_to ?? t.position);
    await click(page, 'trigger');
    await until(page, (i) => window.grove.snapshot.task.targets[i].satisfied, i, 20000).catch(async (e) => {
      const s = await page.evaluate(() => window.grove.snapshot);
      throw new Error(
        `target ${i} (${t.model} at ${t.moved_to ?? t.position}) not satisfied: the ray hits ${JSON.stringify(s.controller.hit)}, trees ${JSON.stringify(s.trees.map((x) => [x.model, x.position]))}, current ${s.menu.current_model}: ${e.message}`,
      );
    });
    planted++;
  }
}

/**
 * Enters an immersive mode (`ar` or `vr`) and starts the task with a trigger press (a session
 * being continued starts at once).
 */
export async function enterAndStart(page, mode) {
  await page.click(`#enter-${mode}`);
  await until(
    page,
    () => ['instructions', 'task'].includes(window.grove.state) && window.xrDevice.activeSession,
    null,
    30000,
  );
  if ((await page.evaluate(() => window.grove.state)) !== 'task') {
    await page.waitForTimeout(300);
    await page.evaluate(() => window.xrParticipant.press('trigger', 1));
    await until(page, () => ['task', 'error'].includes(window.grove.state), null, 30000);
    await page.evaluate(() => window.xrParticipant.press('trigger', 0));
  }
  await until(page, () => ['task', 'error'].includes(window.grove.state), null, 30000);
  assert.equal(await page.evaluate(() => window.grove.error), null);
}

/** Holds the controller at `simPoint` ([x, y, z], the simulation's frame), its orientation kept. */
export async function moveHand(page, simPoint) {
  await page.evaluate((p) => {
    const s = window.grove.toSession(p);
    window.xrParticipant.pointer().position.set(s.x, s.y, s.z);
  }, simPoint);
  await ticks(page, 2);
}

/** Manual mode: aims at tree `id` (selected: at its box's middle) and presses the trigger on it. */
export async function grab(page, id) {
  const box = await page.evaluate(() => window.grove.snapshot.bounding_box);
  assert.equal(box?.tree, id, 'the tree is selected');
  // Its middle, else lower down its axis (a billboard's crossed quads, a thin trunk).
  const [x, y, z] = box.center;
  let hit = null;
  for (const f of [0, 0.25, 0.5, 0.75, -0.25]) {
    await aimAt(page, [x, y - f * box.half_extents[1], z]);
    hit = await page.evaluate(() => window.grove.snapshot.controller.hit);
    if (hit?.entity === id) break;
  }
  assert.equal(hit?.entity, id, `the ray meets the tree: ${JSON.stringify(hit)}`);
  await page.evaluate(() => window.xrParticipant.press('trigger', 1));
  await ticks(page, 3);
}

/**
 * Manual mode, the trigger held on tree `id`: carries the controller so that the tree's origin
 * comes to `to` ([x, y, z]) in steps of at most `step` metres; returns the snapshot there.
 */
export async function carry(page, id, to, { step = 0.15 } = {}) {
  const tree = async () => page.evaluate((id) => window.grove.snapshot.trees.find((t) => t.id === id), id);
  let hand = await page.evaluate(() => window.grove.snapshot.controller.pose.position);
  for (let k = 0; k < 400; k++) {
    const at = (await tree()).position;
    const d = [to[0] - at[0], to[1] - at[1], to[2] - at[2]];
    const n = Math.hypot(...d);
    if (n < 1e-3) break;
    const f = Math.min(1, step / n);
    hand = hand.map((v, i) => v + d[i] * f);
    await moveHand(page, hand);
  }
  return page.evaluate(() => window.grove.snapshot);
}

/** Releases the trigger and waits a few ticks. */
export async function release(page) {
  await page.evaluate(() => window.xrParticipant.press('trigger', 0));
  await ticks(page, 3);
  return page.evaluate(() => window.grove.snapshot);
}

/** A protocol's participant enters immersive-vr (or `mode`); their step shows at once (a panel, the practice or a task). */
export async function enterStudy(page, mode = 'vr') {
  await page.click(`#enter-${mode}`);
  await until(
    page,
    () => ['step', 'practice', 'task', 'error'].includes(window.grove.state) && window.xrDevice.activeSession,
    null,
    30000,
  );
  assert.equal(await page.evaluate(() => window.grove.error), null);
  await until(page, () => window.grove.state !== 'step' || window.grove.panel);
}

/**
 * Brings participant `p` of tree-planting.ron to its seven questions through the server's routes
 * (at `url`): the steps before them passed, each task's session pushed from the study's
 * recording of `p`, each NASA-TLX answered. Resolves to the participant's state.
 */
export async function toTheQuestions(url, p) {
  const api = async (method, path, body) => {
    const r = await fetch(new URL(path, url), {
      method,
      headers: { 'content-type': 'application/json' },
      body: body === undefined ? undefined : JSON.stringify(body),
    });
    const v = await r.json();
    assert.ok(r.ok, `${method} ${path}: ${r.status} ${JSON.stringify(v)}`);
    return v;
  };
  const tlx = { mental: 25, physical: 30, temporal: 20, performance: 10, effort: 35, frustration: 5 };
  let s = await api('POST', '/api/protocol/participants', { participant: p });
  for (;;) {
    const st = s.steps[s.step - 1];
    if (st.kind === 'questionnaire' && st.instrument.id === 'tree-planting') return s;
    if (st.kind === 'task') {
      const rec = studyLines(`${p}-${st.task}.jsonl`);
      const session = await openSession(url, { header: rec[0] });
      for (const l of rec.slice(1)) session.append(l);
      await session.flush();
      await session.end();
    }
    if (st.kind === 'questionnaire')
      await api('POST', `/api/protocol/participants/${p}/answers`, { step: s.step, answers: tlx });
    s = await api('POST', `/api/protocol/participants/${p}/next`, { from: s.step });
  }
}

/**
 * Opens the menu with `menu` held 40 ticks, as `choose` does (B, or the touchpad of a controller
 * without a squeeze), and chooses Finish task (docs/headset.md, "How a task ends").
 */
export async function finishTask(page, menu = 'b-button') {
  await click(page, menu, 40);
  await until(page, () => window.grove.snapshot.menu.open);
  await aimAt(page, await page.evaluate(() => window.grove.menuItemPoint('finish')));
  await click(page, 'trigger');
}

/**
 * Manual mode: brings a tree of each target's model from the menu onto the target not yet
 * satisfied (grabbed, carried above it, lowered until the anchor ball is white, released).
 */
export async function dragAll(page, { limit = Infinity } = {}) {
  let placed = 0;
  for (;;) {
    const targets = await page.evaluate(() => window.grove.snapshot.task.targets);
    const open = targets.map((t, i) => [t, i]).filter(([t]) => !t.satisfied);
    if (open.length === 0 || placed >= limit) return placed;
    const [t, i] = open[0];
    const own = await page.evaluate(() => window.grove.snapshot.trees.map((x) => x.id));
    await choose(page, t.model);
    await until(page, (n) => window.grove.snapshot.trees.length === n, own.length + 1);
    const spawned = await page.evaluate((own) => window.grove.snapshot.trees.find((x) => !own.includes(x.id)), own);
    await grab(page, spawned.id);
    const [x, y, z] = t.moved_to ?? t.position;
    await carry(page, spawned.id, [x, y + 1, z], { step: 0.5 });
    await carry(page, spawned.id, [x, y + 0.05, z]);
    await release(page);
    await until(page, (i) => window.grove.snapshot.task.targets[i].satisfied, i, 20000);
    placed++;
  }
}

/**
 * Plays the task the page has started: `trees` targets planted (ray-casting) or dragged onto
 * (manual), all by default, then Finish task if any is left; waits for the server's verification.
 * Resolves to { file, task, trees, verification }.
 */
export async function playTask(page, { trees = Infinity } = {}) {
  await until(page, () => window.grove.snapshot?.task || window.grove.state === 'error');
  const { file, task, mode } = await page.evaluate(() => ({
    file: window.grove.file,
    task: window.grove.snapshot.task?.id,
    mode: window.grove.snapshot.mode,
  }));
  const done = mode === 'manual' ? await dragAll(page, { limit: trees }) : await plantAll(page, { limit: trees });
  // Every target met ends the task by itself; else Finish task in the menu.
  if (
    await page.evaluate(
      () => window.grove.state === 'task' && window.grove.snapshot.task.targets.some((t) => !t.satisfied),
    )
  )
    await finishTask(page);
  // On its own the page stays at done with the verification; with a protocol it goes on once it has it.
  await until(
    page,
    () =>
      (window.grove.state === 'done' && window.grove.verification) ||
      ['step', 'practice', 'instructions', 'typing', 'error'].includes(window.grove.state),
    null,
    120000,
  );
  const verification = await page.evaluate(() => window.grove.verification);
  return { file, task, trees: done, verification };
}

/** The item's answer a scripted participant gives: 'Skip it' for optional free text, else the middle option. */
function pick(buttons) {
  const options = buttons.filter((b) => b.id.startsWith('opt:'));
  const skip = options.find((b) => b.label === 'Skip it');
  if (skip) return skip.id;
  return options.length ? options[Math.floor(options.length / 2)].id : null;
}

/**
 * Takes a protocol's participant through every step the server gives them, in the headset
 * (`mode`): instructions continued, the practice ended, each task played (`trees` as playTask),
 * each questionnaire answered item by item on the panel (the middle option, optional free text
 * skipped, required free text typed on the page as "dry run"), until the server says they are
 * done. Resolves to the tasks' recordings as playTask gives them.
 */
export async function throughProtocol(page, { mode = 'vr', trees = Infinity } = {}) {
  const sessions = [];
  const now = () =>
    page.evaluate(() => ({
      state: window.grove.state,
      study: window.grove.study,
      panel: window.grove.panel,
      error: window.grove.error,
    }));
  for (let turn = 0; turn < 1000; turn++) {
    const { state, study, panel, error } = await now();
    if (state === 'error') throw new Error(`the page failed: ${error}`);
    if (study?.kind === 'done') return sessions;
    if (state === 'step' && study?.message) throw new Error(`step ${study.step}: ${study.message}`);
    if (state === 'instructions') await enterStudy(page, mode);
    else if (state === 'typing') {
      for (const box of await page.$$('#typed textarea')) await box.fill('dry run');
      await page.click('#typed-send');
      await until(page, () => window.grove.state !== 'typing');
    } else if (state === 'task') sessions.push(await playTask(page, { trees }));
    else if (state === 'practice' && panel) await pressPanel(page, 'end-practice');
    else if (state === 'step' && panel && study.typing) await pressPanel(page, 'leave');
    else if (state === 'step' && panel && study.kind === 'instructions') await pressPanel(page, 'continue');
    else if (state === 'step' && panel && study.kind === 'task') {
      await pressPanel(page, 'start-task');
      await until(page, () => ['task', 'error'].includes(window.grove.state), null, 30000);
    } else if (state === 'step' && panel && study.kind === 'questionnaire') {
      const ids = panel.buttons.map((b) => b.id);
      const chosen = panel.buttons.some((b) => b.id.startsWith('opt:') && b.on);
      const answer = chosen ? null : pick(panel.buttons);
      if (answer) await pressPanel(page, answer);
      else await pressPanel(page, ids.includes('send') ? 'send' : 'next');
    } else await frames(page, 2);
  }
  throw new Error('the protocol did not end within 1000 moves');
}
