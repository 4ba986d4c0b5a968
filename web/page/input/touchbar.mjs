// A phone's buttons for what a screen tap cannot say (docs/headset.md, "Devices and their
// mappings"): Remove (Bumper, on the tree last tapped), Menu, a Move pad (a thumb dragged on it
// is the touchpad: up and down move the selected tree along the ray, left and right turn it) and a
// Scale pad (a thumb dragged up grows the selected tree, down shrinks it: grove's scale_axis). They
// are HTML in the page's DOM overlay over the camera's view. A tap on them never reaches the
// scene: their `beforexrselect` is cancelled (the browser then fires no select for it), and the
// screen input source the same touch makes is claimed by the bar (`claims()`) and ignored by the
// screen's source (input/screen.mjs).

import { touchpadAxes } from './buttons.mjs';

/** How long after a touch on the bar ends a new screen source is still the bar's, ms. */
export const CLAIM_MS = 150;

/** The pad's radius in CSS pixels: a thumb this far from where it landed is full deflection. */
const PAD_PX = 48;

export class TouchBar {
  /** `root`: the bar's element (inside the DOM overlay); `now()`: ms. */
  constructor(root, now = () => performance.now()) {
    this.root = root;
    this.now = now;
    this.held = { bumper: false, menu: false };
    this.axes = [0, 0];
    this.scale = 0; // the Scale pad's value in [-1, 1]
    this.down = 0; // touches on the bar now
    this.upAt = -Infinity;
    root.replaceChildren();
    root.addEventListener('beforexrselect', (e) => e.preventDefault());
    for (const [id, label, button] of [
      ['touch-remove', 'Remove', 'bumper'],
      ['touch-menu', 'Menu', 'menu'],
    ]) {
      const b = root.ownerDocument.createElement('button');
      b.id = id;
      b.type = 'button';
      b.textContent = label;
      this.#track(b, (on) => (this.held[button] = on));
      root.append(b);
    }
    this.#pad('touch-move', 'Move', (dx, dy) => (this.axes = touchpadAxes({ axes: [0, 0, dx, dy] })));
    // Up (towards the top of the screen) grows: the value is minus the thumb's downward travel.
    this.#pad('touch-scale', 'Scale', (dx, dy) => (this.scale = Math.max(-1, Math.min(1, -dy)) || 0));
  }

  /** A pad: `set(dx, dy)` with the thumb's travel from where it landed, in pad radii; (0, 0) on release. */
  #pad(id, label, set) {
    const pad = this.root.ownerDocument.createElement('div');
    pad.id = id;
    pad.textContent = label;
    let from = null;
    this.#track(pad, (on, e) => {
      from = on ? [e.clientX, e.clientY] : null;
      if (!on) set(0, 0);
    });
    pad.addEventListener('pointermove', (e) => {
      if (from) set((e.clientX - from[0]) / PAD_PX, (e.clientY - from[1]) / PAD_PX);
    });
    this.root.append(pad);
  }

  /** Calls `set(on, event)` as a pointer goes down on `el` and up (or is cancelled). */
  #track(el, set) {
    el.addEventListener('pointerdown', (e) => {
      e.preventDefault();
      el.setPointerCapture?.(e.pointerId);
      this.down++;
      set(true, e);
    });
    const up = (e) => {
      this.down = Math.max(0, this.down - 1);
      this.upAt = this.now();
      set(false, e);
    };
    el.addEventListener('pointerup', up);
    el.addEventListener('pointercancel', up);
  }

  /** Shows or hides the bar. */
  show(on) {
    this.root.hidden = !on;
  }

  /** Whether a screen touch that begins now is the bar's: a touch on it is down, or just ended. */
  claims() {
    return this.down > 0 || this.now() - this.upAt < CLAIM_MS;
  }

  /** The bar's buttons, the Move pad's axes and the Scale pad's value now. */
  read() {
    return { bumper: this.held.bumper, menu: this.held.menu, axes: this.axes, scale: this.scale };
  }
}
