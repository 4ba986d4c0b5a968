// The page's view: the three.js renderer (WebXR enabled), the scene in the session's reference
// space, the simulation's frame placed in it by the offset (room.mjs), the inline preview's
// camera, and the drawn features (view/features.mjs), each brought to the frame's state by
// `update(s)`. It reads nothing but what the flow hands it (flow/frame.mjs). web/page/still.mjs
// draws its pictures through a view too.

import * as THREE from 'three';
import { EYE_PIXELS_PER_RADIAN } from '../draw/leaves.mjs';
import { createRenderer, environmentFor } from '../draw/renderer.mjs';
import { FEATURES } from './features.mjs';

export class View {
  /**
   * Draws on `canvas`; `low`: no shadows, one pixel per CSS pixel (draw/renderer.mjs); `models`:
   * draw/trees.mjs's Models. For still pictures (web/page/still.mjs): `antialias` false draws one
   * sample a pixel, `preserve` keeps the drawing buffer, `background` false draws the trees alone
   * (no sky, no ground), `pixelsPerRadian` is the picture's (else a headset eye's).
   */
  constructor(canvas, { low = false, models, antialias = true, preserve = false, background = true, pixelsPerRadian = EYE_PIXELS_PER_RADIAN }) {
    const renderer = createRenderer(canvas, { low, antialias, preserve });
    renderer.setPixelRatio(low ? 1 : Math.min(window.devicePixelRatio, 2));
    renderer.setSize(window.innerWidth, window.innerHeight, false);
    renderer.xr.enabled = true;
    this.renderer = renderer;
    this.scene = new THREE.Scene();
    this.simRoot = new THREE.Group(); // the simulation's frame, placed in the session's reference space by the offset
    this.simRoot.name = 'simulation';
    this.scene.add(this.simRoot);
    this.camera = new THREE.PerspectiveCamera(60, window.innerWidth / window.innerHeight, 0.05, 200);
    this.models = models;
    this.shadows = !low;
    this.background = background;
    this.pixelsPerRadian = pixelsPerRadian;
    this.env = null; // the sky's cube and the ground's texture (draw/sky.mjs loadEnvironment), once loaded
    this.features = Object.fromEntries(Object.entries(FEATURES).map(([name, make]) => [name, make(this)]));
    window.addEventListener('resize', () => {
      if (renderer.xr.isPresenting) return;
      renderer.setSize(window.innerWidth, window.innerHeight, false);
      this.camera.aspect = window.innerWidth / window.innerHeight;
      this.camera.updateProjectionMatrix();
    });
  }

  /** The sky and ground grove ships ({ cube, ground }: draw/sky.mjs loadEnvironment), or null. */
  setEnvironment(env) {
    this.env = env;
  }

  /** The environment light of a world (draw/light.mjs): the sky's, or a neutral one in AR. */
  environment(ar) {
    return environmentFor(this.renderer, { ar, cube: this.env?.cube ?? null });
  }

  /**
   * Presents an immersive session; resolves to its `local-floor` reference space. A feature with
   * `beforeSession(session)` sees the session first (draw/xrlight.mjs).
   */
  async present(session) {
    this.renderer.xr.setReferenceSpaceType('local-floor');
    for (const f of Object.values(this.features)) f.beforeSession?.(session);
    await this.renderer.xr.setSession(session);
    return this.renderer.xr.getReferenceSpace();
  }

  /** Calls `loop(time, xrFrame)` every frame (the XR session's frames while one is presented). */
  loop(loop) {
    this.renderer.setAnimationLoop(loop);
  }

  /** Places the simulation's frame in the session's reference space (room.mjs's offset). */
  placeSimRoot(o) {
    this.simRoot.position.set(o.position.x, o.position.y, o.position.z);
    this.simRoot.quaternion.set(o.orientation.x, o.orientation.y, o.orientation.z, o.orientation.w);
    this.simRoot.updateMatrixWorld(true);
  }

  /** The inline preview's camera at a snapshot's head ({ head, fov_y }). */
  placeCamera(snap) {
    const camera = this.camera;
    camera.position.set(...snap.head.position);
    camera.quaternion.set(...snap.head.rotation);
    const fov = THREE.MathUtils.radToDeg(snap.fov_y);
    if (Math.abs(camera.fov - fov) > 1e-3) {
      camera.fov = fov;
      camera.updateProjectionMatrix();
    }
  }

  /** Where a point of the simulation's frame ([x, y, z]) is on the preview's canvas, CSS pixels. */
  screenPoint(p) {
    const v = new THREE.Vector3(p[0], p[1], p[2]).project(this.camera);
    const r = this.renderer.domElement.getBoundingClientRect();
    return { x: r.left + ((v.x + 1) / 2) * r.width, y: r.top + ((1 - v.y) / 2) * r.height };
  }

  /** Brings every feature to the frame's state `s` (view/features.mjs). */
  update(s) {
    for (const f of Object.values(this.features)) f.update(s);
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }
}
