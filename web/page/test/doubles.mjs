// A scripted participant on the devices IWER does not emulate (emulator.mjs's `xrDouble`): a
// phone's screen taps and drags, and gaze and pinch. Each move is made as the browser would
// report it, through XR input sources the page's own input layer reads (input/sources.mjs).

import { frames } from './participant.mjs';
import { until } from './harness.mjs';

/** A finger taps the screen where the camera sees `simPoint` ([x, y, z], the simulation's frame). */
export async function tap(page, simPoint, hold = 5) {
  await page.evaluate((p) => window.xrDouble.touch(p), simPoint);
  await frames(page, hold);
  await page.evaluate(() => window.xrDouble.lift());
  await frames(page, hold);
}

/** A finger comes down where the camera sees `from`, moves to `to` in `steps`, and lifts. */
export async function drag(page, from, to, { steps = 6, before = () => {} } = {}) {
  await page.evaluate((p) => window.xrDouble.touch(p), from);
  await frames(page, 5);
  for (let k = 1; k <= steps; k++) {
    const p = from.map((v, i) => v + ((to[i] - v) * k) / steps);
    await page.evaluate((p) => window.xrDouble.move(p), p);
    await frames(page, 3);
  }
  await before();
  await page.evaluate(() => window.xrDouble.lift());
  await frames(page, 5);
}

/** A press on an element of the page's DOM overlay (the phone's touch bar), `hold` frames down. */
export async function press(page, selector, hold = 5, during = async () => {}) {
  const box = await page.locator(selector).boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await during();
  await frames(page, hold);
  await page.mouse.up();
  await frames(page, hold);
}

/** A pinch of `hand` while the eyes look at `simPoint`, `hold` frames long. */
export async function pinch(page, simPoint, hand = 'right', hold = 5) {
  await page.evaluate(({ p, hand }) => window.xrDouble.pinch(p, hand), { p: simPoint, hand });
  await frames(page, hold);
  await page.evaluate((hand) => window.xrDouble.lift(hand), hand);
  await frames(page, hold);
}

/** Opens the model menu: the phone's Menu button, or a left pinch held 0.5 s. */
export async function openMenu(page, how) {
  if (how === 'screen') await press(page, '#touch-menu');
  else {
    await page.evaluate(() => window.xrDouble.pinch([0, 1, 0], 'left'));
    await until(page, () => window.grove.snapshot.menu.open, null, 30000);
    await page.evaluate(() => window.xrDouble.lift('left'));
    await frames(page, 5);
  }
  await until(page, () => window.grove.snapshot.menu.open, null, 30000);
}

/** Chooses `model` ('finish': Finish task) in the open menu, by a tap or a pinch on its item. */
export async function chooseIn(page, model, how) {
  const at = await page.evaluate((m) => window.grove.menuItemPoint(m), model);
  await (how === 'screen' ? tap(page, at) : pinch(page, at));
  if (model !== 'finish') await until(page, (m) => !window.grove.snapshot.menu.open && window.grove.snapshot.menu.current_model === m, model, 30000);
}

/** Enters `mode` and starts the task with a tap or a pinch (the device has no trigger). */
export async function enterAndTouch(page, mode, how) {
  await page.click(`#enter-${mode}`);
  await until(page, () => window.grove.state === 'instructions' && window.xrDevice.activeSession, null, 30000);
  await frames(page, 10);
  await (how === 'screen' ? tap(page, [0, 0, 4]) : pinch(page, [0, 1, 0]));
  await until(page, () => ['task', 'error'].includes(window.grove.state) && (window.grove.snapshot?.task || window.grove.error), null, 30000);
}
