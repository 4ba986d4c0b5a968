// The browser side of capacity.test.mjs, bundled around the still page (web/page/still.mjs) by
// render.mjs's openStill: a model's stage drawn by the page's own view with its one tree, then
// with that tree repeated where it stands (every copy in the camera's and the sun's view, so
// none is culled), and three.js's count of what each frame drew (renderer.info.render: draw
// calls and triangles, the sun's shadow map included), with the page's shadows on and off (off:
// `quality=low`, draw/renderer.mjs).

import { setUp, show, stage } from '../still.mjs';

/** [{ shadows, trees, calls, triangles }] for each of `counts` trees of `model`, shadows on then off. */
window.capacity = async ({ model, counts, width = 64, height = 48 }) => {
  const { renderer } = await setUp();
  const { models, sim } = await stage(model, { aspect: width / height });
  let snap;
  let ground;
  try {
    snap = sim.snapshot();
    ground = sim.ground();
  } finally {
    sim.free();
  }
  const [tree] = snap.trees;
  const was = renderer.shadowMap.enabled;
  const out = [];
  try {
    for (const shadows of [true, false]) {
      renderer.shadowMap.enabled = shadows;
      for (const n of counts) {
        const trees = Array.from({ length: n }, (_, i) => ({ ...tree, id: tree.id + i }));
        const { scene, camera } = show({ models, snap: { ...snap, trees }, ground, width, height });
        renderer.render(scene, camera);
        const { calls, triangles } = renderer.info.render;
        out.push({ shadows, trees: n, calls, triangles });
      }
    }
  } finally {
    renderer.shadowMap.enabled = was;
  }
  return out;
};
