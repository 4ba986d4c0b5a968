// One still picture drawn by the headset page's own view (view/view.mjs and its features:
// draw/world.mjs, trees.mjs, ground.mjs, shading.mjs, light.mjs, sky.mjs, wind.mjs, leaves.mjs),
// bundled by web/page/render.mjs for headless Chromium and never part of the page itself. The model stands on grove's model stage
// as `grove render --model` frames it: the WebAssembly module builds the very stage
// (grove_systems::stage::model_stage, with the study's wind for a tick), so the camera, the sun
// and the wind are the native renderer's numbers, not copies of them.
//
// With `from` (metres) the camera is a walker's instead (grove_systems::stage::walker_view: eye
// height, looking at 45 % of the model's top, the view of docs/species.md's sheets).
//
// window.still.render({ model, width, height, tick, background, from }) resolves to { pixels (RGBA,
// straight alpha, top row first, base64), width, height, camera, light, wind, trees }; tests
// bundle their own entries around `setUp`, `stage` and `show` (web/page/test/wind-probe.mjs,
// capacity-probe.mjs).

import * as THREE from 'three';
import { loadGrove } from '../sim/grove-sim.mjs';
import { Models } from './draw/world.mjs';
import { loadEnvironment } from './draw/sky.mjs';
import { View } from './view/view.mjs';

let grove = null;
let env = null;
let view = null;
let renderer = null;

const views = new Map();

/**
 * The module, the sky and ground, and the page's view (`antialias`: multisampled, as the page
 * draws; off, one sample a pixel as grove's renderer draws), made once.
 */
export async function setUp({ antialias = true } = {}) {
  grove ??= await loadGrove(new URL('/grove_sim.wasm', location.href));
  env ??= await loadEnvironment(new URL('/env/', location.href));
  if (!views.has(antialias)) {
    const canvas = document.createElement('canvas');
    document.body.append(canvas);
    const v = new View(canvas, { models: null, antialias, preserve: true });
    v.renderer.setPixelRatio(1);
    v.setEnvironment(env);
    views.set(antialias, v);
  }
  view = views.get(antialias);
  renderer = view.renderer;
  return { grove, env, renderer, view };
}

/**
 * `model` (a URL) loaded as the stage's model ('model'), and its stage in the module, framed
 * for `aspect` (or, with `from`, seen by a walker `from` metres away), stepped `tick` ticks in
 * the study's wind (null: calm, tick 0): { models, sim }. Free the sim.
 */
export async function stage(model, { aspect, tick = null, antialias = true, from = null }) {
  await setUp({ antialias });
  const models = new Models('/model/', { antialias });
  await models.load(['model'], { model });
  const box = models.bounds('model');
  const sim = grove.createSim({
    stage: {
      min: box.min.toArray(),
      max: box.max.toArray(),
      aspect,
      wind: tick !== null,
      ...(from === null ? {} : { from }),
    },
  });
  for (let i = 0; i < (tick ?? 0); i++) sim.step();
  return { models, sim };
}

/** The drawn frame's pixels, top row first (RGBA as the canvas holds them). */
function readPixels(width, height) {
  const gl = renderer.getContext();
  const px = new Uint8Array(width * height * 4);
  gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, px);
  const out = new Uint8Array(px.length);
  for (let y = 0; y < height; y++)
    out.set(px.subarray((height - 1 - y) * width * 4, (height - y) * width * 4), y * width * 4);
  return out;
}

/**
 * The scene drawn alone with its coverage as alpha: drawn over black and over white, a pixel's
 * coverage is one less the difference (the multisampled leaves' alpha-to-coverage writes their
 * colour to the covered samples only, whatever alpha they write), and its colour the one over
 * black divided by the coverage.
 */
function drawAlone(scene, camera, width, height) {
  const over = (colour) => {
    renderer.setClearColor(colour, 1);
    renderer.render(scene, camera);
    return readPixels(width, height);
  };
  const [black, white] = [over(0x000000), over(0xffffff)];
  const out = new Uint8Array(black.length);
  for (let i = 0; i < out.length; i += 4) {
    const gap = (white[i] - black[i] + white[i + 1] - black[i + 1] + white[i + 2] - black[i + 2]) / 3;
    const a = Math.min(Math.max(1 - gap / 255, 0), 1);
    for (let c = 0; c < 3; c++) out[i + c] = a > 0 ? Math.min(255, Math.round(black[i + c] / a)) : 0;
    out[i + 3] = Math.round(a * 255);
  }
  return out;
}

function base64(bytes) {
  let s = '';
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(s);
}

/**
 * The view brought to `snap` (the stage's snapshot, or one a test makes of it) with `models` and
 * the stage's `ground`, its camera framed for `width` × `height`: { scene, camera } to draw.
 */
export function show({ models, snap, ground, width, height, background = 'sky' }) {
  renderer.setSize(width, height, false);
  // The frame's state as the flow hands it to the view (view/features.mjs): a world and its
  // snapshot, nothing of a run's interaction.
  const state = {
    state: 'task',
    world: { ar: false, ground, snapshot: snap },
    snap,
    live: null,
    xr: null,
    ray: null,
    eye: null,
    hud: null,
    panel: false,
  };
  Object.assign(view, {
    models,
    background: background !== 'transparent',
    pixelsPerRadian: height / 2 / Math.tan(snap.fov_y / 2),
  });
  view.update(state);
  view.placeCamera(snap);
  const { camera, scene } = view;
  Object.assign(camera, { aspect: width / height, near: 0.05, far: 600 });
  camera.updateProjectionMatrix();
  return { scene, camera };
}

/**
 * Draws `model` (a URL of a glTF file) on its stage at `width` × `height`, after `tick` ticks of
 * the study's wind (null: calm, tick 0), over the stage's sky and ground or (background
 * 'transparent') alone; with `from`, as a walker sees it from that many metres.
 */
async function render({ model, width, height, tick = null, background = 'sky', antialias = true, from = null }) {
  const { models, sim } = await stage(model, { aspect: width / height, tick, antialias, from });
  try {
    const snap = sim.snapshot();
    const { camera, scene } = show({ models, snap, ground: sim.ground(), width, height, background });
    let pixels;
    if (background === 'transparent') pixels = drawAlone(scene, camera, width, height);
    else {
      renderer.setClearColor(0x000000, 1);
      renderer.render(scene, camera);
      pixels = readPixels(width, height);
    }
    const info = { calls: renderer.info.render.calls, triangles: renderer.info.render.triangles };
    return {
      pixels: base64(pixels),
      width,
      height,
      tick: snap.tick,
      camera: snap.head,
      fov_y: snap.fov_y,
      light: snap.light,
      wind: snap.wind,
      trees: snap.trees,
      info,
    };
  } finally {
    sim.free();
  }
}

/**
 * Draws a scene (its file's `name` and `text`) as the module builds it, after `tick` ticks, at
 * its own camera (the head, as `grove render --scene` draws it), with its trees' models from
 * `/models/NAME.gltf`. With a recording's `header` line and its event lines (`events`), the world
 * that recording made by `tick`, at the participant's head (as `grove render --replay FILE
 * --tick T`); `text` is then needed only for a scene that is not built in.
 */
async function renderScene({ name, text, width, height, tick = 0, header = null, events = [] }) {
  await setUp();
  const sim = grove.createSim(header ? { header, scene_text: text } : { scene: name, scene_text: text });
  try {
    // A recording's events, each queued as its tick comes (they apply at the start of it).
    let k = 0;
    for (let i = 0; i < tick; i++) {
      while (k < events.length && events[k].tick <= sim.tick) sim.push(events[k++]);
      sim.step();
    }
    const snap = sim.snapshot();
    const models = new Models('/models/');
    await models.load([...new Set(snap.trees.map((t) => t.model))]);
    const { camera, scene } = show({ models, snap, ground: sim.ground(), width, height });
    renderer.setClearColor(0x000000, 1);
    renderer.render(scene, camera);
    const pixels = base64(readPixels(width, height));
    return { pixels, width, height, tick: snap.tick, trees: snap.trees.length, hash: sim.hash() };
  } finally {
    sim.free();
  }
}

window.still = { render, renderScene, ready: true };
