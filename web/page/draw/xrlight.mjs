// The room's light in AR: where the session grants `light-estimation` (xr.mjs asks for it,
// optional; Android's Chrome offers it), three.js's XREstimatedLight lights the scene from the
// browser's XRLightProbe (its spherical harmonics as a light probe, its main light as a
// directional light, its reflection cube map as the scene's environment); until the first
// estimate, and where there is none, a neutral environment: three.js's RoomEnvironment as a light
// probe (LightProbeGenerator's spherical harmonics; diffuse only: a prefiltered environment map
// halved the frame rate of software WebGL, and leaves are rough). A feature of the view
// (view/features.mjs); it owns `scene.environment` while an estimate lights AR and gives it back
// after. VR and the preview are left as they are.

import * as THREE from 'three';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
import { LightProbeGenerator } from 'three/addons/lights/LightProbeGenerator.js';
import { XREstimatedLight } from 'three/addons/webxr/XREstimatedLight.js';

/** Whether an XR session shows the real world (AR). */
const isAr = (session) => Boolean(session) && ['alpha-blend', 'additive'].includes(session.environmentBlendMode);

export class XrLight {
  /** `renderer`: the view's; `scene`: the session's space (its environment). */
  constructor(renderer, scene) {
    this.renderer = renderer;
    this.scene = scene;
    this.neutral = null; // the neutral room's light probe, once made (#makeNeutral)
    this.making = false;
    this.estimated = null; // XREstimatedLight while a session with light estimation runs
    this.estimating = false; // whether an estimate has come
    this.owned = null; // the environment this module put on the scene
    this.before = null; // the scene's environment before that
    /** Where AR's light comes from now: 'estimate', 'neutral', or null (not in AR). */
    this.source = null;
  }

  /**
   * Called by the view before it presents `session` (XREstimatedLight listens for the session's
   * start): only a session that granted light estimation gets one.
   */
  beforeSession(session) {
    if (!session.enabledFeatures?.includes('light-estimation')) return;
    const light = new XREstimatedLight(this.renderer, true);
    light.name = 'estimated light';
    light.addEventListener('estimationstart', () => (this.estimating = true));
    light.addEventListener('estimationend', () => (this.estimating = false));
    this.scene.add(light);
    this.estimated = light;
    session.addEventListener('end', () => {
      this.scene.remove(light);
      light.dispose();
      if (this.estimated === light) {
        this.estimated = null;
        this.estimating = false;
      }
    });
  }

  update() {
    const xr = this.renderer.xr;
    const ar = xr.isPresenting && isAr(xr.getSession());
    this.source = !ar ? null : this.estimating ? 'estimate' : 'neutral';
    if (this.source === 'neutral' && !this.neutral && !this.making) this.#makeNeutral();
    if (this.neutral) this.neutral.visible = this.source === 'neutral';
    const env = this.source === 'estimate' ? this.estimated.environment : null;
    if (env === this.owned) return;
    if (this.owned === null) this.before = this.scene.environment; // taken now
    this.scene.environment = env ?? this.before; // given back when the estimate ends
    this.owned = env;
  }

  /** What lights AR now: null outside AR, else { source, main } (main: the estimate's light, { direction, intensity, color }, or null). */
  state() {
    if (!this.source) return null;
    const d = this.estimated?.directionalLight;
    const main = this.source === 'estimate' && d ? { direction: d.position.toArray(), intensity: d.intensity, color: d.color.toArray() } : null;
    return { source: this.source, main };
  }

  /** The neutral room's light: RoomEnvironment drawn once into a small cube, as a light probe. */
  async #makeNeutral() {
    this.making = true;
    const target = new THREE.WebGLCubeRenderTarget(16);
    const room = new RoomEnvironment();
    new THREE.CubeCamera(0.1, 100, target).update(this.renderer, room);
    const probe = await LightProbeGenerator.fromCubeRenderTarget(this.renderer, target);
    target.dispose();
    room.dispose();
    probe.name = 'neutral light';
    probe.visible = false;
    this.scene.add(probe);
    this.neutral = probe;
  }
}
