// grove's shading model in three.js materials: what src/render/lighting.wgsl's `shade` and
// src/render/trees/trees.wgsl do, patched into three's standard (or physical) material so that
// its maps, vertex colours, shadows, environment map, alpha test and alpha-to-coverage stay
// three's own:
//
// - the sun: diffuse max(n·l, 0) plus, for leaves, translucency × max(−n·l, 0) (light through a
//   leaf lit from behind), and a Blinn-Phong highlight scaled by the specular map
//   (KHR_materials_specular's factor and texture alpha; 0.5 without one, as grove reads glTF);
// - the sky: its irradiance (the light probe, light.mjs) times the albedo, and a Fresnel-weighted
//   reflection of the environment only where the surface is glossy;
// - the sun's shadow looked up along the shading normal, as grove does;
// - two-sided leaves: the normal (with its normal map) is kept on back faces and only its
//   component along the face normal turned towards the viewer, as grove does, where three.js
//   (following glTF) reverses the whole normal, which darkens a crown whose leaf normals point
//   outwards;
// - the aerial perspective: beyond 40 m the sky's colour along the view ray mixed in by distance
//   (sky.mjs's groveHazeAt, per vertex as grove does);
// - grove's tone curve c / (1 + 0.15 c) instead of the renderer's tone mapping.
//
// The sun's DirectionalLight carries grove's direct light times π (three.js divides by π, grove
// does not), so three's own materials lit by it (the anchor ball, the controllers) see the same
// light. See docs/headset.md, "How the page draws trees".

import * as THREE from 'three';
import { SKY_GLSL, skyUniforms } from './sky.mjs';

/** How much light passes through an alpha-clipped leaf, as grove's renderer sets it (src/render/trees/model.rs). */
export const LEAF_TRANSLUCENCY = 0.35;

const PARS = /* glsl */ `
uniform float groveTranslucency;
uniform float groveSpecularScale;
float groveSpec;
#undef RE_Direct
#define RE_Direct RE_Direct_Grove
#undef RE_IndirectDiffuse
#define RE_IndirectDiffuse RE_IndirectDiffuse_Grove
#undef RE_IndirectSpecular
#define RE_IndirectSpecular RE_IndirectSpecular_Grove
void RE_Direct_Grove( const in IncidentLight directLight, const in vec3 geometryPosition, const in vec3 geometryNormal, const in vec3 geometryViewDir, const in vec3 geometryClearcoatNormal, const in PhysicalMaterial material, inout ReflectedLight reflectedLight ) {
	float ndl = dot( geometryNormal, directLight.direction );
	float diffuse = max( ndl, 0.0 ) + groveTranslucency * max( - ndl, 0.0 );
	vec3 h = normalize( directLight.direction + geometryViewDir );
	float shininess = mix( 128.0, 6.0, clamp( roughness, 0.0, 1.0 ) );
	float spec = groveSpec * 0.25 * pow( max( dot( geometryNormal, h ), 0.0 ), shininess ) * ( ndl > 0.0 ? 1.0 : 0.0 );
	reflectedLight.directDiffuse += directLight.color * RECIPROCAL_PI * material.diffuseContribution * diffuse;
	reflectedLight.directSpecular += directLight.color * RECIPROCAL_PI * spec;
}
void RE_IndirectDiffuse_Grove( const in vec3 irradiance, const in vec3 geometryPosition, const in vec3 geometryNormal, const in vec3 geometryViewDir, const in vec3 geometryClearcoatNormal, const in PhysicalMaterial material, inout ReflectedLight reflectedLight ) {
	reflectedLight.indirectDiffuse += irradiance * RECIPROCAL_PI * material.diffuseContribution;
}
void RE_IndirectSpecular_Grove( const in vec3 radiance, const in vec3 irradiance, const in vec3 clearcoatRadiance, const in vec3 geometryPosition, const in vec3 geometryNormal, const in vec3 geometryViewDir, const in vec3 geometryClearcoatNormal, const in PhysicalMaterial material, inout ReflectedLight reflectedLight ) {
	float glossy = groveSpec * ( 1.0 - roughness ) * ( 1.0 - roughness );
	if ( glossy > 0.02 ) {
		float fres = 0.04 + 0.96 * pow( 1.0 - max( dot( geometryNormal, geometryViewDir ), 0.0 ), 5.0 );
		reflectedLight.indirectSpecular += radiance * fres * glossy;
	}
}
`;

const SPEC = /* glsl */ `
#ifdef USE_SPECULAR
	groveSpec = specularIntensityFactor * groveSpecularScale;
#else
	groveSpec = 0.5 * groveSpecularScale;
#endif
`;

// Back faces of two-sided materials: the normal's component along the face normal (turned to the
// viewer) flipped, its tangential part kept (trees.wgsl's fs_main). vViewPosition points from the
// surface to the eye.
const BACK_FACES = /* glsl */ `
#ifdef DOUBLE_SIDED
	if ( ! gl_FrontFacing ) {
		vec3 groveNg = cross( dFdx( vViewPosition ), dFdy( vViewPosition ) );
		groveNg = dot( groveNg, groveNg ) > 1e-30 ? normalize( groveNg ) : normal;
		if ( dot( groveNg, vViewPosition ) < 0.0 ) groveNg = - groveNg;
		normal = normalize( normal - 2.0 * dot( normal, groveNg ) * groveNg );
	}
#endif
`;

// Alpha-to-coverage centred on the cutoff: half a pixel's alpha gradient either side of it, so
// that a leaf's edge lies where grove's alpha test puts it (three.js ramps from the cutoff up,
// which thins every leaf by half its antialiased edge).
const ALPHA_TEST = /* glsl */ `
#ifdef USE_ALPHATEST
	#ifdef ALPHA_TO_COVERAGE
	diffuseColor.a = clamp( ( diffuseColor.a - alphaTest ) / max( fwidth( diffuseColor.a ), 1e-4 ) + 0.5, 0.0, 1.0 );
	if ( diffuseColor.a == 0.0 ) discard;
	#else
	if ( diffuseColor.a < alphaTest ) discard;
	#endif
#endif
`;

/** grove's tone curve (lighting.wgsl's `tone`). */
const TONE = 'gl_FragColor.rgb = gl_FragColor.rgb / ( 1.0 + 0.15 * gl_FragColor.rgb );';

// The sun's shadow looked up where grove looks it up: at the fragment's world position moved
// along its shading normal (after the normal map and the back faces' turn) by the normal offset,
// where three.js moves it along the vertex normal.
const SHADOW_PARS = /* glsl */ `
varying vec3 vGroveWorld;
#if defined( USE_SHADOWMAP ) && NUM_DIR_LIGHT_SHADOWS > 0
	uniform mat4 directionalShadowMatrix[ NUM_DIR_LIGHT_SHADOWS ];
#endif
`;
const lightsBegin = THREE.ShaderChunk.lights_fragment_begin.replace(
  'vDirectionalShadowCoord[ i ] )',
  '( directionalShadowMatrix[ i ] * vec4( vGroveWorld + inverseTransformDirection( normal, viewMatrix ) * directionalLightShadow.shadowNormalBias, 1.0 ) ) )',
);

const normalBegin = THREE.ShaderChunk.normal_fragment_begin.replace(
  'float faceDirection = gl_FrontFacing ? 1.0 : - 1.0;',
  'float faceDirection = 1.0;',
);

for (const [name, chunk] of [
  ['lights_fragment_begin', lightsBegin],
  ['normal_fragment_begin', normalBegin],
]) {
  if (chunk === THREE.ShaderChunk[name])
    throw new Error(`grove shading: three.js's ${name} is not the one this page patches`);
}

// The vertex's world position (an InstancedMesh's instance placed by its matrix).
const GROVE_WORLD = /* glsl */ `
#ifdef USE_INSTANCING
	vGroveWorld = ( modelMatrix * instanceMatrix * vec4( transformed, 1.0 ) ).xyz;
#else
	vGroveWorld = ( modelMatrix * vec4( transformed, 1.0 ) ).xyz;
#endif`;

function patch(source, marker, replacement) {
  if (!source.includes(marker)) throw new Error(`grove shading: three.js's shader has no ${marker}`);
  return source.replace(marker, replacement);
}

/**
 * Makes a MeshStandardMaterial (or MeshPhysicalMaterial) shade as grove does. `translucency`:
 * how much light passes through (leaves: LEAF_TRANSLUCENCY; 0 for bark and ground);
 * `specular`: a factor on the highlight and reflection (0 for the ground, whose highlight grove
 * leaves out). `vertex(shader)`, if given, patches the vertex shader too (the wind, wind.mjs).
 * Returns the material.
 */
export function groveShading(material, { translucency = 0, specular = 1, vertex = null, key = '' } = {}) {
  const uniforms = { groveTranslucency: { value: translucency }, groveSpecularScale: { value: specular } };
  material.userData.grove = uniforms;
  material.onBeforeCompile = (shader) => {
    Object.assign(shader.uniforms, uniforms);
    let f = shader.fragmentShader;
    f = patch(f, '#include <lights_physical_pars_fragment>', `#include <lights_physical_pars_fragment>\n${PARS}`);
    f = patch(f, '#include <normal_fragment_begin>', normalBegin);
    f = patch(f, '#include <normal_fragment_maps>', `#include <normal_fragment_maps>\n${BACK_FACES}`);
    f = patch(f, '#include <lights_physical_fragment>', `#include <lights_physical_fragment>\n${SPEC}`);
    f = patch(f, '#include <alphatest_fragment>', ALPHA_TEST);
    f = patch(f, '#include <lights_fragment_begin>', lightsBegin);
    f = patch(
      f,
      '#include <tonemapping_fragment>',
      `gl_FragColor.rgb = mix( gl_FragColor.rgb, vGroveHaze.rgb, vGroveHaze.a );\n${TONE}`,
    );
    shader.fragmentShader = `varying vec4 vGroveHaze;\n${SHADOW_PARS}\n${f}`;
    Object.assign(shader.uniforms, skyUniforms);
    const v = patch(
      shader.vertexShader,
      '#include <fog_vertex>',
      `#include <fog_vertex>\n${GROVE_WORLD}\n\tvGroveHaze = groveHazeAt( vGroveWorld );`,
    );
    shader.vertexShader = `${SKY_GLSL}\nvarying vec4 vGroveHaze;\nvarying vec3 vGroveWorld;\n${v}`;
    vertex?.(shader);
  };
  material.customProgramCacheKey = () => `grove-shading${key}`;
  material.needsUpdate = true;
  return material;
}
