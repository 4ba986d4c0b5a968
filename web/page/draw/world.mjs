// The world as three.js draws it from the simulation's snapshot: the ground planes, the trees
// (trees.mjs: the catalogue's models, swaying in the wind), the sky (sky.mjs) and the light
// (light.mjs: the sun, its shadows fitted around the ground and the trees, the environment), as
// grove's renderer draws them. In AR the ground is drawn with a shadow-only material, so the
// trees' shadows fall onto the real floor and nothing else of the ground is seen.
//
// Everything is in the simulation's frame (metres, +Y up); the page's XR reference space is
// offset so that the headset's poses are in that frame too (room.mjs).

import * as THREE from 'three';
import { LEAF_PIXELS, SHADOW_LEAF_TEXELS, keepFraction } from './leaves.mjs';
import { Light } from './light.mjs';
import { groveShading } from './shading.mjs';
import { Sky, updateSky } from './sky.mjs';
import { setWind } from './wind.mjs';

export { Models } from './trees.mjs';

/** Pixels per radian of a headset's eye (Quest 3: 1832 pixels over about 96° of height). */
const EYE_PIXELS_PER_RADIAN = 825;

/** Metres per repeat of the ground's texture (grove's ground tile, src/render/ground/mod.rs). */
const GROUND_REPEAT = 2.5;

/** The ground, trees and light of one scene. */
export class WorldView {
  /**
   * `ar`: draw the ground as a shadow catcher over the real room. `sky`: the sky's cube texture
   * (sky.mjs), drawn behind the world outside AR. `groundTexture`: the ground's texture (else a
   * plain colour). `environment`: the environment light (renderer.mjs `environmentFor`).
   * `background: false` draws the trees alone (no sky, no ground), lit and shadowed as with
   * them. `pixelsPerRadian` (the view's height over its field of view, half over the tangent of
   * half) and `leafPixels` set the leaves' level of detail (leaves.mjs).
   */
  constructor(scene, models, { ar = false, shadows = true, sky = null, groundTexture = null, environment = null, background = true, pixelsPerRadian = EYE_PIXELS_PER_RADIAN, leafPixels = LEAF_PIXELS } = {}) {
    this.detail = { pixelsPerRadian, leafPixels };
    this.scene = scene;
    this.models = models;
    this.ar = ar;
    this.background = background;
    this.groundTexture = groundTexture;
    this.trees = new Map(); // id -> { object, model }
    this.root = new THREE.Group();
    this.root.name = 'world';
    scene.add(this.root);
    this.light = new Light(this.root, { shadows });
    this.light.setEnvironment(environment);
    this.cube = ar ? null : sky;
    this.sky = sky && !ar && background ? new Sky(sky) : null;
    if (this.sky) this.root.add(this.sky.mesh);
    this.ground = new THREE.Group();
    this.ground.visible = background;
    this.groundBox = new THREE.Box3();
    this.root.add(this.ground);
  }

  /** The ground planes, from the module's `ground()`. */
  setGround(planes) {
    this.ground.clear();
    for (const p of planes) {
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
      this.groundBox.union(g.boundingBox);
      const material = this.ar
        ? new THREE.ShadowMaterial({ opacity: 0.45 })
        : groveShading(new THREE.MeshStandardMaterial({ map: this.groundTexture, color: this.groundTexture ? 0xffffff : p.name === 'terrace' ? 0x8d7f62 : 0x6f8f4e, roughness: 0.95 }), { specular: 0 });
      const mesh = new THREE.Mesh(g, material);
      mesh.name = `plane:${p.name}`;
      mesh.receiveShadow = true;
      this.ground.add(mesh);
    }
  }

  /** Brings trees and the sun to the snapshot. */
  update(snap) {
    const seen = new Set();
    for (const t of snap.trees) {
      seen.add(t.id);
      let entry = this.trees.get(t.id);
      if (!entry || entry.model !== t.model) {
        if (entry) this.root.remove(entry.object);
        entry = { object: this.models.instance(t.model), model: t.model };
        entry.object.name = `tree:${t.id}`;
        this.root.add(entry.object);
        this.trees.set(t.id, entry);
      }
      const o = entry.object;
      o.position.set(t.position[0], t.position[1], t.position[2]);
      o.quaternion.set(t.rotation[0], t.rotation[1], t.rotation[2], t.rotation[3]);
      o.scale.setScalar(t.scale);
      o.userData.wind?.set(t);
    }
    for (const [id, entry] of this.trees) {
      if (!seen.has(id)) {
        this.root.remove(entry.object);
        this.trees.delete(id);
      }
    }
    setWind(snap.wind);
    this.light.update(snap.light);
    updateSky(snap.light, this.cube, this.root);
    // The sun's view covers the ground and the trees, cut to 80 m around the head (as
    // src/render/lighting.rs's shadow_bounds cuts it).
    const box = new THREE.Box3();
    for (const { object } of this.trees.values()) box.union(new THREE.Box3().setFromObject(object));
    this.root.updateWorldMatrix(true, false);
    box.applyMatrix4(this.root.matrixWorld.clone().invert()).union(this.groundBox);
    if (snap.head) {
      const h = new THREE.Vector3().fromArray(snap.head.position);
      box.intersect(new THREE.Box3(h.clone().subScalar(80).setY(-1000), h.clone().addScalar(80).setY(1000)));
    }
    const texelsPerMetre = this.light.fitShadow(box);
    const eye = snap.head ? new THREE.Vector3().fromArray(snap.head.position) : null;
    for (const { object } of this.trees.values()) {
      const area = (object.userData.leafArea ?? 0) * object.scale.x * object.scale.x;
      const keep = eye ? keepFraction(area, eye.distanceTo(object.position), this.detail.pixelsPerRadian, this.detail.leafPixels) : 1;
      object.userData.wind?.setKeep(keep, Math.min(keep, keepFraction(area, 1, texelsPerMetre, SHADOW_LEAF_TEXELS)));
    }
    let top = this.root;
    while (top.parent) top = top.parent;
    if (top.isScene) this.light.apply(top, this.root);
  }
}
