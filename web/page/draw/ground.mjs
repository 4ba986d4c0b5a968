// The ground of the world shown, from the module's `ground()` planes: grass and the terrace in
// the study scene; in AR a shadow-only material, so that the trees' shadows fall onto the real
// floor and nothing else of the ground is seen. A feature of the view (view/features.mjs).

import * as THREE from 'three';

export class Ground {
  /** `parent`: the simulation's frame. */
  constructor(parent) {
    this.shown = null;
    this.root = new THREE.Group();
    this.root.name = 'ground';
    parent.add(this.root);
  }

  /** Rebuilt when the world changes ({ ar, ground }: flow/task.mjs's worldOf); nothing else moves it. */
  update(s) {
    if (s.world === this.shown) return;
    this.shown = s.world;
    this.root.clear();
    for (const p of s.world?.ground ?? []) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(p.vertices, 3));
      g.setIndex(p.triangles);
      g.computeVertexNormals();
      const material = s.world.ar
        ? new THREE.ShadowMaterial({ opacity: 0.45 })
        : new THREE.MeshStandardMaterial({ color: p.name === 'terrace' ? 0x8d7f62 : 0x6f8f4e, roughness: 0.95 });
      const mesh = new THREE.Mesh(g, material);
      mesh.name = `plane:${p.name}`;
      mesh.receiveShadow = true;
      this.root.add(mesh);
    }
  }
}
