// Tracked hands as grove's input source (a `tracked-pointer` with an XRHand: Quest's and Pico's
// hand tracking, Vision Pro's hands): the pointing hand's ray is the target ray the browser
// gives it, and its pinch (thumb and index finger) is the Trigger. The other hand's pinch is the
// controller's missing buttons, as the touchpad is on a controller without a squeeze (one rule,
// ButtonMapper's): a pinch shorter than 0.5 s is Bumper (it removes the tree the pointing hand's
// ray is on), a pinch held 0.5 s is Menu. Hands have no touchpad: moving a tree along the ray and
// turning it are done by dragging it and by the box's edge handles (docs/headset.md, "Devices
// and their mappings").
//
// A pinch is the hand's gamepad button 0 where the browser gives hands a gamepad (Quest's
// browser, IWER), else the distance of the thumb's tip to the index finger's tip, with
// hysteresis: closed under 1.5 cm, open again over 3 cm.

import { ButtonMapper, LONG_PRESS_MS } from './buttons.mjs';
import { deviceOf } from './device.mjs';
import { simPose } from './pose.mjs';

/** A pinch closes under this distance between the thumb's and the index finger's tips, metres … */
export const PINCH_CLOSE_M = 0.015;
/** … and opens again over this one. */
export const PINCH_OPEN_M = 0.03;

/** Whether a hand pinches now, given whether it pinched before (`was`). */
export function pinching(frame, source, space, was) {
  if (!source) return false;
  const b = source.gamepad?.buttons?.[0];
  if (b) return Boolean(b.pressed || b.value > 0.8);
  const tip = (name) => source.hand?.get(name) && frame.getJointPose?.(source.hand.get(name), space);
  const thumb = tip('thumb-tip');
  const index = tip('index-finger-tip');
  if (!thumb || !index) return false;
  const a = thumb.transform.position;
  const c = index.transform.position;
  const d = Math.hypot(a.x - c.x, a.y - c.y, a.z - c.z);
  return was ? d < PINCH_OPEN_M : d < PINCH_CLOSE_M;
}

export class Hands {
  static accepts(source) {
    return source.targetRayMode === 'tracked-pointer' && Boolean(source.hand);
  }

  /** `ctx`: { space, offset(), now() } as every kind takes it (input/sources.mjs). */
  constructor(source, ctx) {
    this.source = source;
    this.ctx = ctx;
    this.noSqueeze = false;
    this.mapper = new ButtonMapper({ noSqueeze: true }); // the other hand's pinch: short Bumper, held Menu
    this.pinch = false;
    this.otherPinch = false;
  }

  get handedness() {
    return this.source.handedness;
  }

  poll(frame) {
    const { space } = this.ctx;
    const pose = frame.getPose(this.source.targetRaySpace, space);
    const other = [...frame.session.inputSources].find((s) => s !== this.source && s.hand);
    this.pinch = pinching(frame, this.source, space, this.pinch);
    this.otherPinch = pinching(frame, other, space, this.otherPinch);
    // ButtonMapper's gamepad: button 0 the Trigger, button 2 the press that is Bumper or Menu.
    const pad = { buttons: [{ pressed: this.pinch }, { pressed: false }, { pressed: this.otherPinch }] };
    return { pose: simPose(pose?.transform, this.ctx.offset()), buttons: this.mapper.read(pad, this.ctx.now()), axes: [0, 0] };
  }

  controls(mode) {
    return [
      ['Pinch (pointing hand)', mode === 'manual' ? 'grab and drag a tree or a handle; choose in the menu' : 'plant on the ground, select a tree; choose in the menu'],
      ['Pinch, other hand', 'remove the tree under the ray (Bumper; palm away from you: palm up is the headset\'s own menu)'],
      [`Pinch held ${LONG_PRESS_MS / 1000} s, other hand`, 'open the model menu'],
      ['(no touchpad)', 'move a tree by dragging it; turn it with the edge handles of its box'],
    ];
  }

  /** What the recording's header says of this device. */
  device() {
    return deviceOf(this.source, 'hands');
  }

  /** Why a task's mode cannot be done with hands, or null: both can. */
  refuses() {
    return null;
  }
}
