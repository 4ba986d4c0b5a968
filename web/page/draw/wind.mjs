// Wind: every tree vertex displaced from its model's `_WIND` channels (height to root, distance
// to trunk, distance to branch, branch phase) as grove's renderer displaces it
// (src/render/trees/wind.wgsl, whose CPU reference is systems/src/wind_model/), in the main pass
// and in the shadow pass alike, from the snapshot's wind (`snap.wind`: grove's WindParams at the
// tick) and each tree's own state (`tree.wind`: its trunk's lean, gain and phase).
//
// WIND_GLSL is wind.wgsl's functions in GLSL, operation for operation (names without the
// `wind_` prefix of WGSL kept with it); web/page/test/wind.test.mjs holds it against grove's CPU
// reference within a millimetre on sample vertices at three ticks.

import * as THREE from 'three';
import { LEAF_GLSL, LEAF_SCALE_GLSL } from './leaves.mjs';

export const WIND_GLSL = /* glsl */ `
uniform vec2 windDirection;
uniform float windStrength;
uniform float windGust;
uniform float windDensity;
uniform float windNoiseSpeed;
uniform float windNoiseAmplitude;
uniform float windTime;
uniform float windTrunkStiffness;
uniform float windBranchStiffness;
uniform float windBranchFrequency;
uniform float windLeafFlutter;
uniform float windLeafFrequency;
uniform int windModel;
const float WIND_TAU = 6.2831855;
const float WIND_INV_TAU = 0.15915494;
const uint WIND_NOISE_SEED = 0x67726f76u;
uint wind_hash( uint x ) {
	x = x ^ ( x >> 16u );
	x = x * 0x7feb352du;
	x = x ^ ( x >> 15u );
	x = x * 0x846ca68bu;
	x = x ^ ( x >> 16u );
	return x;
}
uint wind_lattice_hash( ivec3 i ) {
	uint hz = wind_hash( uint( i.z ) + WIND_NOISE_SEED );
	uint hy = wind_hash( uint( i.y ) + hz );
	return wind_hash( uint( i.x ) + hy );
}
float wind_grad( uint h_in, vec3 p ) {
	uint h = h_in & 15u;
	float u = h < 8u ? p.x : p.y;
	float v = h < 4u ? p.y : ( ( h == 12u || h == 14u ) ? p.x : p.z );
	float a = ( h & 1u ) == 0u ? u : - u;
	float b = ( h & 2u ) == 0u ? v : - v;
	return a + b;
}
vec3 wind_fade( vec3 t ) {
	return t * t * t * ( t * ( t * 6.0 - 15.0 ) + 10.0 );
}
float wind_perlin3( vec3 p ) {
	vec3 fl = floor( p );
	ivec3 i = ivec3( fl );
	vec3 f = p - fl;
	vec3 u = wind_fade( f );
	float n000 = wind_grad( wind_lattice_hash( i ), f );
	float n100 = wind_grad( wind_lattice_hash( i + ivec3( 1, 0, 0 ) ), f - vec3( 1.0, 0.0, 0.0 ) );
	float n010 = wind_grad( wind_lattice_hash( i + ivec3( 0, 1, 0 ) ), f - vec3( 0.0, 1.0, 0.0 ) );
	float n110 = wind_grad( wind_lattice_hash( i + ivec3( 1, 1, 0 ) ), f - vec3( 1.0, 1.0, 0.0 ) );
	float n001 = wind_grad( wind_lattice_hash( i + ivec3( 0, 0, 1 ) ), f - vec3( 0.0, 0.0, 1.0 ) );
	float n101 = wind_grad( wind_lattice_hash( i + ivec3( 1, 0, 1 ) ), f - vec3( 1.0, 0.0, 1.0 ) );
	float n011 = wind_grad( wind_lattice_hash( i + ivec3( 0, 1, 1 ) ), f - vec3( 0.0, 1.0, 1.0 ) );
	float n111 = wind_grad( wind_lattice_hash( i + ivec3( 1, 1, 1 ) ), f - vec3( 1.0, 1.0, 1.0 ) );
	float x00 = mix( n000, n100, u.x );
	float x10 = mix( n010, n110, u.x );
	float x01 = mix( n001, n101, u.x );
	float x11 = mix( n011, n111, u.x );
	return mix( mix( x00, x10, u.y ), mix( x01, x11, u.y ), u.z );
}
float wind_noise_at( vec3 v0, vec2 dir, float density, float speed, float t ) {
	float drift = speed * t;
	vec3 p = vec3( v0.x - dir.x * drift, v0.y, v0.z - dir.y * drift );
	return clamp( 0.5 + 0.5 * wind_perlin3( density * p ), 0.0, 1.0 );
}
float wind_wave( float cycles ) {
	float u = cycles + 0.5;
	float f = u - floor( u );
	return sin( WIND_TAU * ( f - 0.5 ) );
}
vec3 wind_displace( vec3 v0, vec4 ch, vec2 bend, float gain, float tree_phase ) {
	if ( windModel == 0 ) {
		float s = windStrength * windGust * gain * windNoiseAmplitude;
		float n = wind_noise_at( v0, windDirection, windDensity, windNoiseSpeed, windTime );
		float k = s * ( ch.x + ch.y ) * ( n - 0.5 );
		return vec3( v0.x + windDirection.x * k, v0.y, v0.z + windDirection.y * k );
	}
	float h = ch.x;
	float r = ch.y;
	float b = ch.z;
	float phi = ch.w + tree_phase * WIND_INV_TAU;
	float s = windStrength * windGust * gain;
	float t = windTime;
	float lean = h * h / windTrunkStiffness;
	vec3 trunk = vec3( bend.x * lean, 0.0, bend.y * lean );
	float bob = s * ( r * r / windBranchStiffness ) * wind_wave( windBranchFrequency * t + phi );
	vec3 branch = vec3( 0.4 * windDirection.x * bob, bob, 0.4 * windDirection.y * bob );
	float a = s * windLeafFlutter * b;
	float f = windLeafFrequency;
	vec3 leaf = vec3( a * wind_wave( f * t + phi ), a * wind_wave( 1.37 * f * t + phi + 0.25 ), a * wind_wave( 1.71 * f * t + phi + 0.5 ) );
	return v0 + trunk + branch + leaf;
}
vec3 wind_rotate_y( vec3 v, float yaw ) {
	float c = cos( yaw );
	float s = sin( yaw );
	return vec3( c * v.x + s * v.z, v.y, - s * v.x + c * v.z );
}
`;

// A tree's own values, and the displacement of `transformed` (model space) by the wind in the
// simulation's frame: the leaf grown or shrunk by its level of detail (leaves.mjs), the rest
// position placed as the tree stands (trees.wgsl's world_position), displaced, and the
// difference turned back into the model's frame. A lone tree (a Mesh) has them as uniforms; the
// trees of an InstancedMesh (forest.mjs) as instanced attributes, packed in three vec4s as
// TREE_ATTRIBUTES lists them, read under the same names by the same code; the sun's shadow map
// (GROVE_SHADOW) reads its own share of the leaves.
export const TREE_GLSL = /* glsl */ `
#ifdef USE_INSTANCING
attribute vec4 treePlace;
attribute vec4 treeSway;
attribute vec4 treeLevel;
#define treeOrigin treePlace.xyz
#define treeYaw treePlace.w
#define treeBend treeSway.xy
#define treeGain treeSway.z
#define treePhase treeSway.w
#define treeScale treeLevel.x
#ifdef GROVE_SHADOW
#define treeKeep treeLevel.z
#else
#define treeKeep treeLevel.y
#endif
#else
uniform vec3 treeOrigin;
uniform float treeYaw;
uniform float treeScale;
uniform vec2 treeBend;
uniform float treeGain;
uniform float treePhase;
uniform float treeKeep;
#endif
attribute vec4 _wind;
${LEAF_GLSL}`;

/** The instanced attributes of a tree (TREE_GLSL), four floats each: TreeWind's `pack` writes them. */
export const TREE_ATTRIBUTES = ['treePlace', 'treeSway', 'treeLevel'];

export const DISPLACE_GLSL = /* glsl */ `
${LEAF_SCALE_GLSL}
{
	vec3 v0 = treeOrigin + wind_rotate_y( transformed * treeScale, treeYaw );
	vec3 d = wind_displace( v0, vec4( _wind.xyz * treeScale, _wind.w ), treeBend, treeGain, treePhase ) - v0;
	transformed += wind_rotate_y( d, - treeYaw ) / treeScale;
}
`;

/** The wind's uniforms, shared by every tree: set from each snapshot with `setWind`. */
export const windUniforms = {
  windDirection: { value: new THREE.Vector2(1, 0) },
  windStrength: { value: 0 },
  windGust: { value: 0 },
  windDensity: { value: 0 },
  windNoiseSpeed: { value: 0 },
  windNoiseAmplitude: { value: 0 },
  windTime: { value: 0 },
  windTrunkStiffness: { value: 5 },
  windBranchStiffness: { value: 20 },
  windBranchFrequency: { value: 0 },
  windLeafFlutter: { value: 0 },
  windLeafFrequency: { value: 0 },
  windModel: { value: 1 },
};

/** The snapshot's wind (grove's WindParams, field for field). */
export function setWind(p) {
  if (!p) return;
  const u = windUniforms;
  u.windDirection.value.set(p.direction[0], p.direction[1]);
  u.windStrength.value = p.strength;
  u.windGust.value = p.gust;
  u.windDensity.value = p.density;
  u.windNoiseSpeed.value = p.noise_speed;
  u.windNoiseAmplitude.value = p.noise_amplitude;
  u.windTime.value = p.time;
  u.windTrunkStiffness.value = p.trunk_stiffness;
  u.windBranchStiffness.value = p.branch_stiffness;
  u.windBranchFrequency.value = p.branch_frequency;
  u.windLeafFlutter.value = p.leaf_flutter;
  u.windLeafFrequency.value = p.leaf_frequency;
  u.windModel.value = p.model;
}

function inject(shader, uniforms, shadow = false) {
  Object.assign(shader.uniforms, windUniforms, uniforms);
  shader.vertexShader =
    `${shadow ? '#define GROVE_SHADOW\n' : ''}${WIND_GLSL}\n${TREE_GLSL}\n${shader.vertexShader}`.replace(
      '#include <begin_vertex>',
      `#include <begin_vertex>\n${DISPLACE_GLSL}`,
    );
}

/** The wind's vertex patch of a material shared by the trees of an InstancedMesh (forest.mjs). */
export const instancedVertex = (shader) => inject(shader, {});

/**
 * The depth material of the sun's shadow map: the tree's displacement (`uniforms`, a lone
 * tree's; none for an InstancedMesh's trees, whose values are attributes), and the depth bias of
 * grove's shadow pass (a slope of 1.5, src/render/trees/pipelines.rs; its constant of 2 is in
 * steps of grove's 16-bit shadow map, 512 of three's 24-bit one). `fragment(shader)`, if given,
 * patches the fragment shader too (forest.mjs's cross-fade).
 */
export function windDepthMaterial(uniforms = {}, fragment = null) {
  const m = new THREE.MeshDepthMaterial({ polygonOffset: true, polygonOffsetFactor: 1.5, polygonOffsetUnits: 512 });
  m.onBeforeCompile = (shader) => {
    inject(shader, uniforms, true);
    fragment?.(shader);
  };
  m.customProgramCacheKey = () => (fragment ? 'grove-wind-depth-faded' : 'grove-wind-depth');
  return m;
}

/** One tree's wind: its uniforms, the vertex patch for its materials, and its shadow's material. */
export class TreeWind {
  constructor() {
    this.uniforms = {
      treeOrigin: { value: new THREE.Vector3() },
      treeYaw: { value: 0 },
      treeScale: { value: 1 },
      treeBend: { value: new THREE.Vector2() },
      treeGain: { value: 0 },
      treePhase: { value: 0 },
      treeKeep: { value: 1 },
    };
    // The shadow map's own share of the leaves (leaves.mjs), the rest shared.
    this.shadowUniforms = { ...this.uniforms, treeKeep: { value: 1 } };
    this.key = '-wind';
    this.vertex = (shader) => inject(shader, this.uniforms);
  }

  /** The shares of the leaves the camera's view and the shadow map draw (leaves.mjs). */
  setKeep(keep, shadowKeep) {
    this.uniforms.treeKeep.value = keep;
    this.shadowUniforms.treeKeep.value = shadowKeep;
  }

  /** The tree as a snapshot has it (position, yaw, scale, and its `wind` state or none). */
  set(tree) {
    const u = this.uniforms;
    u.treeOrigin.value.fromArray(tree.position);
    u.treeYaw.value = tree.yaw;
    u.treeScale.value = tree.scale;
    u.treeBend.value.fromArray(tree.wind?.bend ?? [0, 0]);
    u.treeGain.value = tree.wind?.gain ?? 0;
    u.treePhase.value = tree.wind?.phase ?? 0;
  }

  /**
   * The tree's instanced attributes (TREE_ATTRIBUTES, in order) into `out` from `at` (12 floats):
   * `share`, levels.mjs's share of the tree's pixels kept by the level drawn, last; `keep`, the
   * shares of the leaves [camera's, shadow map's] where not this tree's own (its far model's).
   */
  pack(out, at, share = 0, keep = null) {
    const u = this.uniforms;
    const o = u.treeOrigin.value;
    const b = u.treeBend.value;
    out[at] = o.x;
    out[at + 1] = o.y;
    out[at + 2] = o.z;
    out[at + 3] = u.treeYaw.value;
    out[at + 4] = b.x;
    out[at + 5] = b.y;
    out[at + 6] = u.treeGain.value;
    out[at + 7] = u.treePhase.value;
    out[at + 8] = u.treeScale.value;
    out[at + 9] = keep ? keep[0] : u.treeKeep.value;
    out[at + 10] = keep ? keep[1] : this.shadowUniforms.treeKeep.value;
    out[at + 11] = share;
  }

  /** The depth material of the sun's shadow map (windDepthMaterial) with this tree's values. */
  depthMaterial() {
    return windDepthMaterial(this.shadowUniforms);
  }
}

/** The wind's state of the frame's snapshot, for every tree (a feature of the view: view/features.mjs). */
export class Wind {
  update(s) {
    setWind((s.snap ?? s.world?.snapshot)?.wind);
  }
}
