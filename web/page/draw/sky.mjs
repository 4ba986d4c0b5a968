// The sky grove ships (assets/env: six cube faces, served from the page's `env/`), drawn as
// grove's renderer draws it (src/render/lighting.wgsl's `sky_lit`, src/render/sky/sky.wgsl): the
// cube map seen along each view ray, raised to just above the horizon, dimmed with the sky's
// brightness and tinted like the ambient light, with the sun's halo, glow and disc, through
// grove's tone curve; and the aerial perspective's haze, the sky's colour over what lies far
// from the eye. The same cube, unraised and undimmed, is what the environment light is
// prefiltered from (light.mjs).
//
// The faces are in the layout grove writes them (src/cubemap.rs), which is WebGL's own: the
// shader samples them along world directions as they are, with no mirroring.

import * as THREE from 'three';

/** The cube faces in grove's (and WebGL's) order: +X, −X, +Y, −Y, +Z, −Z. */
export const FACES = ['px', 'nx', 'py', 'ny', 'pz', 'nz'];

/** Loads the six faces under `base` (a URL ending in `/`) as an sRGB cube texture. */
export async function loadSkyCube(base) {
  const texture = await new THREE.CubeTextureLoader().loadAsync(FACES.map((f) => new URL(`${f}.png`, base).href));
  texture.colorSpace = THREE.SRGBColorSpace;
  texture.generateMipmaps = false;
  texture.minFilter = THREE.LinearFilter;
  return texture;
}

/**
 * The sky's uniforms, shared by the sky and by every material that fades into it (the haze,
 * shading.mjs): the cube, the sky's brightness and tint, the sun, the haze's distances (metres:
 * start, depth, full from, full at), whether there is haze (not over a real room), and the
 * rotation from three's world into the simulation's frame. Set by `updateSky` every frame.
 */
export const skyUniforms = {
  groveSkyEnv: { value: null },
  groveSky: { value: 1 },
  groveSkyTint: { value: new THREE.Vector3(1, 1, 1) },
  groveSunDir: { value: new THREE.Vector3(0, 1, 0) },
  groveSunColor: { value: new THREE.Vector3(0, 0, 0) },
  groveHaze: { value: new THREE.Vector4(40, 400, 350, 590) },
  groveHazeOn: { value: 0 },
  groveSimFrame: { value: new THREE.Matrix3() },
};

/**
 * The sky along a unit direction `u` of the simulation's frame, without the sun's disc
 * (lighting.wgsl's `sky_lit`): the cube read with the direction raised to just above the
 * horizon, dimmed and tinted, with the sun's halo and its glow near the horizon.
 */
export const SKY_GLSL = /* glsl */ `
uniform samplerCube groveSkyEnv;
uniform float groveSky;
uniform vec3 groveSkyTint;
uniform vec3 groveSunDir;
uniform vec3 groveSunColor;
uniform vec4 groveHaze;
uniform float groveHazeOn;
uniform mat3 groveSimFrame;
vec3 groveSkyLit( vec3 u ) {
	float ls = log2( max( dot( u, groveSunDir ), 1e-6 ) );
	vec3 c = texture( groveSkyEnv, vec3( u.x, max( u.y, 0.02 ), u.z ) ).rgb * groveSky * groveSkyTint;
	float low = 1.0 - clamp( groveSunDir.y * 2.0, 0.0, 1.0 );
	return c + groveSunColor * ( exp2( 40.0 * ls ) * 0.12 + exp2( 4.0 * ls ) * 0.25 * low );
}
// The haze at a point of three's world: its colour (the sky along the view ray) and share
// (lighting.wgsl's haze_at), none within groveHaze.x of the eye.
vec4 groveHazeAt( vec3 world ) {
	vec3 to = groveSimFrame * ( world - cameraPosition );
	float d = max( length( to ), 1e-6 );
	if ( groveHazeOn < 0.5 || d <= groveHaze.x ) return vec4( 0.0 );
	float f = max( 1.0 - exp( - ( d - groveHaze.x ) / groveHaze.y ), smoothstep( groveHaze.z, groveHaze.w, d ) );
	return vec4( groveSkyLit( to / d ), f );
}
`;

/** The sky's uniforms from a snapshot's `light`, the cube (null: no haze) and the simulation's frame (`root`). */
export function updateSky(light, cube, root) {
  const u = skyUniforms;
  u.groveSkyEnv.value = cube;
  u.groveHazeOn.value = cube ? 1 : 0;
  u.groveSimFrame.value.setFromMatrix4(new THREE.Matrix4().makeRotationFromQuaternion(root.getWorldQuaternion(new THREE.Quaternion()).invert()));
  if (!light) return;
  u.groveSky.value = light.sky;
  const a = light.ambient;
  const r = Math.max(a[0], 0.001);
  u.groveSkyTint.value.set(a[0] / r, a[1] / r, a[2] / r);
  u.groveSunDir.value.fromArray(light.sun_direction);
  u.groveSunColor.value.fromArray(light.direct);
  if (light.haze) u.groveHaze.value.fromArray(light.haze);
}

const vertexShader = /* glsl */ `
varying vec3 vDir;
void main() {
	vDir = position;
	vec4 p = projectionMatrix * vec4( mat3( viewMatrix ) * mat3( modelMatrix ) * position, 1.0 );
	gl_Position = p.xyww;
}
`;

const fragmentShader = /* glsl */ `
${SKY_GLSL}
uniform samplerCube env;
uniform bool raw;
varying vec3 vDir;
void main() {
	vec3 u = normalize( vDir );
	if ( raw ) {
		gl_FragColor = vec4( texture( env, u ).rgb, 1.0 );
	} else {
		float ls = log2( max( dot( u, groveSunDir ), 1e-6 ) );
		vec3 c = groveSkyLit( u ) + groveSunColor * exp2( 600.0 * ls ) * 4.0 * ( u.y > 0.0 ? 1.0 : 0.0 );
		gl_FragColor = vec4( c, 1.0 );
		gl_FragColor.rgb = gl_FragColor.rgb / ( 1.0 + 0.15 * gl_FragColor.rgb );
	}
	#include <colorspace_fragment>
}
`;

/**
 * The sky: a mesh drawn behind everything (at the far plane, wherever the camera is), turned
 * with the frame it is added to (the simulation's). `raw` draws the cube map alone, for the
 * environment light's prefiltering.
 */
export class Sky {
  constructor(cube, { raw = false } = {}) {
    this.material = new THREE.ShaderMaterial({
      uniforms: { ...skyUniforms, env: { value: cube }, raw: { value: raw } },
      vertexShader,
      fragmentShader,
      side: THREE.BackSide,
      depthWrite: false,
    });
    this.mesh = new THREE.Mesh(new THREE.SphereGeometry(1, 32, 16), this.material);
    this.mesh.name = 'sky';
    this.mesh.frustumCulled = false;
    this.mesh.renderOrder = -1;
  }
}

/**
 * The sky's cube and the ground's texture (a 2.5 m tile, repeated) under `base`, the page's
 * `env/` (assets/env, copied there by web/page/build.mjs).
 */
export async function loadEnvironment(base) {
  const [cube, ground] = await Promise.all([loadSkyCube(base), new THREE.TextureLoader().loadAsync(new URL('ground.png', base).href)]);
  ground.colorSpace = THREE.SRGBColorSpace;
  ground.wrapS = ground.wrapT = THREE.RepeatWrapping;
  ground.anisotropy = 4;
  return { cube, ground };
}

/** The plain sky's colour where grove's sky has not loaded. */
const PLAIN_SKY = new THREE.Color(0x9cc3e6);

/**
 * The sky of the world shown (a feature of the view: view/features.mjs): grove's sky behind VR
 * and the preview, turned with the simulation's frame, and the sky's uniforms (the haze) from
 * the frame's snapshot; nothing in AR, where the room is seen, nor where the view draws the
 * trees alone (`view.background` false).
 */
export class SkyFeature {
  constructor(view) {
    this.view = view;
    this.sky = null; // the Sky, made once the environment is there
  }

  update(s) {
    const { view } = this;
    const cube = view.env?.cube ?? null;
    if (cube && !this.sky) {
      this.sky = new Sky(cube);
      view.simRoot.add(this.sky.mesh);
    }
    const shown = Boolean(s.world && !s.world.ar);
    if (this.sky) this.sky.mesh.visible = shown && view.background;
    view.scene.background = shown && view.background && !this.sky ? PLAIN_SKY : null;
    updateSky((s.snap ?? s.world?.snapshot)?.light, shown ? cube : null, view.simRoot);
  }
}
