// The inline preview's input: the mouse as the controller, as `grove play` has it
// (docs/desktop.md). The ray leaves the head (the view's camera, placed where the simulation's
// head is) through the pointer; the left button is Trigger, the right button Bumper, the middle
// button or M is Menu; the wheel moves the selected tree along the ray (Touchpad front and
// back), Q and E turn it (Touchpad left and right). The same shape as the XR sources
// (input/xr.mjs), with no head of its own: the simulation's head stays where it is.

import * as THREE from 'three';
import { lookRotation } from './pose.mjs';

export class MouseInput {
  /** `canvas`: the preview's; `camera`: the three.js camera the preview is drawn from. */
  constructor(canvas, camera) {
    this.canvas = canvas;
    this.camera = camera;
    this.noSqueeze = false;
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
   * The controller's pose: at the camera, its ray through the pointer (input/pose.mjs's shape;
   * plain numbers, which the run rounds to f32).
   */
  pose() {
    const camera = this.camera;
    const v = new THREE.Vector3(this.ndc[0], this.ndc[1], 0.5).unproject(camera);
    const o = camera.position;
    const d = v.sub(o).normalize();
    return { position: [o.x, o.y, o.z], rotation: lookRotation([d.x, d.y, d.z]) };
  }

  /** This frame's { head: null, pose, buttons, axes } (the XR frame, if any, is not the mouse's). */
  poll() {
    return { head: null, pose: this.pose(), buttons: { ...this.buttons }, axes: this.touchpad() };
  }

  /** What the recording's header says of this device. */
  device() {
    return { profile: 'mouse', target_ray_mode: 'none', mapping: 'mouse' };
  }

  /** Why a task's mode cannot be done with the mouse, or null: it does both. */
  refuses() {
    return null;
  }

  /** The rows [control, what it does] for a task's mode ('ray-casting' or 'manual'). */
  controls(mode) {
    return [
      ['Left button', mode === 'manual' ? 'grab and drag a tree or a handle' : 'plant on the ground, select a tree; choose in the menu'],
      ['Right button', 'remove the tree under the ray'],
      ['M or middle button', 'open the model menu'],
      ['Wheel, Q / E', 'move the selected tree along the ray, turn it'],
    ];
  }
}
