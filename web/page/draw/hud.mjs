// The task panel that follows the controller: the task, its clock and targets, what to do next,
// the controls of this controller (with Bumper's alternative where it has no squeeze), and the
// connection's state; before the task, what to press to start it. Shown in an immersive session
// only. A feature of the view (view/features.mjs).

import * as THREE from 'three';
import { Label } from './label.mjs';

export class Hud {
  constructor(scene) {
    this.label = new Label(0.36, 0.2, { px: 900 });
    this.label.mesh.name = 'hud';
    this.label.mesh.visible = false;
    scene.add(this.label.mesh);
  }

  /**
   * `s.hud`: { lines, at, eye } (flow/frame.mjs), or null to hide the panel; `lines` null keeps
   * the text, `at` (a pose) null keeps the place.
   */
  update(s) {
    this.label.mesh.visible = Boolean(s.hud);
    if (s.hud?.at) this.place(s.hud.at, s.hud.eye);
    if (s.hud?.lines) this.set(s.hud.lines);
  }

  /** Places the panel above the controller (pose arrays), facing the eye; both in its parent's frame. */
  place(controller, eye) {
    const [x, y, z] = controller.position;
    const m = this.label.mesh;
    m.position.set(x, y + 0.16, z);
    if (eye) m.lookAt(m.parent.localToWorld(new THREE.Vector3(eye.x, eye.y, eye.z)));
  }

  set(lines) {
    this.label.set(lines);
  }
}
