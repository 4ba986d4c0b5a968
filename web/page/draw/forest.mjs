// The trees drawn: one THREE.InstancedMesh per model, level of detail and primitive (bark,
// leaves), so that a model in view costs the same draw calls whatever its count (docs/headset.md,
// "What a headset holds"). A feature of the view (view/features.mjs), after the trees' places
// (world.mjs: a light proxy Object3D per tree, no mesh) and their leaves' level of detail
// (leaves.mjs): every frame each tree's matrix and its wind's values (wind.mjs's TreeWind, packed
// as instanced attributes) are written into the instances of the levels it is drawn as
// (levels.mjs: its model, its far model, or both sharing its pixels).

import * as THREE from 'three';
import { farShare, levels } from './levels.mjs';
import { keeps } from './leaves.mjs';
import { TREE_ATTRIBUTES } from './wind.mjs';

/** Every instance of one primitive of a model: an InstancedMesh grown as needed. */
class Batch {
  constructor(part, root, name) {
    Object.assign(this, { part, root, name, mesh: null, capacity: 0 });
  }

  #grow(n) {
    const capacity = Math.max(8, 2 ** Math.ceil(Math.log2(n)));
    const { geometry: g, material, depth } = this.part;
    // The model's own buffers, shared, with this mesh's instanced attributes beside them.
    const geometry = new THREE.BufferGeometry();
    geometry.setIndex(g.index);
    for (const [k, a] of Object.entries(g.attributes)) geometry.setAttribute(k, a);
    if (!g.boundingSphere) g.computeBoundingSphere();
    geometry.boundingSphere = g.boundingSphere;
    for (const a of TREE_ATTRIBUTES)
      geometry.setAttribute(
        a,
        new THREE.InstancedBufferAttribute(new Float32Array(capacity * 4), 4).setUsage(THREE.DynamicDrawUsage),
      );
    const mesh = new THREE.InstancedMesh(geometry, material, capacity);
    mesh.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
    Object.assign(mesh, { name: this.name, castShadow: true, receiveShadow: true });
    if (depth) mesh.customDepthMaterial = depth;
    if (this.mesh) this.root.remove(this.mesh);
    this.root.add(mesh);
    Object.assign(this, { mesh, capacity });
  }

  /** Draws `trees` ([{ object, wind, share, keep }]) and no other. */
  set(trees) {
    if (trees.length > this.capacity) this.#grow(trees.length);
    if (!this.mesh) return;
    const { mesh } = this;
    const [place, sway, level] = TREE_ATTRIBUTES.map((a) => mesh.geometry.attributes[a]);
    const packed = new Float32Array(12);
    trees.forEach(({ object, wind, share, keep }, i) => {
      mesh.instanceMatrix.array.set(object.matrix.elements, 16 * i);
      wind.pack(packed, 0, share, keep);
      place.array.set(packed.subarray(0, 4), 4 * i);
      sway.array.set(packed.subarray(4, 8), 4 * i);
      level.array.set(packed.subarray(8, 12), 4 * i);
    });
    mesh.count = trees.length;
    mesh.visible = trees.length > 0;
    for (const a of [mesh.instanceMatrix, place, sway, level]) {
      a.clearUpdateRanges();
      a.addUpdateRange(0, trees.length * a.itemSize);
      a.needsUpdate = true;
    }
    if (trees.length) mesh.computeBoundingSphere();
  }
}

/** The trees drawn instanced (a feature of the view: view/features.mjs). */
export class Forest {
  constructor(view) {
    this.view = view;
    this.root = new THREE.Group();
    this.root.name = 'forest';
    view.simRoot.add(this.root);
    this.batches = new Map(); // `${model}|${primitive}` -> Batch ('' for the stand-in)
  }

  update(s) {
    const { view } = this;
    const world = view.features.world;
    this.root.visible = world.root.visible;
    const snap = s.snap ?? s.world?.snapshot;
    const eye = snap?.head ? new THREE.Vector3().fromArray(snap.head.position) : null;
    const { models, pixelsPerRadian } = view;
    if (models !== this.models) {
      // Another catalogue (a still picture's model): its own meshes.
      for (const b of this.batches.values()) if (b.mesh) this.root.remove(b.mesh);
      this.batches.clear();
      this.models = models;
    }
    const texelsPerMetre = view.features.light.texelsPerMetre;
    // model -> the trees drawn as it: [{ object, wind, share, keep }]
    const drawn = new Map();
    const add = (model, entry) => (drawn.get(model) ?? drawn.set(model, []).get(model)).push(entry);
    for (const { object, model } of this.root.visible ? world.trees.values() : []) {
      object.updateMatrix();
      const wind = object.userData.wind;
      const name = models?.models.has(model) ? model : '';
      const far = name && models.far.get(name);
      const distance = eye ? eye.distanceTo(object.position) : 0;
      const share =
        far && models.models.has(far) && eye
          ? farShare(models.boxes.get(name), object.scale.x, distance, pixelsPerRadian)
          : null;
      for (const level of levels(share)) {
        // The far model's leaves have their own level of detail (leaves.mjs).
        const area = level.far ? models.models.get(far).userData.leafArea * object.scale.x ** 2 : null;
        const keep = level.far ? keeps(area, eye ? distance : null, pixelsPerRadian, texelsPerMetre) : null;
        add(level.far ? far : name, { object, wind, share: level.share, keep, bark: level.bark });
      }
    }
    const seen = new Set();
    for (const [model, trees] of drawn) {
      const parts = models?.primitives(model || null) ?? [];
      parts.forEach((part, k) => {
        const key = `${model}|${k}`;
        seen.add(key);
        if (!this.batches.has(key))
          this.batches.set(key, new Batch(part, this.root, `trees:${model || 'stand-in'}:${k}`));
        this.batches.get(key).set(part.leaf ? trees : trees.filter((t) => t.bark).map((t) => ({ ...t, share: 0 })));
      });
    }
    for (const [key, batch] of this.batches) if (!seen.has(key)) batch.set([]);
  }
}
