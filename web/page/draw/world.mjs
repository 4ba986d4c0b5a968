// The world as three.js draws it from the simulation's snapshot: the trees (the catalogue's mesh
// and billboard models, loaded once each through GLTFLoader and cloned), the sun and its
// shadows, the sky (none in AR, where the room is seen). The ground is draw/ground.mjs's.
//
// Everything is in the simulation's frame (metres, +Y up); the page's XR reference space is
// offset so that the headset's poses are in that frame too (room.mjs).

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

/** Loads the catalogue's models (by name) from the server's `/models/shipped/`. */
export class Models {
  constructor(base = '/models/shipped/') {
    this.base = base;
    this.loader = new GLTFLoader();
    this.models = new Map();
  }

  /** Loads every name not loaded yet; resolves when all are. */
  async load(names) {
    await Promise.all(
      names.filter((n) => !this.models.has(n)).map(async (n) => {
        const gltf = await this.loader.loadAsync(`${this.base}${n}.gltf`);
        gltf.scene.traverse((o) => {
          if (o.isMesh) {
            o.castShadow = true;
            o.receiveShadow = false;
          }
        });
        this.models.set(n, gltf.scene);
      }),
    );
  }

  /** A copy of a model (sharing its geometry and materials), or a plain stand-in. */
  instance(name) {
    const m = this.models.get(name);
    if (m) return m.clone();
    const stand = new THREE.Mesh(new THREE.ConeGeometry(0.8, 3, 8), new THREE.MeshStandardMaterial({ color: 0x2f6b2f }));
    stand.position.y = 1.5;
    const g = new THREE.Group();
    g.add(stand);
    return g;
  }
}

/** The trees, sun and sky of the world shown (a feature of the view: view/features.mjs). */
export class World {
  /** `scene`: the view's scene (its sky); `parent`: the simulation's frame. */
  constructor(scene, parent, models, { shadows = true } = {}) {
    this.scene = scene;
    this.models = models;
    this.shown = null; // the world record drawn (flow/task.mjs's worldOf), or null
    this.trees = new Map(); // id -> { object, model }
    this.sky = new THREE.Color(0x9cc3e6);
    this.root = new THREE.Group();
    this.root.name = 'world';
    this.root.visible = false;
    parent.add(this.root);
    this.hemi = new THREE.HemisphereLight(0xdfeaff, 0x4a4030, 1.0);
    this.root.add(this.hemi);
    this.sun = new THREE.DirectionalLight(0xfff4e0, 2.2);
    this.sun.castShadow = shadows;
    this.sun.shadow.mapSize.set(1024, 1024);
    const c = this.sun.shadow.camera;
    c.left = -22;
    c.right = 22;
    c.top = 22;
    c.bottom = -22;
    c.near = 1;
    c.far = 120;
    this.sun.shadow.bias = -0.0005;
    this.root.add(this.sun);
    this.root.add(this.sun.target);
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
    this.scene.background = world && !world.ar ? this.sky : null;
    if (!world) return;
    this.hemi.intensity = world.ar ? 1.2 : 1.0;
    if (world.snapshot) this.#trees(world.snapshot);
  }

  /** Brings trees and the sun to the snapshot. */
  #trees(snap) {
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
    }
    for (const [id, entry] of this.trees) {
      if (!seen.has(id)) {
        this.root.remove(entry.object);
        this.trees.delete(id);
      }
    }
    const d = snap.sun_direction;
    if (d && d[1] > 0) {
      // The light looks at the task area from the sun's direction.
      this.sun.target.position.set(0, 0, -4);
      this.sun.position.set(d[0] * 60, d[1] * 60 - 0, d[2] * 60 - 4);
      this.sun.visible = true;
    } else {
      this.sun.visible = false;
    }
  }
}
