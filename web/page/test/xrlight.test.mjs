// AR's light (draw/xrlight.mjs). IWER has no light estimation, so a test double of the browser's
// (emulator.mjs's `light`: the session grants `light-estimation`, its probe gives a fixed
// estimate) stands in for Android's Chrome: the page lights AR from it through three.js's
// XREstimatedLight; IWER's own Quest 3, which has none, gets the neutral environment. What a real
// XRLightProbe gives, and its reflection cube map, are not checked here.

import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import { start, until } from './harness.mjs';

/** A warm estimate from the room's upper left: spherical harmonics (9 × RGB), the main light. */
const ESTIMATE = {
  sh: [0.9, 0.6, 0.4, ...new Array(24).fill(0)],
  direction: [-0.6, 0.8, 0],
  intensity: [3, 2, 1],
};

/** Enters AR (the instructions' button; the task need not start). */
async function enterAr(page) {
  await page.click('#enter-ar');
  await until(page, () => window.grove.lighting !== null, null, 30000);
}

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

test("AR is lit by the browser's light estimate where it gives one, else by a neutral environment", async () => {
  const lit = await h.open('participant=LIGHT&task=ray-casting-7&seed=1&quality=low', { xr: true, room: true, light: ESTIMATE, width: 320, height: 320 });
  await enterAr(lit.page);
  await until(lit.page, () => window.grove.lighting.source === 'estimate', null, 20000);
  const estimate = await lit.page.evaluate(() => window.grove.lighting);
  // XREstimatedLight takes the brightest channel as the intensity and the rest as the colour.
  assert.deepEqual(estimate.main.direction, ESTIMATE.direction);
  assert.equal(estimate.main.intensity, 3);
  assert.deepEqual(estimate.main.color.map((c) => Math.round(c * 1000) / 1000), [1, 0.667, 0.333]);
  await lit.page.close();

  const plain = await h.open('participant=PLAIN&task=ray-casting-7&seed=1&quality=low', { xr: true, room: true, width: 320, height: 320 });
  assert.equal(await plain.page.evaluate(() => window.grove.lighting), null, 'nothing before a session');
  await enterAr(plain.page);
  await until(plain.page, () => window.grove.frames > 10);
  assert.deepEqual(await plain.page.evaluate(() => window.grove.lighting), { source: 'neutral', main: null });
  await plain.page.close();
  assert.deepEqual(h.errors, []);
});
