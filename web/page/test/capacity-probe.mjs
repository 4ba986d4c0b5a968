// The browser side of capacity.test.mjs, bundled around the still page (web/page/still.mjs) by
// render.mjs's openStill: a model's stage drawn by the page's own view with no tree, its one
// tree, and that tree repeated where it stands (every copy in the camera's and the sun's view, so
// none is culled); a mix of models on one stage; and a model with its far model at chosen sizes
// on screen; with three.js's count of what each frame drew (renderer.info.render: draw calls and
// triangles, the sun's shadow map included), with the page's shadows on and off (off:
// `quality=low`, draw/renderer.mjs).

import * as THREE from 'three';
import { Models } from '../draw/world.mjs';
import { setUp, show, stage } from '../still.mjs';

/** The stage of `model` (a URL) without its sim: { models, snap, ground }. */
async function staged(model, width, height) {
  const { models, sim } = await stage(model, { aspect: width / height });
  try {
    return { models, snap: sim.snapshot(), ground: sim.ground() };
  } finally {
    sim.free();
  }
}

/** Each of `snaps` drawn with the shadows on, then off: [{ shadows, at, calls, triangles }]. */
function draw(renderer, models, ground, snaps, width, height) {
  const was = renderer.shadowMap.enabled;
  const out = [];
  try {
    for (const shadows of [true, false]) {
      renderer.shadowMap.enabled = shadows;
      snaps.forEach((snap, at) => {
        const { scene, camera } = show({ models, snap, ground, width, height });
        renderer.render(scene, camera);
        const { calls, triangles } = renderer.info.render;
        out.push({ shadows, at, calls, triangles });
      });
    }
  } finally {
    renderer.shadowMap.enabled = was;
  }
  return out;
}

/** [{ shadows, trees, calls, triangles }] for each of `counts` trees of `model`, shadows on then off. */
window.capacity = async ({ model, counts, width = 64, height = 48 }) => {
  const { renderer } = await setUp();
  const { models, snap, ground } = await staged(model, width, height);
  const [tree] = snap.trees;
  const snaps = counts.map((n) => ({
    ...snap,
    trees: Array.from({ length: n }, (_, i) => ({ ...tree, id: tree.id + i })),
  }));
  return draw(renderer, models, ground, snaps, width, height).map(({ at, ...f }) => ({ ...f, trees: counts[at] }));
};

/**
 * `mix` ({ name: count }) trees of the models `${dir}${name}.gltf` (`dir` a URL under /model/)
 * standing where the stage of the first one stands its tree: [{ shadows, calls, triangles }].
 */
window.mix = async ({ dir, mix, width = 64, height = 48 }) => {
  const { renderer } = await setUp();
  const names = Object.keys(mix);
  const { snap, ground } = await staged(`${dir}${names[0]}.gltf`, width, height);
  const models = new Models(dir);
  await models.load(names);
  const [tree] = snap.trees;
  const trees = names.flatMap((name) => Array.from({ length: mix[name] }, () => ({ ...tree, model: name })));
  trees.forEach((t, i) => (t.id = tree.id + i));
  return draw(renderer, models, ground, [{ ...snap, trees }], width, height).map(({ at, ...f }) => f);
};

/**
 * `near` and its far model `far` (URLs under /model/, far given as the catalogue gives it), one
 * tree of `near` moved along the line from the eye to where its stage stands it until its
 * bounding sphere covers each of `pixels` on screen (the page's view: its pixels per radian):
 * [{ shadows, pixels, calls, triangles }], and `zero`: the same frames without a tree.
 */
window.levels = async ({ near, far, pixels, width = 64, height = 48 }) => {
  const { renderer, view } = await setUp();
  const { snap, ground } = await staged(near, width, height);
  const models = new Models('/model/');
  await models.load(['near'], { near, far }, { near: 'far' });
  const box = models.bounds('near');
  const r = Math.hypot(...['x', 'y', 'z'].map((k) => Math.max(Math.abs(box.min[k]), Math.abs(box.max[k]))));
  show({ models, snap, ground, width, height });
  const eye = new THREE.Vector3().fromArray(snap.head.position);
  const [tree] = snap.trees;
  const along = new THREE.Vector3().fromArray(tree.position).sub(eye).normalize();
  const snaps = pixels.map((p) => {
    const d = (2 * r * tree.scale * view.pixelsPerRadian) / p;
    return { ...snap, trees: [{ ...tree, model: 'near', position: eye.clone().addScaledVector(along, d).toArray() }] };
  });
  const frames = draw(renderer, models, ground, [...snaps, { ...snap, trees: [] }], width, height);
  return frames.map(({ at, ...f }) => ({ ...f, pixels: pixels[at] ?? 0 }));
};
