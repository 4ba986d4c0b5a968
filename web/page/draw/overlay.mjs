// What the simulation shows beyond the world: the controller's ray and its hit marker, the
// anchor ball under a dragged tree (green while a release would not snap, white when it would),
// the selected tree's bounding box and its 12 handles, and the task's targets (each on the
// plane it lies on: `moved_to` where the room has no plane at its height), all from the snapshot
// of the run shown. A feature of the view (view/features.mjs).

import * as THREE from 'three';
import { Label } from './label.mjs';

const GREEN = 0x3fd16b;
const WHITE = 0xffffff;

export class Overlay {
  constructor(scene) {
    this.root = new THREE.Group();
    this.root.name = 'overlay';
    scene.add(this.root);
    const rayGeometry = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3(0, 0, -1)]);
    this.ray = new THREE.Line(rayGeometry, new THREE.LineBasicMaterial({ color: 0xa8e8ff }));
    this.ray.frustumCulled = false;
    this.root.add(this.ray);
    this.marker = new THREE.Mesh(new THREE.RingGeometry(0.06, 0.1, 24), new THREE.MeshBasicMaterial({ color: 0xa8e8ff, side: THREE.DoubleSide, depthTest: false }));
    this.marker.renderOrder = 5;
    this.root.add(this.marker);
    this.ball = new THREE.Mesh(new THREE.SphereGeometry(0.12, 16, 12), new THREE.MeshStandardMaterial({ color: GREEN, emissive: 0x202020 }));
    this.ball.name = 'anchor-ball';
    this.root.add(this.ball);
    this.box = new THREE.LineSegments(new THREE.EdgesGeometry(new THREE.BoxGeometry(2, 2, 2)), new THREE.LineBasicMaterial({ color: 0xffd24a }));
    this.root.add(this.box);
    this.handles = [];
    const handleMaterial = new THREE.MeshBasicMaterial({ color: 0xffd24a });
    const hot = new THREE.MeshBasicMaterial({ color: 0xff6a3a });
    this.handleMaterials = [handleMaterial, hot];
    for (let i = 0; i < 12; i++) {
      const h = new THREE.Mesh(i < 8 ? new THREE.SphereGeometry(0.12, 10, 8) : new THREE.BoxGeometry(0.2, 0.2, 0.2), handleMaterial);
      this.handles.push(h);
      this.root.add(h);
    }
    this.targets = [];
    this.targetGroup = new THREE.Group();
    this.root.add(this.targetGroup);
    this.targetKey = '';
    this._v = new THREE.Vector3();
    this._q = new THREE.Quaternion();
    this._up = new THREE.Vector3(0, 0, 1);
  }

  /** The anchor ball as drawn: 'hidden', 'white' or 'green'. */
  ballState() {
    if (!this.ball.visible) return 'hidden';
    return this.ball.material.color.getHex() === WHITE ? 'white' : 'green';
  }

  /** Shown with a run's snapshot (`s.live`), its labels turned to `s.eye`; hidden on a step's panel. */
  update(s) {
    this.root.visible = Boolean(s.live);
    if (s.live) this.#draw(s.live, s.eye);
  }

  #draw(snap, eye) {
    const c = snap.controller;
    // A task laid out in a room is a scale model: its markers, ball and handles at its scale.
    const k = snap.task?.layout_scale ?? 1;
    for (const m of [this.marker, this.ball, ...this.handles]) m.scale.setScalar(k);
    const o = c.ray_origin;
    const d = c.ray_direction;
    const length = c.hit ? c.hit.distance : 30;
    const pos = this.ray.geometry.attributes.position;
    pos.setXYZ(0, o[0], o[1], o[2]);
    pos.setXYZ(1, o[0] + d[0] * length, o[1] + d[1] * length, o[2] + d[2] * length);
    pos.needsUpdate = true;
    this.marker.visible = Boolean(c.hit);
    if (c.hit) {
      const h = c.hit;
      this.marker.position.set(h.position[0], h.position[1] + 0.01, h.position[2]);
      this.marker.quaternion.setFromUnitVectors(this._up, this._v.set(h.normal[0], h.normal[1], h.normal[2]));
    }
    const ball = snap.anchor_ball;
    this.ball.visible = ball.state !== 'hidden';
    if (this.ball.visible) {
      this.ball.position.set(ball.position[0], ball.position[1] + 0.12 * k, ball.position[2]);
      this.ball.material.color.setHex(ball.state === 'white' ? WHITE : GREEN);
    }
    const b = snap.bounding_box;
    this.box.visible = Boolean(b);
    const hotHandle = c.hit?.kind === 'handle' ? c.hit.handle : null;
    this.handles.forEach((h, i) => (h.visible = Boolean(b)));
    if (b) {
      this.box.position.set(b.center[0], b.center[1], b.center[2]);
      this.box.rotation.set(0, b.yaw, 0);
      this.box.scale.set(b.half_extents[0], b.half_extents[1], b.half_extents[2]);
      // The snapshot's handles: the 8 corners, then the 4 edges (systems/src/interact.rs).
      b.handles.forEach((p, i) => {
        const h = this.handles[i];
        h.position.set(p.position[0], p.position[1], p.position[2]);
        h.material = hotHandle && hotHandle[0] === p.kind && hotHandle[1] === p.index ? this.handleMaterials[1] : this.handleMaterials[0];
      });
    }
    this.#targets(snap.task, eye, k);
  }

  #targets(task, eye, k) {
    const targets = task?.targets ?? [];
    const key = targets.map((t) => `${t.model}@${(t.moved_to ?? t.position).join(',')}`).join(';');
    if (key !== this.targetKey) {
      this.targetKey = key;
      this.targetGroup.clear();
      this.targets = targets.map((t) => {
        const at = t.moved_to ?? t.position;
        const g = new THREE.Group();
        g.position.set(at[0], at[1], at[2]);
        g.scale.setScalar(k);
        const ring = new THREE.Mesh(new THREE.RingGeometry(0.38, 0.5, 32), new THREE.MeshBasicMaterial({ color: 0xff9f3a, side: THREE.DoubleSide }));
        ring.rotation.x = -Math.PI / 2;
        ring.position.y = 0.02;
        const post = new THREE.Mesh(new THREE.CylinderGeometry(0.03, 0.03, 1.2, 8), ring.material);
        post.position.y = 0.6;
        const label = new Label(1.6, 0.3, { px: 160 });
        label.set([t.moved_to ? `${t.model} (moved)` : t.model]);
        label.mesh.position.y = 1.45;
        g.add(ring, post, label.mesh);
        this.targetGroup.add(g);
        return { group: g, ring, label };
      });
    }
    targets.forEach((t, i) => {
      const v = this.targets[i];
      v.ring.material.color.setHex(t.satisfied ? GREEN : 0xff9f3a);
      if (eye) v.label.mesh.lookAt(this.root.parent.localToWorld(this._v.set(eye.x, v.group.position.y + 1.45 * k, eye.z)));
    });
  }
}
