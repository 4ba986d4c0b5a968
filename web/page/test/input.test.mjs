// The page's input kinds (web/page/input/) driven by test doubles of XR input sources and frames,
// without a browser: hands and their pinches, gaze and pinch (`transient-pointer`), a phone's
// screen taps and drags, the touch bar's claim on a touch, the pointer's choice and what the
// recording's header says of each device. The browser tests drive the same kinds through the page.

import assert from 'node:assert/strict';
import { test } from 'node:test';
import { Hands, PINCH_CLOSE_M } from '../input/hands.mjs';
import { forward, lookRotation } from '../input/pose.mjs';
import { DRAG_M, floorPoint } from '../input/screen.mjs';
import { XrInput, primaryOf, sourceFor } from '../input/sources.mjs';
import { XrController } from '../input/xr.mjs';

const xyz = ([x, y, z]) => ({ x, y, z });
const xyzw = ([x, y, z, w]) => ({ x, y, z, w });
const at = (position, rotation = [0, 0, 0, 1]) => ({ transform: { position: xyz(position), orientation: xyzw(rotation) } });
const looking = (from, to) => {
  const d = to.map((v, i) => v - from[i]);
  const n = Math.hypot(...d);
  return at(from, lookRotation(d.map((v) => v / n)));
};

/** A frame whose poses are looked up by space in `poses` (a Map), with the session's `sources`. */
function frameOf(sources, poses, extra = {}) {
  return { session: { inputSources: sources }, getPose: (space) => poses.get(space) ?? null, getViewerPose: () => at([0, 1.6, 6]), getJointPose: (joint) => poses.get(joint) ?? null, ...extra };
}

function clock() {
  const c = { t: 0 };
  c.ctx = { space: 'base', offset: () => null, now: () => c.t };
  return c;
}

/** A hand whose thumb's and index finger's tips are `gap` metres apart. */
function hand(handedness, poses, gap) {
  const joints = new Map([['thumb-tip', { j: `${handedness}-thumb` }], ['index-finger-tip', { j: `${handedness}-index` }]]);
  const s = { targetRayMode: 'tracked-pointer', handedness, profiles: ['generic-hand'], hand: joints, targetRaySpace: `${handedness}-ray` };
  const set = (g) => {
    poses.set(joints.get('thumb-tip'), at([0, 1, 5]));
    poses.set(joints.get('index-finger-tip'), at([g, 1, 5]));
  };
  set(gap);
  poses.set(s.targetRaySpace, looking([0.2, 1.2, 5.7], [0, 0, 2]));
  return { s, set };
}

test('hands: the pointing hand pinches the trigger (with hysteresis), the other hand is Bumper when short and Menu when held', () => {
  const poses = new Map();
  const c = clock();
  const right = hand('right', poses, 0.08);
  const left = hand('left', poses, 0.08);
  const frame = frameOf([left.s, right.s], poses);
  assert.equal(XrController.accepts(right.s), false, 'a hand is not a controller');
  const input = new XrInput(c.ctx);
  const poll = () => input.poll(frame);
  assert.equal(poll().buttons.trigger, false);
  assert.ok(input.pointer instanceof Hands && input.pointer.handedness === 'right', 'the right hand points');
  right.set(PINCH_CLOSE_M - 0.005);
  assert.equal(poll().buttons.trigger, true);
  right.set(0.025); // between closing and opening: still pinched
  assert.equal(poll().buttons.trigger, true);
  right.set(0.04);
  assert.equal(poll().buttons.trigger, false);
  // The other hand: a short pinch is Bumper, for one tick, at its end.
  left.set(0.005);
  assert.deepEqual(poll().buttons, { trigger: false, bumper: false, touchpad: false, menu: false });
  c.t = 200;
  left.set(0.08);
  assert.equal(poll().buttons.bumper, true);
  assert.equal(poll().buttons.bumper, false);
  // Held 0.5 s: Menu, until it opens.
  left.set(0.005);
  poll();
  c.t = 800;
  assert.equal(poll().buttons.menu, true);
  left.set(0.08);
  assert.deepEqual(poll().buttons, { trigger: false, bumper: false, touchpad: false, menu: false });
  assert.deepEqual(input.device(), { profile: 'generic-hand', target_ray_mode: 'tracked-pointer', mapping: 'hands' });
  // A browser that gives hands a gamepad (Quest's, IWER): its button 0 is the pinch.
  right.s.gamepad = { buttons: [{ pressed: true, value: 1 }] };
  assert.equal(poll().buttons.trigger, true);
});

test('gaze and pinch: the ray is the gaze where the pinch began, carried by the grip; the pinch ends the trigger; the left hand is Bumper or Menu', () => {
  const poses = new Map();
  const c = clock();
  const input = new XrInput(c.ctx);
  const frame = frameOf([], poses);
  assert.equal(input.poll(frame).pose, null, 'no pinch yet: no pointer');
  const pinch = (handedness, grip) => {
    const s = { targetRayMode: 'transient-pointer', handedness, profiles: ['generic-button'], targetRaySpace: `${handedness}-gaze`, gripSpace: `${handedness}-grip` };
    poses.set(s.targetRaySpace, looking([0, 1.6, 6], [1, 0, 2]));
    poses.set(s.gripSpace, at(grip));
    frame.session.inputSources.push(s);
    return s;
  };
  const right = pinch('right', [0.2, 1.2, 5.6]);
  const first = input.poll(frame);
  assert.equal(first.buttons.trigger, true);
  assert.deepEqual(first.pose.position, [0, 1.6, 6], 'the gaze ray leaves the eyes');
  const d0 = forward(first.pose.rotation);
  const want = [1, -1.6, -4].map((v) => v / Math.hypot(1, 1.6, 4));
  assert.deepEqual(d0.map((v) => +v.toFixed(6)), want.map((v) => +v.toFixed(6)), 'towards where the eyes looked');
  // The eyes look elsewhere (the browser's ray would follow): the ray stays; the hand moves 0.3 m: so does the ray.
  poses.set(right.targetRaySpace, looking([0, 1.6, 6], [-3, 0, 0]));
  poses.set(right.gripSpace, at([0.5, 1.2, 5.6]));
  const moved = input.poll(frame);
  assert.deepEqual(moved.pose.position.map((v) => +v.toFixed(6)), [0.3, 1.6, 6]);
  assert.deepEqual(forward(moved.pose.rotation).map((v) => +v.toFixed(6)), d0.map((v) => +v.toFixed(6)));
  // The pinch ends: the source is gone, the trigger goes up where the ray was.
  frame.session.inputSources.length = 0;
  const after = input.poll(frame);
  assert.equal(after.buttons.trigger, false);
  assert.deepEqual(after.pose, moved.pose);
  // The left hand: short is Bumper (at its own gaze), held is Menu.
  const left = pinch('left', [-0.2, 1.2, 5.6]);
  input.poll(frame);
  c.t = 100;
  frame.session.inputSources.length = 0;
  assert.equal(input.poll(frame).buttons.bumper, true);
  pinch('left', [-0.2, 1.2, 5.6]);
  input.poll(frame);
  c.t = 700;
  assert.equal(input.poll(frame).buttons.menu, true);
  assert.ok(left);
  assert.deepEqual(input.device(), { profile: 'generic-button', target_ray_mode: 'transient-pointer', mapping: 'transient-pointer' });
});

/** A phone's touch bar as input/touchbar.mjs's TouchBar answers. */
function bar() {
  return { claimed: false, bumper: false, menu: false, axes: [0, 0], show() {}, claims() { return this.claimed; }, read() { return { bumper: this.bumper, menu: this.menu, axes: this.axes }; } };
}

test("a phone's screen: a tap waits a frame, is the trigger, and a touch the bar claims never is; a drag brings the grabbed tree's base under the finger", () => {
  const poses = new Map();
  const c = clock();
  const b = bar();
  let snapshot = null;
  const input = new XrInput({ ...c.ctx, bar: b, snapshot: () => snapshot });
  const frame = frameOf([], poses);
  const touch = (to) => {
    const s = { targetRayMode: 'screen', handedness: 'none', profiles: ['generic-touchscreen'], targetRaySpace: {} };
    poses.set(s.targetRaySpace, looking([0, 1.5, 6], to));
    frame.session.inputSources.push(s);
    return s;
  };
  // A touch on the bar: its screen source is the bar's for as long as it lasts.
  b.claimed = true;
  b.menu = true;
  touch([0, 0, 3]);
  for (let i = 0; i < 3; i++) {
    const r = input.poll(frame);
    assert.equal(r.buttons.trigger, false, 'a tap on the bar is not the scene\'s');
    assert.equal(r.buttons.menu, true);
  }
  frame.session.inputSources.length = 0;
  b.claimed = false;
  b.menu = false;
  input.poll(frame);
  // A tap on the scene: a frame later it is the trigger, at the ray where it came down.
  const s = touch([1, 0, 3]);
  assert.equal(input.poll(frame).buttons.trigger, false, 'the first frame waits for the bar');
  const down = input.poll(frame);
  assert.equal(down.buttons.trigger, true);
  assert.deepEqual(floorPoint(down.pose).map((v) => +v.toFixed(6)), [1, 0, 3]);
  // The finger moves 2 cm over the floor: still a tap; 1 m: a drag of the tree it touched, whose base follows the finger.
  snapshot = { controller: { hit: { kind: 'plane', entity: 1 } }, bounding_box: { tree: 9 }, trees: [{ id: 9, position: [1, 1, 3] }] };
  poses.set(s.targetRaySpace, looking([0, 1.5, 6], [1 + DRAG_M * 0.6, 0, 3]));
  assert.deepEqual(input.poll(frame).pose, down.pose);
  poses.set(s.targetRaySpace, looking([0, 1.5, 6], [2, 0, 3]));
  const drag = input.poll(frame);
  assert.deepEqual(drag.pose.rotation, down.pose.rotation, 'the ray keeps its direction');
  assert.deepEqual(drag.pose.position.map((v) => +v.toFixed(6)), [1, 0.5, 6], 'moved by the finger\'s point (2, 0, 3) less the tree\'s base (1, 1, 3)');
  // A touch that grabbed something else (a handle) drags with the finger's own ray.
  frame.session.inputSources.length = 0;
  input.poll(frame);
  snapshot = { controller: { hit: { kind: 'handle', entity: null } }, bounding_box: { tree: 9 }, trees: [{ id: 9, position: [1, 1, 3] }] };
  const h = touch([0, 0, 4]);
  input.poll(frame);
  input.poll(frame);
  poses.set(h.targetRaySpace, looking([0, 1.5, 6], [0.5, 0, 4]));
  const handle = input.poll(frame);
  assert.deepEqual(handle.pose, { position: [0, 1.5, 6], rotation: handle.pose.rotation });
  assert.deepEqual(floorPoint(handle.pose).map((v) => +v.toFixed(6)), [0.5, 0, 4], 'the finger\'s own ray');
  // The finger lifts: the trigger goes up where the ray was; Remove then acts there.
  frame.session.inputSources.length = 0;
  b.bumper = true;
  const up = input.poll(frame);
  assert.deepEqual([up.buttons.trigger, up.buttons.bumper], [false, true]);
  assert.deepEqual(up.pose, handle.pose);
  assert.deepEqual(input.device(), { profile: 'generic-touchscreen', target_ray_mode: 'screen', mapping: 'screen' });
});

test('the pointer and the registry: shared kinds are one object, a persistent pointer wins, a gaze source is nobody\'s', () => {
  const shared = new Map();
  const c = clock();
  const a = sourceFor({ targetRayMode: 'screen' }, c.ctx, undefined, shared);
  const b = sourceFor({ targetRayMode: 'screen' }, c.ctx, undefined, shared);
  assert.equal(a, b);
  assert.equal(sourceFor({ targetRayMode: 'gaze' }, c.ctx), null);
  const ctl = sourceFor({ targetRayMode: 'tracked-pointer', handedness: 'right', gamepad: { buttons: [{}, {}] }, profiles: ['Meta Quest Touch Plus!'] }, c.ctx);
  assert.deepEqual(ctl.device(), { profile: 'meta-quest-touch-plus-', target_ray_mode: 'tracked-pointer', mapping: 'controller' });
  assert.equal(primaryOf([ctl, a]), a);
  const input = new XrInput(c.ctx);
  const frame = frameOf([{ targetRayMode: 'gaze', handedness: 'none' }], new Map());
  input.poll(frame);
  assert.deepEqual(input.unusable(), ['gaze']);
  assert.equal(input.device(), null);
});
