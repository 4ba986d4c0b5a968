// Gaze and pinch (a `transient-pointer`: Apple Vision Pro's Safari) as grove's input source. An
// XR input source of this mode exists only while a hand pinches: its target ray is where the eyes
// looked when the pinch began. That ray is kept fixed, and while the pinch is held it is carried
// by the pinching hand's grip space, so a drag follows the hand (input/pose.mjs's `carried`).
//
// The pinch of the right hand (or of a hand the browser does not name) is the Trigger. A pinch of
// the left hand is the controller's missing buttons, with the rule of a controller without a
// squeeze (ButtonMapper's): shorter than 0.5 s Bumper, at the gaze of that pinch (it removes the
// tree looked at), held 0.5 s Menu. There is no touchpad: a tree is moved by dragging it and
// turned by the box's edge handles. Between pinches the ray stays where the last one left it.
//
// One object serves every transient source of the session (`static shared`: input/sources.mjs
// attaches and detaches them), and stays the pointer between pinches (`persistent`), so that the
// pinch's end is seen as the Trigger's release.

import { ButtonMapper, LONG_PRESS_MS } from './buttons.mjs';
import { deviceOf } from './device.mjs';
import { carried, simPose } from './pose.mjs';

export class TransientPointer {
  static accepts(source) {
    return source.targetRayMode === 'transient-pointer';
  }

  static shared = true;

  /** `ctx`: { space, offset(), now() } as every kind takes it (input/sources.mjs). */
  constructor(ctx) {
    this.ctx = ctx;
    this.noSqueeze = false;
    this.persistent = true;
    this.handedness = 'right';
    this.mapper = new ButtonMapper({ noSqueeze: true }); // the left hand's pinch: short Bumper, held Menu
    this.pinches = new Map(); // XRInputSource -> { ray0, grip0 } once seen in a frame
    this.pose = null;
    this.last = null; // the source whose description the header takes
  }

  attach(source) {
    this.pinches.set(source, null);
    this.last = source;
  }

  detach(source) {
    this.pinches.delete(source);
  }

  /** The ray of a pinch now: its gaze ray at the start, carried by its grip. */
  #ray(frame, source) {
    const { space } = this.ctx;
    const at = (s) => (s ? simPose(frame.getPose(s, space)?.transform, this.ctx.offset()) : null);
    let p = this.pinches.get(source);
    if (!p) {
      p = { ray0: at(source.targetRaySpace), grip0: at(source.gripSpace) };
      if (!p.ray0) return null;
      this.pinches.set(source, p);
    }
    return carried(p.ray0, p.grip0, at(source.gripSpace));
  }

  poll(frame) {
    const sources = [...this.pinches.keys()];
    const main = sources.find((s) => s.handedness !== 'left') ?? null;
    const other = sources.find((s) => s.handedness === 'left') ?? null;
    const ray = (main && this.#ray(frame, main)) ?? (other && this.#ray(frame, other));
    if (ray) this.pose = ray;
    const pad = { buttons: [{ pressed: Boolean(main) }, { pressed: false }, { pressed: Boolean(other) }] };
    return { pose: this.pose, buttons: this.mapper.read(pad, this.ctx.now()), axes: [0, 0] };
  }

  controls(mode) {
    return [
      ['Look, pinch (right hand)', mode === 'manual' ? 'grab the tree you look at; move the hand to drag it; choose in the menu' : 'plant where you look, select a tree; choose in the menu'],
      ['Look, pinch (left hand)', 'remove the tree you look at (Bumper)'],
      [`Pinch held ${LONG_PRESS_MS / 1000} s (left hand)`, 'open the model menu'],
      ['(no touchpad)', 'move a tree by dragging it; turn it with the edge handles of its box'],
    ];
  }

  device() {
    return deviceOf(this.last ?? { targetRayMode: 'transient-pointer' }, 'transient-pointer');
  }

  refuses() {
    return null;
  }
}
