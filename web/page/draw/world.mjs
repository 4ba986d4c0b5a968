// The trees of the world shown, from the simulation's snapshot: a light proxy per tree (an
// Object3D named `tree:ID`, no mesh: its place, its TreeWind's values and its leaves' area),
// which forest.mjs draws as the catalogue's models (trees.mjs: loaded once each, one
// InstancedMesh per model and primitive, shaded as grove shades them and swaying in the wind with
// their shadows). A feature of the view (view/features.mjs); the
// ground is ground.mjs's, the sun and the environment light.mjs's, the sky sky.mjs's, the wind's
// state wind.mjs's and the leaves' level of detail leaves.mjs's.
//
// Everything is in the simulation's frame (metres, +Y up); the page's XR reference space is
// offset so that the headset's poses are in that frame too (room.mjs).

import * as THREE from 'three';
import { STAND_IN_BOX } from './trees.mjs';
import { TreeWind } from './wind.mjs';

export { Models } from './trees.mjs';

/** The trees of the world shown (a feature of the view: view/features.mjs). */
export class World {
  /** `view`: the view (its simulation's frame, and its `models`: trees.mjs's Models). */
  constructor(view) {
    this.view = view;
    this.shown = null; // the world record drawn (flow/task.mjs's worldOf), or null
    this.trees = new Map(); // id -> { object: the tree's proxy, model }
    this.root = new THREE.Group();
    this.root.name = 'world';
    this.root.visible = false;
    view.simRoot.add(this.root);
  }

  /** A new world ({ ar, snapshot }) starts with its own trees; a run's snapshot moves them. */
  update(s) {
    if (s.world !== this.shown) this.#show(s.world);
    if (this.shown && s.snap) this.#trees(s.snap);
  }

  #show(world) {
    this.shown = world;
    for (const entry of this.trees.values()) this.root.remove(entry.object);
    this.trees.clear();
    this.root.visible = Boolean(world);
    if (world?.snapshot) this.#trees(world.snapshot);
  }

  /** Brings the trees to the snapshot: where they stand, and their state in the wind. */
  #trees(snap) {
    const seen = new Set();
    for (const t of snap.trees) {
      seen.add(t.id);
      let entry = this.trees.get(t.id);
      if (!entry) {
        entry = { object: new THREE.Object3D(), model: t.model };
        entry.object.name = `tree:${t.id}`;
        entry.object.userData.wind = new TreeWind();
        this.root.add(entry.object);
        this.trees.set(t.id, entry);
      }
      entry.model = t.model;
      const o = entry.object;
      o.position.set(t.position[0], t.position[1], t.position[2]);
      o.quaternion.set(t.rotation[0], t.rotation[1], t.rotation[2], t.rotation[3]);
      o.scale.setScalar(t.scale);
      o.updateMatrix();
      o.userData.leafArea = this.view.models?.models.get(t.model)?.userData.leafArea ?? 0;
      o.userData.wind.set(t);
    }
    for (const [id, entry] of this.trees) {
      if (!seen.has(id)) {
        this.root.remove(entry.object);
        this.trees.delete(id);
      }
    }
  }

  /** The trees' box in the simulation's frame (empty when none is shown). */
  box() {
    const box = new THREE.Box3();
    if (!this.root.visible) return box;
    // The root stands at the simulation's origin: a proxy's matrix is in the simulation's frame.
    for (const { object, model } of this.trees.values())
      box.union((this.view.models?.bounds(model) ?? STAND_IN_BOX.clone()).applyMatrix4(object.matrix));
    return box;
  }
}
