// docs/headset-phone.png: the page on a phone in immersive-ar (IWER's small office from
// @iwer/sem, the phone's screen taps from emulator.mjs's test doubles), the ray-casting task laid
// out on the office's floor, a few trees planted by taps, the last one tapped selected, and the
// DOM overlay over the camera's view: the header and the touch bar (Remove, Menu, the Move pad).
// Run after the page is built (node web/page/build.mjs):
//
//   node web/page/test/phone-screenshot.mjs OUT.png [TREES]

import { start, until } from './harness.mjs';
import { frames } from './participant.mjs';
import { chooseIn, enterAndTouch, openMenu, tap } from './doubles.mjs';

const out = process.argv[2];
if (!out) {
  console.error('usage: node web/page/test/phone-screenshot.mjs OUT.png [TREES]');
  process.exit(2);
}
const trees = Number(process.argv[3] ?? 4);
const h = await start();
try {
  const { page } = await h.open('participant=PHONE&task=ray-casting-7&seed=1', { xr: true, room: true, device: 'phone', width: 390, height: 760 });
  await enterAndTouch(page, 'ar', 'screen');
  // The phone held a step back from where the task started, looking down at the floor.
  await page.evaluate(() => {
    const d = window.xrDevice;
    d.position.set(d.position.x + 0.05, 1.0, d.position.z + 1.3);
    d.quaternion.set(-Math.sin(0.3), 0, 0, Math.cos(0.3)); // pitched 34° down
  });
  await frames(page, 10);
  const targets = await page.evaluate(() => window.grove.snapshot.task.targets);
  const last = [];
  for (const t of targets.slice(0, trees)) {
    await openMenu(page, 'screen');
    await chooseIn(page, t.model, 'screen');
    await tap(page, t.position);
    last.splice(0, 1, t);
  }
  if (last[0]) await tap(page, [last[0].position[0], 0.02, last[0].position[2]]);
  await until(page, () => window.grove.snapshot.task.targets.filter((t) => t.satisfied).length >= 1, null, 10000);
  await frames(page, 20);
  await page.screenshot({ path: out });
  console.log(`${out}: a phone in AR, ${trees} trees, the touch bar`);
  if (h.errors.length) console.error(h.errors.join('\n'));
} finally {
  await h.close();
}
