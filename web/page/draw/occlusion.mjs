// Real things hide the trees: in AR, where the session grants `depth-sensing` (xr.mjs asks for it,
// optional, as a GPU texture), whatever the page drew behind a real object fades out, with a soft
// edge. A feature of the view (view/features.mjs); without depth sensing it draws nothing.
//
// three.js (r187) keeps the session's depth texture (`renderer.xr.getDepthTexture()`) and draws
// with it a hard occluder of its own before the scene; this module hides that one and draws,
// after everything else, a few full-screen passes instead. Each pass writes a depth taken from
// the real depth around the pixel and, where the page's drawing lies behind it (the depth test),
// scales the pixel's colour and alpha down. Pass i stands at the i-th nearest of four real depths
// a little apart (a 2 × 2 texel footprint, percentage-closer filtering as in shadow maps), so a
// pixel behind k of the 4 keeps (4 − k) / 4 of itself: the outline of a real object is a ramp
// about two depth texels wide rather than the depth map's blocks. A margin that grows with
// distance (the sensor's noise) keeps the sensed floor from eating the shadow catcher
// (draw/ground.mjs) or a trunk's foot.
//
// The depth texture holds window-space depth for the view's projection with the information's
// near and far planes (the spec's GPU layout; IWER's and Quest's); three.js sets the XR camera's
// near and far to those, so a real depth in metres is turned into the same depth buffer's values.

import * as THREE from 'three';

/** Samples of the real depth per pixel, and so passes. */
const TAPS = 4;
/** How far apart the samples are, depth texels. */
const SPREAD = 1.0;
/** Real depth nearer than the page's by less than this does not hide it, metres: MARGIN[0] + MARGIN[1] × depth. */
export const MARGIN = [0.05, 0.03];

const VERTEX = /* glsl */ `
void main() {
  gl_Position = vec4(position.xy, 0.0, 1.0);
}`;

const FRAGMENT = /* glsl */ `
uniform sampler2DArray depthTexture;
uniform vec2 eyeSize;   // one eye's viewport, pixels (the eyes side by side)
uniform float near;
uniform float far;
uniform vec2 margin;

// Window depth <-> metres for a perspective projection with these planes (far may be Infinity).
float metres(float z) {
  float k = isinf(far) ? 1.0 : (far - near) / far;
  return near / (1.0 - z * k);
}
float windowDepth(float d) {
  float k = isinf(far) ? 1.0 : far / (far - near);
  return k * (1.0 - near / d);
}

// The real depth at a texel, metres; a texel without data is far away.
float real(ivec3 t, ivec2 size) {
  float z = texelFetch(depthTexture, ivec3(clamp(t.xy, ivec2(0), size - 1), t.z), 0).r;
  return (z <= 0.0 || z >= 1.0) ? 1e9 : metres(z);
}

void main() {
  vec2 uv = gl_FragCoord.xy / eyeSize;
  int layer = uv.x >= 1.0 ? 1 : 0;
  uv.x -= float(layer);
  ivec2 size = textureSize(depthTexture, 0).xy;
  vec2 p = uv * vec2(size) - 0.5;
  float h = ${SPREAD.toFixed(2)} * 0.5;
  float s0 = real(ivec3(ivec2(floor(p + vec2(-h, -h) + 0.5)), layer), size);
  float s1 = real(ivec3(ivec2(floor(p + vec2(h, -h) + 0.5)), layer), size);
  float s2 = real(ivec3(ivec2(floor(p + vec2(-h, h) + 0.5)), layer), size);
  float s3 = real(ivec3(ivec2(floor(p + vec2(h, h) + 0.5)), layer), size);
  // Sorted nearest first (a sorting network of five exchanges).
  float a = min(s0, s1), b = max(s0, s1), c = min(s2, s3), d = max(s2, s3);
  float lo = min(a, c), hi = max(b, d);
  float m1 = max(a, c), m2 = min(b, d);
  float sorted[4] = float[4](lo, min(m1, m2), max(m1, m2), hi);
  float r = sorted[PASS];
  if (r > 1e8) discard;
  float behind = r + margin.x + margin.y * r;
  gl_FragDepth = clamp(windowDepth(behind), 0.0, 1.0);
  gl_FragColor = vec4(0.0, 0.0, 0.0, KEEP);
}`;

/** The occlusion of the page's drawing by the real room (a feature of the view). */
export class Occlusion {
  /** `renderer`: the view's (WebXR enabled); `scene`: the session's space. */
  constructor(renderer, scene) {
    this.renderer = renderer;
    this.uniforms = {
      depthTexture: { value: null },
      eyeSize: { value: new THREE.Vector2(1, 1) },
      near: { value: 0.1 },
      far: { value: 1000 },
      margin: { value: new THREE.Vector2(...MARGIN) },
    };
    this.root = new THREE.Group();
    this.root.name = 'occlusion';
    this.root.visible = false;
    const quad = new THREE.PlaneGeometry(2, 2);
    for (let i = 0; i < TAPS; i++) {
      const material = new THREE.ShaderMaterial({
        name: `occlusion-${i}`,
        vertexShader: VERTEX,
        fragmentShader: FRAGMENT,
        // Pass i, behind the i nearest samples, keeps (TAPS - i - 1) / (TAPS - i) of the pixel:
        // the passes a pixel fails are always the first k, and their product is (TAPS - k) / TAPS.
        defines: { PASS: i, KEEP: ((TAPS - i - 1) / (TAPS - i)).toFixed(6) },
        uniforms: this.uniforms,
        transparent: true,
        depthWrite: false,
        depthTest: true,
        depthFunc: THREE.LessDepth,
        blending: THREE.CustomBlending,
        blendEquation: THREE.AddEquation,
        blendSrc: THREE.ZeroFactor,
        blendDst: THREE.SrcAlphaFactor,
        blendSrcAlpha: THREE.ZeroFactor,
        blendDstAlpha: THREE.SrcAlphaFactor,
      });
      const mesh = new THREE.Mesh(quad, material);
      mesh.name = `occlusion:${i}`;
      mesh.frustumCulled = false;
      mesh.renderOrder = 1e6 + i; // after everything the page draws
      mesh.onBeforeRender = (_r, _s, camera) => this.#eye(camera);
      this.root.add(mesh);
    }
    scene.add(this.root);
    /** What hides the trees now: null, or { usage, format, width, height } of the session's depth. */
    this.active = null;
  }

  /** On in AR while the session gives a depth texture; three.js's own hard occluder stays hidden. */
  update(s) {
    const xr = this.renderer.xr;
    const session = xr.isPresenting ? xr.getSession() : null;
    const texture = session && s.xr ? xr.getDepthTexture() : null;
    const builtIn = session ? xr.getDepthSensingMesh() : null;
    if (builtIn) builtIn.visible = false;
    this.uniforms.depthTexture.value = texture;
    this.root.visible = Boolean(texture);
    this.active = texture ? { usage: session.depthUsage, format: session.depthDataFormat } : null;
  }

  /** The eye's viewport and planes (the same for both eyes; set as each pass is drawn). */
  #eye(camera) {
    const v = camera.viewport;
    if (v && v.z > 0) this.uniforms.eyeSize.value.set(v.z, v.w);
    this.uniforms.near.value = camera.near;
    this.uniforms.far.value = camera.far;
  }
}
