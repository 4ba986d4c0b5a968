// The room's light in AR: where the session grants `light-estimation` (xr.mjs asks for it,
// optional; Android's Chrome offers it), three.js's XREstimatedLight lights the scene from the
// browser's XRLightProbe (its spherical harmonics as a light probe, its main light as a
// directional light, its reflection cube map as the scene's environment), in place of the world's
// neutral AR environment (draw/light.mjs: its light probe is hidden and `scene.environment` is the
// estimate's while an estimate lights AR, and both are given back after; the sun stays, casting
// the shadows). Until the first estimate, and where there is none, the neutral environment of
// draw/light.mjs lights AR. A feature of the view (view/features.mjs), updated after `light`.
// VR and the preview are left as they are.

import { XREstimatedLight } from 'three/addons/webxr/XREstimatedLight.js';

/** Whether an XR session shows the real world (AR). */
const isAr = (session) => Boolean(session) && ['alpha-blend', 'additive'].includes(session.environmentBlendMode);

export class XrLight {
  /** `view`: the view (its renderer, the session's space `scene`, and its `light` feature). */
  constructor(view) {
    this.view = view;
    this.renderer = view.renderer;
    this.scene = view.scene;
    this.estimated = null; // XREstimatedLight while a session with light estimation runs
    this.estimating = false; // whether an estimate has come
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
    const world = this.view.features.light;
    // The world's light (updated just before) set its own environment and probe this frame.
    if (world) world.probe.visible = this.source !== 'estimate';
    if (this.source === 'estimate' && this.estimated.environment) this.scene.environment = this.estimated.environment;
  }

  /** What lights AR now: null outside AR, else { source, main } (main: the estimate's light, { direction, intensity, color }, or null). */
  state() {
    if (!this.source) return null;
    const d = this.estimated?.directionalLight;
    const main = this.source === 'estimate' && d ? { direction: d.position.toArray(), intensity: d.intensity, color: d.color.toArray() } : null;
    return { source: this.source, main };
  }
}
