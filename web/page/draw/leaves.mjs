// Foliage level of detail as grove's renderer draws it (src/render/trees/lod.rs, after Cook et
// al., "Stochastic Simplification of Aggregate Detail"): an alpha-clipped primitive's triangles
// are grouped into leaves, shuffled in the order grove shuffles them (seeded by the model's file
// name, SplitMix64's finaliser); each vertex carries its leaf's centre and rank. A tree far
// enough that its leaves would cover fewer than `leafPixels` pixels keeps the share `keep` of
// them, each grown so that the crown keeps its area (LEAF_GLSL's leaf_scale, trees.wgsl's
// twin), and the sun's shadow map keeps no more than 4 × 4 texels a leaf can show
// (src/render/trees/views.rs).

import * as THREE from 'three';

/** A primitive needs at least this many leaves to be simplified (lod.rs MIN_LEAVES). */
const MIN_LEAVES = 16;
/** The smallest keep fraction (lod.rs MIN_KEEP). */
const MIN_KEEP = 1 / 32;
/** grove's default smallest area, pixels, a drawn leaf should cover (RenderOptions::leaf_pixels). */
export const LEAF_PIXELS = 32;
/** The smallest area, in shadow-map texels, of a leaf drawn into the shadow map (views.rs). */
export const SHADOW_LEAF_TEXELS = 16;

const U64 = (1n << 64n) - 1n;

/** SplitMix64's finaliser (src/render/mix.rs). */
function mix(z) {
  z = ((z ^ (z >> 30n)) * 0xbf58476d1ce4e5b9n) & U64;
  z = ((z ^ (z >> 27n)) * 0x94d049bb133111ebn) & U64;
  return z ^ (z >> 31n);
}

/** The shuffle's seed of a model: FNV-1a of its file name's stem (src/render/trees/model.rs). */
export function modelSeed(name) {
  let h = 0xcbf29ce484222325n;
  for (const b of new TextEncoder().encode(name)) h = ((h ^ BigInt(b)) * 0x100000001b3n) & U64;
  return h;
}

/** Marks every vertex of `geometry` as of a primitive that is not simplified (rank −1). */
export function unsimplified(geometry) {
  const leaf = new Float32Array(geometry.attributes.position.count * 4);
  for (let v = 3; v < leaf.length; v += 4) leaf[v] = -1;
  geometry.setAttribute('leaf', new THREE.BufferAttribute(leaf, 4));
}

/**
 * Groups `geometry`'s triangles into leaves (triangles sharing vertices), shuffles them with
 * `seed`, rewrites the index in rank order and adds the attribute `leaf` (centre, rank in 0..1;
 * rank −1 where the primitive is not simplified). Returns the mean leaf area, m², or 0.
 */
export function orderLeaves(geometry, seed) {
  const n = geometry.attributes.position.count;
  unsimplified(geometry);
  const leafAttr = geometry.attributes.leaf.array;
  const index = geometry.index?.array;
  if (!index || index.length < 3) return 0;
  const parent = Uint32Array.from({ length: n }, (_, i) => i);
  const find = (i) => {
    while (parent[i] !== i) {
      parent[i] = parent[parent[i]];
      i = parent[i];
    }
    return i;
  };
  for (let t = 0; t + 2 < index.length; t += 3) {
    const a = find(index[t]);
    for (const v of [index[t + 1], index[t + 2]]) {
      const b = find(v);
      if (a !== b) parent[b] = a;
    }
  }
  const leafOfRoot = new Map();
  const leaves = [];
  for (let t = 0; t + 2 < index.length; t += 3) {
    const r = find(index[t]);
    if (!leafOfRoot.has(r)) {
      leafOfRoot.set(r, leaves.length);
      leaves.push([]);
    }
    leaves[leafOfRoot.get(r)].push(t);
  }
  if (leaves.length < MIN_LEAVES) return 0;
  const keys = leaves.map((_, k) => mix(seed ^ mix(BigInt(k))));
  const order = leaves.map((_, k) => k).sort((a, b) => (keys[a] < keys[b] ? -1 : keys[a] > keys[b] ? 1 : a - b));
  const p = geometry.attributes.position;
  const out = new index.constructor(index.length);
  let o = 0;
  let total = 0;
  const [A, B, C] = [new THREE.Vector3(), new THREE.Vector3(), new THREE.Vector3()];
  order.forEach((k, rank) => {
    let [area, weights] = [0, 0];
    const centre = new THREE.Vector3();
    for (const t of leaves[k]) {
      A.fromBufferAttribute(p, index[t]);
      B.fromBufferAttribute(p, index[t + 1]);
      C.fromBufferAttribute(p, index[t + 2]);
      const w = 0.5 * new THREE.Vector3().subVectors(B, A).cross(new THREE.Vector3().subVectors(C, A)).length();
      area += w;
      weights += Math.max(w, 1e-12);
      centre.addScaledVector(A.add(B).add(C), Math.max(w, 1e-12) / 3);
    }
    centre.divideScalar(weights);
    total += area;
    const r = (rank + 0.5) / leaves.length;
    for (const t of leaves[k]) {
      for (let j = 0; j < 3; j++) {
        const v = index[t + j];
        out[o++] = v;
        leafAttr.set([centre.x, centre.y, centre.z, r], 4 * v);
      }
    }
  });
  geometry.setIndex(new THREE.BufferAttribute(out, 1));
  return total / leaves.length;
}

/**
 * The share of a tree's leaves to draw (lod.rs keep_fraction): a leaf of `leafArea` m² seen
 * from `distance` m at `pixelsPerRadian` should cover `leafPixels`; 1 where it does.
 */
export function keepFraction(leafArea, distance, pixelsPerRadian, leafPixels) {
  if (leafPixels <= 0 || !(leafArea > 0)) return 1;
  const perMetre = pixelsPerRadian / Math.max(distance, 0.01);
  return Math.min(Math.max((leafArea * perMetre * perMetre) / leafPixels, MIN_KEEP), 1);
}

/** Each vertex of a leaf moved towards its centre by leaf_scale (trees.wgsl's twin of lod.rs's). */
export const LEAF_GLSL = /* glsl */ `
attribute vec4 leaf;
float leaf_scale( float rank, float keep ) {
	if ( rank < 0.0 || keep >= 1.0 ) return 1.0;
	float weight = clamp( ( 2.0 * keep - rank ) / keep, 0.0, 1.0 );
	float over = max( 2.0 * keep - 1.0, 0.0 );
	float kept = keep + ( keep * keep - over * over ) / ( 2.0 * keep );
	return sqrt( weight / kept );
}
`;

/** The leaf scaling of `transformed` (model space), before the wind. */
export const LEAF_SCALE_GLSL = 'transformed = leaf.xyz + ( transformed - leaf.xyz ) * leaf_scale( leaf.w, treeKeep );';

/** Pixels per radian of a headset's eye (Quest 3: 1832 pixels over about 96° of height). */
export const EYE_PIXELS_PER_RADIAN = 825;

/**
 * The shares of a tree's leaves drawn, [camera's, shadow map's]: leaves of `area` m² (scaled
 * with the tree) at `distance` m from the eye (null: none, every leaf) and `pixelsPerRadian`,
 * and no more than the shadow map of `texelsPerMetre` can show.
 */
export function keeps(area, distance, pixelsPerRadian, texelsPerMetre) {
  const keep = distance === null ? 1 : keepFraction(area, distance, pixelsPerRadian, LEAF_PIXELS);
  return [keep, Math.min(keep, keepFraction(area, 1, texelsPerMetre, SHADOW_LEAF_TEXELS))];
}

/**
 * The leaves' level of detail (a feature of the view, view/features.mjs, after the trees and the
 * light): each tree draws the share of its leaves grove would draw at its distance from the head
 * (`view.pixelsPerRadian`), and its shadow no more than the shadow map can show.
 */
export class LeafDetail {
  constructor(view) {
    this.view = view;
  }

  update(s) {
    const snap = s.snap ?? s.world?.snapshot;
    if (!s.world || !snap) return;
    const { features, pixelsPerRadian } = this.view;
    const eye = snap.head ? new THREE.Vector3().fromArray(snap.head.position) : null;
    for (const { object } of features.world.trees.values()) {
      const area = (object.userData.leafArea ?? 0) * object.scale.x * object.scale.x;
      const distance = eye ? eye.distanceTo(object.position) : null;
      object.userData.wind?.setKeep(...keeps(area, distance, pixelsPerRadian, features.light.texelsPerMetre));
    }
  }
}
