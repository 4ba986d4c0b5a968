// The scene of the occlusion test and its picture (occlusion.test.mjs, occlusion-screenshot.mjs):
// in immersive-ar on IWER's Quest 3 in @iwer/sem's small office, the ray-casting task laid out so
// that its shrub stands behind the office's desk, planted, then looked at from in front of the
// desk, and the open floor in front of it looked down at.

import assert from 'node:assert/strict';
import { until } from './harness.mjs';
import { aimAt, choose, click, enterAndStart } from './participant.mjs';

/** The ray-casting task's shrub target, the simulation's frame. */
const SHRUB = [-3, 0, -9.5];
/** Where the shrub is to stand in the office (local-floor): behind the front of its desk (the desk spans z −1.03 to −0.27, its top at 0.75 m). */
const BEHIND_DESK = { x: 0.06, z: -0.65 };
/** Where the participant presses the trigger, facing −Z: the task's targets are laid out from there, the shrub's behind the desk. */
const START = { x: BEHIND_DESK.x - SHRUB[0], y: 1.6, z: BEHIND_DESK.z - SHRUB[2] + 6 };
/** Where the headset then looks at the desk from, level, facing −Z. */
export const VIEW = { x: 0.06, y: 1.1, z: 1.0 };
/** The row of the desk's front top edge (0.75 m high at z −0.27) on a canvas of `h` rows, from the top, for IWER's 90° field of view. */
export const deskRow = (h) => Math.round((h / 2) * (1 + (VIEW.y - 0.75) / (VIEW.z + 0.27)));
/** Open floor in front of the desk (local-floor), and the pitch that looks down at it from (0.06, 1.6, 1.1). */
const FLOOR = { x: 0.06, z: 0.6 };
const DOWN = -1.1;
/** A point of the office's floor in the simulation's frame (the offset of START facing −Z). */
const sim = (p) => [p.x - START.x, 0, p.z - START.z + 6];

/**
 * The page's own canvas (its alpha is what the page drew over the room, rows from the top),
 * read in a frame the page drew (one whose number is a multiple of 4: with render_every=4 it draws
 * one frame in four while the run goes on).
 */
export function readCanvas(page) {
  return page.evaluate(
    () =>
      new Promise((resolve) => {
        const session = window.xrDevice.activeSession;
        const read = () => {
          if (window.grove.frames % 4 !== 0) return session.requestAnimationFrame(read);
          const gl = document.getElementById('canvas').getContext('webgl2');
          const [w, h] = [gl.drawingBufferWidth, gl.drawingBufferHeight];
          const px = new Uint8Array(w * h * 4);
          gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
          const alpha = new Array(w * h);
          for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) alpha[y * w + x] = px[((h - 1 - y) * w + x) * 4 + 3];
          resolve({ w, h, alpha });
        };
        session.requestAnimationFrame(read);
      }),
  );
}

/** Places the headset at `at`, pitched by `pitch` radians, and the controller at `hand` aiming at `aim` (the simulation's frame). */
async function look(page, at, pitch, hand, aim) {
  await page.evaluate(
    ({ at, pitch }) => {
      const d = window.xrDevice;
      d.position.set(at.x, at.y, at.z);
      d.quaternion.set(Math.sin(pitch / 2), 0, 0, Math.cos(pitch / 2));
    },
    { at, pitch },
  );
  await aimAt(page, aim, hand);
}

/**
 * Plants the shrub behind the desk (IWER's Quest 3 with depth sensing or without, `depth`), then
 * reads the page's canvas looking at the desk (`shot(page)` then, if given), and looking down at
 * the open floor in front of it with the ray's marker on the floor: { desk, floor, occlusion }.
 */
export async function shrubBehindDesk(h, { depth, quality = 'low', every = 4, size = 320, shot = null }) {
  const { page } = await h.open(
    `participant=OCC&task=ray-casting-7&layout=file&seed=1&quality=${quality}&render_every=${every}`,
    {
      xr: true,
      room: true,
      depth,
      width: size,
      height: size,
    },
  );
  await page.evaluate((p) => window.xrDevice.position.set(p.x, p.y, p.z), START);
  await enterAndStart(page, 'ar');
  await until(page, () => window.grove.snapshot?.task);
  const targets = await page.evaluate(() => window.grove.snapshot.task.targets);
  const i = targets.findIndex((t) => t.model === 'shrub-billboard');
  assert.deepEqual(targets[i].position, SHRUB, 'the task lays its shrub where the test stands it');
  await choose(page, 'shrub-billboard');
  await aimAt(page, SHRUB);
  await click(page, 'trigger');
  await until(page, (i) => window.grove.snapshot.task.targets[i].satisfied, i, 20000);
  // At the desk, the controller low and behind the head, its ray on the ground beside the view.
  await look(page, VIEW, 0, { x: 0.3, y: -0.5, z: 0.6 }, sim({ x: 1.1, z: 1.3 }));
  const desk = await readCanvas(page);
  if (shot) await shot(page);
  // Looking down at the open floor in front of the desk, the ray's marker on it.
  await look(page, { x: 0.06, y: 1.6, z: 1.1 }, DOWN, { x: 0.15, y: -0.3, z: -0.25 }, sim(FLOOR));
  const floor = await readCanvas(page);
  const occlusion = await page.evaluate(() => window.grove.occlusion);
  await page.close();
  return { desk, floor, occlusion };
}
