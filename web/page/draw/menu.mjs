// The model menu in the 3D scene: a panel of the catalogue's models that opens in front of the
// head when the simulation's menu opens; the controller's ray picks an item and the trigger
// chooses it (the run then sends `choose_model`, run.mjs; the pick is flow/task.mjs's). A feature
// of the view (view/features.mjs).

import * as THREE from 'three';
import { Label } from './label.mjs';
import { horizontalForward } from './panel.mjs';

const ROW = 0.09; // metres per item
const WIDTH = 0.7;

export class Menu {
  constructor(scene) {
    this.scene = scene;
    this.models = [];
    this.label = null;
    this.group = new THREE.Group();
    this.group.name = 'menu';
    this.group.visible = false;
    scene.add(this.group);
    this.hover = -1;
    this.current = '';
    this._plane = new THREE.Plane();
    this._n = new THREE.Vector3();
    this._p = new THREE.Vector3();
    this._local = new THREE.Vector3();
  }

  #build(models) {
    this.models = models;
    if (this.label) this.group.remove(this.label.mesh);
    this.label = new Label(WIDTH, ROW * (models.length + 1), { px: 512 });
    this.group.add(this.label.mesh);
  }

  /**
   * Opens the panel 1 m in front of `head` ({ position: [x, y, z], rotation: [x, y, z, w] }),
   * level, facing it.
   */
  open(models, head) {
    if (models.join() !== this.models.join()) this.#build(models);
    const [x, y, z] = head.position;
    const f = horizontalForward(head.rotation);
    this.group.position.set(x + f.x, y - 0.15, z + f.z);
    this.group.lookAt(this.group.parent.localToWorld(new THREE.Vector3(x, y - 0.15, z)));
    this.group.visible = true;
    this.group.updateMatrixWorld(true);
  }

  close() {
    this.group.visible = false;
    this.hover = -1;
  }

  get isOpen() {
    return this.group.visible;
  }

  /** The item the ray from `origin` along `dir` (arrays) points at, or -1. */
  itemAt(origin, dir) {
    if (!this.group.visible || !this.label) return -1;
    // In the parent's frame (the simulation's), where the ray is.
    this.group.updateMatrix();
    this._n.set(0, 0, 1).transformDirection(this.group.matrix);
    this._plane.setFromNormalAndCoplanarPoint(this._n, this.group.position);
    const o = new THREE.Vector3(...origin);
    const d = new THREE.Vector3(...dir);
    const denom = this._plane.normal.dot(d);
    if (Math.abs(denom) < 1e-6) return -1;
    const t = -(this._plane.normal.dot(o) + this._plane.constant) / denom;
    if (t < 0) return -1;
    this._p.copy(o).addScaledVector(d, t);
    this._local.copy(this._p).applyMatrix4(new THREE.Matrix4().copy(this.group.matrix).invert());
    const h = ROW * (this.models.length + 1);
    if (Math.abs(this._local.x) > WIDTH / 2 || Math.abs(this._local.y) > h / 2) return -1;
    const row = Math.floor((h / 2 - this._local.y) / ROW) - 1; // the first row is the title
    return row >= 0 && row < this.models.length ? row : -1;
  }

  /** The middle of item `i` in the simulation's frame (for tests aiming at it), [x, y, z]. */
  itemPoint(i) {
    this.group.updateMatrix();
    const h = ROW * (this.models.length + 1);
    const p = new THREE.Vector3(0, h / 2 - ROW * (i + 1.5), 0).applyMatrix4(this.group.matrix);
    return [p.x, p.y, p.z];
  }

  /** Open while the run's snapshot (`s.live`) has its menu open: the item under `s.ray` highlighted. */
  update(s) {
    const snap = s.live;
    if (snap?.menu.open && !this.isOpen) this.open([...snap.menu.models, 'Finish task'], snap.head);
    if (!snap?.menu.open && this.isOpen) this.close();
    if (this.isOpen) this.#items(s.ray ? this.itemAt(s.ray[0], s.ray[1]) : -1, snap.menu.current_model, 'Choose a model (trigger)');
  }

  /** Redraws the items: the one under the ray highlighted, the current model marked. */
  #items(hover, current, hint) {
    if (!this.label) return;
    this.hover = hover;
    this.label.set([hint, ...this.models.map((m, i) => `${i === hover ? '!' : ''}${m === current ? '• ' : '   '}${m}`)]);
  }
}
