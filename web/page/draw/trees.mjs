// The trees: the catalogue's glTF models loaded once each (GLTFLoader) and cloned per tree, their
// materials set up to look as grove's renderer draws them (shading.mjs: grove's light, leaves
// translucent, back faces of two-sided leaves lit as grove lights them; mips.mjs: the albedo's
// mips as grove makes them; alpha-to-coverage on the leaves' alpha test where the renderer
// multisamples; leaves.mjs: fewer, larger leaves with distance), casting and receiving shadows,
// each tree swaying in the simulation's wind with its shadow (wind.mjs).

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { orderLeaves, modelSeed, unsimplified } from './leaves.mjs';
import { groveMips } from './mips.mjs';
import { LEAF_TRANSLUCENCY, groveShading } from './shading.mjs';
import { TreeWind } from './wind.mjs';

/** Loads the catalogue's models (by name) from `base` (the server's `/models/shipped/`). */
export class Models {
  constructor(base = '/models/shipped/', { antialias = true } = {}) {
    this.base = base;
    this.antialias = antialias;
    this.loader = new GLTFLoader();
    this.models = new Map();
  }

  /**
   * Loads every name not loaded yet (from `urls[name]` where given, else `${base}${name}.gltf`);
   * resolves when all are.
   */
  async load(names, urls = {}) {
    await Promise.all(
      names.filter((n) => !this.models.has(n)).map(async (n) => {
        const url = urls[n] ?? `${this.base}${n}.gltf`;
        const gltf = await this.loader.loadAsync(url);
        // grove shuffles a model's leaves by its file name and its primitives' order.
        const seed = modelSeed(decodeURIComponent(new URL(url, location.href).pathname.split('/').pop()).replace(/\.(gltf|glb)$/i, ''));
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
        this.models.set(n, gltf.scene);
      }),
    );
  }

  /** The model's box in model space (metres), from its vertices. */
  bounds(name) {
    const m = this.models.get(name);
    return m ? new THREE.Box3().setFromObject(m, true) : null;
  }

  /**
   * A tree of a model: a copy sharing its geometry and textures, with materials of its own
   * (grove's shading, and its own wind), or a plain stand-in when the model is missing.
   */
  instance(name) {
    const m = this.models.get(name);
    if (!m) return standIn();
    const tree = m.clone();
    const wind = new TreeWind();
    tree.userData.wind = wind;
    tree.userData.leafArea = m.userData.leafArea;
    tree.traverse((o) => {
      if (!o.isMesh) return;
      const leaf = o.material.alphaTest > 0;
      o.material = groveShading(o.material.clone(), { translucency: leaf ? LEAF_TRANSLUCENCY : 0, vertex: wind.vertex, key: wind.key });
      o.customDepthMaterial = wind.depthMaterial(o.material);
    });
    return tree;
  }
}

function standIn() {
  const stand = new THREE.Mesh(new THREE.ConeGeometry(0.8, 3, 8), groveShading(new THREE.MeshStandardMaterial({ color: 0x2f6b2f })));
  stand.position.y = 1.5;
  const g = new THREE.Group();
  g.add(stand);
  return g;
}
