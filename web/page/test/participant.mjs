// A scripted participant for the browser tests: poses the emulated controller (IWER's right
// Touch Plus) and presses its buttons, frame by frame, as a person in the headset would.

import { lookRotation } from '../input.mjs';
import { ticks, until } from './harness.mjs';

/** Where the controller is held, relative to the head, metres (local-floor). */
const HAND = { x: 0.15, y: -0.3, z: -0.25 };

/** Points the controller at `simPoint` ([x, y, z] in the simulation's frame). */
export async function aimAt(page, simPoint) {
  await page.evaluate(
    ({ p, hand }) => {
      const d = window.xrDevice;
      const target = window.grove.toSession(p);
      const from = { x: d.position.x + hand.x, y: d.position.y + hand.y, z: d.position.z + hand.z };
      window.__aim = { from, target };
      d.controllers.right.position.set(from.x, from.y, from.z);
    },
    { p: simPoint, hand: HAND },
  );
  const { from, target } = await page.evaluate(() => window.__aim);
  const dir = [target.x - from.x, target.y - from.y, target.z - from.z];
  const n = Math.hypot(...dir);
  const q = lookRotation(dir.map((v) => v / n));
  await page.evaluate((q) => window.xrDevice.controllers.right.quaternion.set(q[0], q[1], q[2], q[3]), q);
  await ticks(page, 3);
}

/** Presses and releases an IWER button ('trigger', 'squeeze', 'b-button', …), a few ticks each. */
export async function click(page, button, hold = 4) {
  await page.evaluate((b) => window.xrDevice.controllers.right.updateButtonValue(b, 1), button);
  await ticks(page, hold);
  await page.evaluate((b) => window.xrDevice.controllers.right.updateButtonValue(b, 0), button);
  await ticks(page, hold);
}

/** Opens the menu with B and chooses `model` with the trigger. */
export async function choose(page, model) {
  await click(page, 'b-button');
  await until(page, () => window.grove.snapshot.menu.open);
  await aimAt(page, await page.evaluate((m) => window.grove.menuItemPoint(m), model));
  await click(page, 'trigger');
  await until(page, (m) => !window.grove.snapshot.menu.open && window.grove.snapshot.menu.current_model === m, model);
}

/** Plants the model of every target not yet satisfied at it (ray-casting): menu, aim, trigger. */
export async function plantAll(page, { limit = Infinity } = {}) {
  let planted = 0;
  for (;;) {
    const targets = await page.evaluate(() => window.grove.snapshot.task.targets);
    // The farthest first, so that no planted crown stands between the hand and a target.
    const far = (t) => Math.hypot(t.position[0], t.position[2] - 6);
    const open = targets.map((t, i) => [t, i]).filter(([t]) => !t.satisfied).sort((a, b) => far(b[0]) - far(a[0]));
    if (open.length === 0 || planted >= limit) return planted;
    const i = open[0][1];
    const t = targets[i];
    await choose(page, t.model);
    await aimAt(page, t.moved_to ?? t.position);
    await click(page, 'trigger');
    await until(page, (i) => window.grove.snapshot.task.targets[i].satisfied, i, 20000).catch(async (e) => {
      const s = await page.evaluate(() => window.grove.snapshot);
      throw new Error(`target ${i} (${t.model} at ${t.moved_to ?? t.position}) not satisfied: the ray hits ${JSON.stringify(s.controller.hit)}, trees ${JSON.stringify(s.trees.map((x) => [x.model, x.position]))}, current ${s.menu.current_model}: ${e.message}`);
    });
    planted++;
  }
}
