// The light of the world as grove's renderer computes it, from the snapshot's `light` (the sun's
// direction and grove_systems::light::sun_light of its elevation, systems/src/light.rs):
//
// - the sun, a DirectionalLight carrying grove's direct light (times π: shading.mjs), casting
//   shadows from an orthographic view fitted around what is drawn, as
//   src/render/lighting.rs's `light_matrix` fits it;
// - the environment light: in VR and the preview the sky grove ships (sky.mjs), its irradiance
//   as spherical harmonics (three's LightProbeGenerator; grove convolves the same cube with the
//   cosine, src/render/assets/textures.rs `irradiance`) at the ambient light's strength, and its
//   reflections prefiltered by three's PMREMGenerator at the sky's brightness; in AR a neutral
//   white environment and three's RoomEnvironment's reflections, which draw/xrlight.mjs replaces
//   by the browser's light estimate where there is one.
//
// A feature of the view (view/features.mjs): every frame the sun and the sky's brightness follow
// the snapshot, and the shadow's view is fitted around the ground and the trees (cut to 80 m
// around the head, as src/render/lighting.rs's `shadow_bounds` cuts it).

import * as THREE from 'three';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
import { LightProbeGenerator } from 'three/addons/lights/LightProbeGenerator.js';
import { Sky } from './sky.mjs';

/** The shadow map's edge, texels, as grove's renderer has it by default. */
export const SHADOW_SIZE = 1024;

export class Light {
  /** `view`: the view (its renderer, scene, simulation's frame, and the ground and trees it draws). */
  constructor(view) {
    this.view = view;
    this.shown = null;
    this.root = new THREE.Group();
    this.root.name = 'light';
    this.root.visible = false;
    view.simRoot.add(this.root);
    this.sun = new THREE.DirectionalLight(0xffffff, Math.PI);
    this.sun.name = 'sun';
    this.sun.castShadow = view.shadows;
    this.sun.shadow.mapSize.set(SHADOW_SIZE, SHADOW_SIZE);
    this.sun.shadow.bias = -0.0005;
    this.probe = new THREE.LightProbe();
    this.probe.name = 'sky light';
    this.root.add(this.sun, this.sun.target, this.probe);
    this.direction = new THREE.Vector3(0, 1, 0);
    this.sky = 1;
    this.reflections = null;
    this.texelsPerMetre = SHADOW_SIZE;
  }

  /** The world's light (s.world, and the snapshot's `light`); none without a world. */
  update(s) {
    const { view } = this;
    if (s.world !== this.shown) {
      this.shown = s.world;
      this.root.visible = Boolean(s.world);
      if (s.world) this.setEnvironment(view.environment(s.world.ar));
    }
    if (!s.world) {
      view.scene.environment = null;
      return;
    }
    const snap = s.snap ?? s.world.snapshot;
    this.set(snap?.light);
    const box = view.features.world.box().union(view.features.ground.box);
    if (snap?.head) {
      const h = new THREE.Vector3().fromArray(snap.head.position);
      box.intersect(new THREE.Box3(h.clone().subScalar(80).setY(-1000), h.clone().addScalar(80).setY(1000)));
    }
    this.texelsPerMetre = this.fitShadow(box);
    this.apply(view.scene, view.simRoot);
  }

  /** The environment (`environmentFor` in renderer.mjs): its irradiance and reflections. */
  setEnvironment(environment) {
    if (!environment) return;
    this.probe.sh.copy(environment.sh);
    this.reflections = environment.map;
  }

  /** The sun of a snapshot's `light`; hidden below the horizon. */
  set(light) {
    if (!light) return;
    this.direction.fromArray(light.sun_direction).normalize();
    const [r, g, b] = light.direct;
    this.sun.color.setRGB(r, g, b, THREE.LinearSRGBColorSpace);
    this.sun.visible = Math.max(r, g, b) > 0;
    this.probe.intensity = light.ambient[0];
    this.sky = light.sky;
  }

  /**
   * Fits the sun's shadow camera around `box` (a Box3 in the root's frame): looking along the
   * sun's direction from outside it, just wide and deep enough for its corners, the normal
   * offset 1.5 texels (lighting.rs). Returns the shadow map's texels per metre.
   */
  fitShadow(box) {
    if (box.isEmpty()) return SHADOW_SIZE;
    const centre = box.getCenter(new THREE.Vector3());
    const radius = box.getSize(new THREE.Vector3()).length() / 2 + 1;
    this.sun.position.copy(centre).addScaledVector(this.direction, radius * 2);
    this.sun.target.position.copy(centre);
    this.sun.updateMatrixWorld(true);
    this.sun.target.updateMatrixWorld(true);
    const view = new THREE.Matrix4().lookAt(this.sun.position, centre, Math.abs(this.direction.y) > 0.99 ? new THREE.Vector3(0, 0, 1) : new THREE.Vector3(0, 1, 0));
    view.setPosition(this.sun.position).invert();
    const lo = new THREE.Vector3(Infinity, Infinity, Infinity);
    const hi = new THREE.Vector3(-Infinity, -Infinity, -Infinity);
    for (let i = 0; i < 8; i++) {
      const c = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y, i & 4 ? box.max.z : box.min.z).applyMatrix4(view);
      lo.min(c);
      hi.max(c);
    }
    const cam = this.sun.shadow.camera;
    Object.assign(cam, { left: lo.x, right: hi.x, bottom: lo.y, top: hi.y, near: Math.max(-hi.z - 1, 0.01), far: -lo.z + 1 });
    cam.updateProjectionMatrix();
    const extent = Math.max(hi.x - lo.x, hi.y - lo.y);
    this.sun.shadow.normalBias = (extent / SHADOW_SIZE) * 1.5;
    return SHADOW_SIZE / Math.max(extent, 1e-3);
  }

  /**
   * An environment light: { sh, map }, the irradiance (spherical harmonics) and the prefiltered
   * reflections of the sky's cube (VR, the preview), or of a neutral environment where `cube`
   * is null (AR): white light of radiance 1 from everywhere, a room's reflections.
   */
  static environment(renderer, cube) {
    const pmrem = new THREE.PMREMGenerator(renderer);
    let target;
    let sh;
    if (cube) {
      const s = new THREE.Scene();
      s.add(new Sky(cube, { raw: true }).mesh);
      target = pmrem.fromScene(s, 0, 0.1, 10);
      sh = LightProbeGenerator.fromCubeTexture(cube).sh;
      // three reads a cube texture mirrored in x (its CubeTexture convention); grove's faces
      // are WebGL's own: mirror the harmonics back (the basis functions odd in x).
      for (const i of [3, 4, 7]) sh.coefficients[i].multiplyScalar(-1);
    } else {
      target = pmrem.fromScene(new RoomEnvironment(), 0.04);
      sh = new THREE.SphericalHarmonics3();
      sh.coefficients[0].setScalar(2 * Math.sqrt(Math.PI));
    }
    pmrem.dispose();
    return { sh, map: target.texture };
  }

  /**
   * Sets `scene`'s environment: its reflections at the sky's brightness, turned with the
   * simulation's frame (`root`, whose rotation the room's offset sets).
   */
  apply(scene, root) {
    scene.environment = this.reflections;
    scene.environmentIntensity = this.sky;
    scene.environmentRotation.setFromQuaternion(root.getWorldQuaternion(new THREE.Quaternion()).invert());
  }
}
