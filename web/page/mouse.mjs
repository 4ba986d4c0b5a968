// The inline preview's input: the mouse as the controller, as `grove play` has it
// (docs/desktop.md). The ray leaves the head through the pointer; the left button is Trigger,
// the right button Bumper, the middle button or M is Menu; the wheel moves the selected tree
// along the ray (Touchpad front and back), Q and E turn it (Touchpad left and right).

import { lookRotation } from './input.mjs';

export class MouseInput {
  constructor(canvas) {
    this.canvas = canvas;
    this.ndc = [0, 0];
    this.buttons = { trigger: false, bumper: false, touchpad: false, menu: false };
    this.axes = [0, 0];
    this.wheelUntil = 0;
    const down = (e, v) => {
      if (e.button === 0) this.buttons.trigger = v;
      if (e.button === 2) this.buttons.bumper = v;
      if (e.button === 1) this.buttons.menu = v;
    };
    canvas.addEventListener('pointermove', (e) => this.#move(e));
    canvas.addEventListener('pointerdown', (e) => {
      this.#move(e);
      down(e, true);
      canvas.setPointerCapture?.(e.pointerId);
    });
    canvas.addEventListener('pointerup', (e) => down(e, false));
    canvas.addEventListener('contextmenu', (e) => e.preventDefault());
    canvas.addEventListener('wheel', (e) => {
      e.preventDefault();
      this.axes = [0, e.deltaY < 0 ? 0.5 : -0.5];
      this.wheelUntil = performance.now() + 150;
    }, { passive: false });
    window.addEventListener('keydown', (e) => {
      if (e.key === 'm' || e.key === 'M') this.buttons.menu = true;
      if (e.key === 'q' || e.key === 'Q') this.axes = [-0.5, 0];
      if (e.key === 'e' || e.key === 'E') this.axes = [0.5, 0];
    });
    window.addEventListener('keyup', (e) => {
      if (e.key === 'm' || e.key === 'M') this.buttons.menu = false;
      if ('qQeE'.includes(e.key)) this.axes = [0, 0];
    });
  }

  #move(e) {
    const r = this.canvas.getBoundingClientRect();
    this.ndc = [((e.clientX - r.left) / r.width) * 2 - 1, -(((e.clientY - r.top) / r.height) * 2 - 1)];
  }

  /** The touchpad's axes now. */
  touchpad() {
    if (this.wheelUntil && performance.now() > this.wheelUntil) {
      this.wheelUntil = 0;
      this.axes = [0, 0];
    }
    return this.axes;
  }

  /**
   * The controller's pose: at the camera (a three.js camera placed at the head), its ray through
   * the pointer. Plain numbers; the caller rounds them to f32.
   */
  pose(camera, THREE) {
    const v = new THREE.Vector3(this.ndc[0], this.ndc[1], 0.5).unproject(camera);
    const o = camera.position;
    const d = v.sub(o).normalize();
    const q = lookRotation([d.x, d.y, d.z]);
    return { position: { x: o.x, y: o.y, z: o.z }, orientation: { x: q[0], y: q[1], z: q[2], w: q[3] } };
  }
}
