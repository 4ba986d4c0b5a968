// The trees: the catalogue's glTF models loaded once each (GLTFLoader), each primitive drawn for
// every tree of its model by one InstancedMesh (forest.mjs), its material set up to look as grove's renderer draws them (shading.mjs: grove's light, leaves
// translucent, back faces of two-sided leaves lit as grove lights them; mips.mjs: the albedo's
// mips as grove makes them; alpha-to-coverage on the leaves' alpha test where the renderer
// multisamples; leaves.mjs: fewer, larger leaves with distance), casting and receiving shadows,
// each tree swaying in the simulation's wind with its shadow (wind.mjs: per-tree values as
// instanced attributes) and giving way to its far model (levels.mjs).

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { orderLeaves, modelSeed, unsimplified } from './leaves.mjs';
import { groveMips } from './mips.mjs';
import { crossFade } from './levels.mjs';
import { LEAF_TRANSLUCENCY, groveShading } from './shading.mjs';
import { instancedVertex, windDepthMaterial } from './wind.mjs';

/** Loads the catalogue's models (by name) from `base` (the server's `/models/shipped/`). */
export class Models {
  constructor(base = '/models/shipped/', { antialias = true } = {}) {
    this.base = base;
    this.antialias = antialias;
    this.loader = new GLTFLoader();
    this.models = new Map();
    this.far = new Map(); // name -> its far model's name (a bank catalogue's `far:`)
    this.boxes = new Map();
    this.parts = new Map();
  }

  /**
   * Loads every name not loaded yet (from `urls[name]` where given, else `${base}${name}.gltf`),
   * and the far model of each that `far` (name -> name, a bank catalogue's `far:`) gives one;
   * resolves when all are.
   */
  async load(names, urls = {}, far = {}) {
    for (const n of names) if (far[n]) this.far.set(n, far[n]);
    await Promise.all(
      [...new Set([...names, ...names.map((n) => far[n]).filter(Boolean)])]
        .filter((n) => !this.models.has(n))
        .map(async (n) => {
          const url = urls[n] ?? `${this.base}${n}.gltf`;
          const gltf = await this.loader.loadAsync(url);
          // grove shuffles a model's leaves by its file name and its primitives' order.
          const seed = modelSeed(
            decodeURIComponent(new URL(url, location.href).pathname.split('/').pop()).replace(/\.(gltf|glb)$/i, ''),
          );
          const areas = [];
          let primitive = 0;
          gltf.scene.traverse((o) => {
            if (!o.isMesh) return;
            o.castShadow = true;
            o.receiveShadow = true;
            const m = o.material;
            m.map = groveMips(m.map);
            if (m.specularIntensityMap) m.specularIntensityMap = groveMips(m.specularIntensityMap);
            if (m.alphaTest > 0) {
              m.alphaToCoverage = this.antialias;
              const area = orderLeaves(o.geometry, seed ^ BigInt(primitive));
              if (area > 0) areas.push(area);
            } else unsimplified(o.geometry);
            primitive++;
          });
          gltf.scene.userData.leafArea = areas.length ? areas.reduce((a, b) => a + b) / areas.length : 0;
          this.boxes.set(n, new THREE.Box3().setFromObject(gltf.scene, true));
          this.models.set(n, gltf.scene);
        }),
    );
  }

  /** The model's box in model space (metres), from its vertices. */
  bounds(name) {
    return this.boxes.get(name)?.clone() ?? null;
  }

  /**
   * What draws every tree of a model (forest.mjs), made once: per primitive its geometry, a
   * material of grove's shading (shared by the model's trees, their wind and cross-fade read
   * from instanced attributes), its shadow's depth material and whether it is alpha-clipped
   * (leaves); a plain stand-in where the model is missing.
   */
  primitives(name) {
    const m = this.models.get(name);
    const key = m ? name : null;
    if (!this.parts.has(key)) this.parts.set(key, m ? this.#primitives(m) : standIn());
    return this.parts.get(key);
  }

  #primitives(model) {
    // grove writes a model as one node at the origin: its primitives' vertices are in model space.
    const parts = [];
    model.traverse((o) => {
      if (!o.isMesh) return;
      const leaf = o.material.alphaTest > 0;
      const material = groveShading(o.material.clone(), {
        translucency: leaf ? LEAF_TRANSLUCENCY : 0,
        vertex: (shader) => {
          instancedVertex(shader);
          crossFade(shader);
        },
        key: '-forest',
      });
      parts.push({ geometry: o.geometry, material, depth: windDepthMaterial({}, crossFade), leaf });
    });
    return parts;
  }
}

/** A cone where a model is missing. */
function standIn() {
  const geometry = new THREE.ConeGeometry(0.8, 3, 8).translate(0, 1.5, 0);
  const material = groveShading(new THREE.MeshStandardMaterial({ color: 0x2f6b2f }));
  return [{ geometry, material, depth: null, leaf: false }];
}

/** The stand-in's box (standIn). */
export const STAND_IN_BOX = new THREE.Box3(new THREE.Vector3(-0.8, 0, -0.8), new THREE.Vector3(0.8, 3, 0.8));
