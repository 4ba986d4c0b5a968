// The ground of the world shown, from the module's `ground()` planes: grass and the terrace in
// the study scene, textured with grove's ground tile (assets/env/ground.png, a 2.5 m repeat, as
// src/render/ground/mod.rs lays it) and shaded as grove shades it (shading.mjs); in AR a
// shadow-only material, so that the trees' shadows fall onto the real floor and nothing else of
// the ground is seen. A feature of the view (view/features.mjs); hidden where the view draws
// the trees alone (`view.background` false: web/page/still.mjs's transparent pictures).

import * as THREE from 'three';
import { groveShading } from './shading.mjs';

/** Metres per repeat of the ground's texture (grove's ground tile, src/render/ground/mod.rs). */
const GROUND_REPEAT = 2.5;

export class Ground {
  /** `view`: the view (its simulation's frame, its environment's ground texture). */
  constructor(view) {
    this.view = view;
    this.shown = null;
    this.box = new THREE.Box3(); // the planes' box in the simulation's frame
    this.root = new THREE.Group();
    this.root.name = 'ground';
    view.simRoot.add(this.root);
  }

  /** Rebuilt when the world changes ({ ar, ground }: flow/task.mjs's worldOf); nothing else moves it. */
  update(s) {
    this.root.visible = this.view.background;
    if (s.world === this.shown) return;
    this.shown = s.world;
    this.root.clear();
    this.box.makeEmpty();
    const texture = this.view.env?.ground ?? null;
    for (const p of s.world?.ground ?? []) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(p.vertices, 3));
      g.setIndex(p.triangles);
      g.computeVertexNormals();
      const v = p.vertices;
      const uv = new Float32Array((v.length / 3) * 2);
      for (let i = 0; i < v.length / 3; i++) {
        uv[2 * i] = v[3 * i] / GROUND_REPEAT;
        uv[2 * i + 1] = v[3 * i + 2] / GROUND_REPEAT;
      }
      g.setAttribute('uv', new THREE.Float32BufferAttribute(uv, 2));
      g.computeBoundingBox();
      this.box.union(g.boundingBox);
      const colour = texture ? 0xffffff : p.name === 'terrace' ? 0x8d7f62 : 0x6f8f4e;
      const material = s.world.ar
        ? new THREE.ShadowMaterial({ opacity: 0.45 })
        : groveShading(new THREE.MeshStandardMaterial({ map: texture, color: colour, roughness: 0.95 }), { specular: 0 });
      const mesh = new THREE.Mesh(g, material);
      mesh.name = `plane:${p.name}`;
      mesh.receiveShadow = true;
      this.root.add(mesh);
    }
  }
}
