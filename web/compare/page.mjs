// The comparison page (bundled by web/compare/compare.mjs, never part of the headset page): grove's
// trees (glTF written by `grove trees generate`) and ez-tree's presets drawn alike by the headset
// page's own drawing (web/page/still.mjs, as web/page/render.mjs draws: the page's View with its
// shading, light, environment, sky, ground, shadows and leaf level of detail) on grove's model
// stage seen by a walker (grove_systems::stage::walker_view through the module: eye height,
// looking at 45 % of the height, the sun 40° up). grove's trees are loaded as the headset page
// loads them (web/page/draw/trees.mjs's Models: grove's mips, leaves shuffled as grove shuffles
// them); ez-tree's keep their textures and colours, their Phong materials turned into the
// standard ones the page's shading patches (its leaves translucent as grove's). The framing check
// draws silhouettes with a camera of its own ('mask', 'profile'). The page only exposes functions
// on `window.compare`; node drives it (docs/species.md).

import * as THREE from 'three';
import { Tree } from '@dgreenheck/ez-tree';
import { LeafDetail } from '../page/draw/leaves.mjs';
import { Models } from '../page/draw/trees.mjs';
import { TreeWind } from '../page/draw/wind.mjs';
import { setUp, show } from '../page/still.mjs';

let renderer = null;

function stage(width, height) {
  if (!renderer) {
    const canvas = document.createElement('canvas');
    document.body.appendChild(canvas);
    renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    renderer.shadowMap.enabled = true;
    renderer.shadowMap.type = THREE.PCFSoftShadowMap;
  }
  renderer.setPixelRatio(1);
  renderer.setSize(width, height, false);
  return renderer;
}

/** A tree's box, in its parent's frame, from its meshes' geometry (not their bounding spheres). */
function box(object) {
  object.updateMatrixWorld(true);
  return new THREE.Box3().setFromObject(object, true);
}

/**
 * Scales `object` uniformly to `height` metres and stands it on the ground with its box's middle
 * over the origin; returns its box afterwards.
 */
function standAt(object, height) {
  const b = box(object);
  const s = height / (b.max.y - b.min.y);
  object.scale.multiplyScalar(s);
  const c = box(object);
  object.position.x -= (c.min.x + c.max.x) / 2;
  object.position.z -= (c.min.z + c.max.z) / 2;
  object.position.y -= c.min.y;
  return box(object);
}

const trees = new Map();

/** Keeps `tree` as `handle`, freeing the GPU buffers of the tree it replaces. */
function keep(handle, tree) {
  trees.get(handle)?.traverse((o) => {
    if (o.isMesh) o.geometry.dispose();
  });
  trees.set(handle, tree);
}

/**
 * Loads one of grove's glTF trees from `url` as the headset page does (its materials kept; no
 * alpha-to-coverage, whose part-covered pixels the silhouette's cut at half coverage would drop);
 * the handle names it for `render` and `stand`. `render` sets its leaves' level of detail.
 */
async function groveTree(handle, url) {
  const models = new Models('', { antialias: false });
  await models.load([handle], { [handle]: url });
  const model = models.models.get(handle);
  const wind = new TreeWind();
  const tree = new THREE.Group();
  tree.add(model);
  tree.userData.wind = wind;
  tree.userData.leafArea = model.userData.leafArea;
  tree.traverse((o) => {
    if (!o.isMesh) return;
    o.material.onBeforeCompile = wind.vertex;
    o.customDepthMaterial = wind.depthMaterial();
  });
  keep(handle, tree);
  return measure(tree);
}

/**
 * The share of grove's leaves `tree` draws seen from `cam` in a frame `height` pixels tall, and
 * in a shadow map of `texelsPerMetre` (LeafDetail, as the headset page sets it each frame).
 */
function leafDetail(tree, cam, height, texelsPerMetre = 0) {
  if (!tree.userData.wind) return;
  const pixelsPerRadian = height / 2 / Math.tan(THREE.MathUtils.degToRad(cam.fov) / 2);
  const view = {
    pixelsPerRadian,
    features: { world: { trees: new Map([[0, { object: tree }]]) }, light: { texelsPerMetre } },
  };
  new LeafDetail(view).update({ world: {}, snap: { head: { position: cam.position.toArray() } } });
}

/** Generates one of ez-tree's presets (by its name in TreePreset); the handle names it for `render` and `stand`. */
function ezTree(handle, preset) {
  const ez = new Tree();
  ez.loadPreset(preset);
  ez.generate();
  ez.traverse((o) => {
    if (o.isMesh) {
      o.castShadow = true;
      o.receiveShadow = true;
    }
  });
  const tree = new THREE.Group();
  tree.add(ez);
  keep(handle, tree);
  return measure(tree);
}

function measure(tree) {
  const b = box(tree);
  return { min: b.min.toArray(), max: b.max.toArray(), triangles: triangles(tree) };
}

/** Tree `handle` scaled to `height` metres and stood on the ground over the origin; its box. */
function stand(handle, height) {
  standAt(trees.get(handle), height);
  return measure(trees.get(handle));
}

function triangles(object) {
  let n = 0;
  object.traverse((o) => {
    if (o.isMesh) n += (o.geometry.index ? o.geometry.index.count : o.geometry.attributes.position.count) / 3;
  });
  return n;
}

function camera(view, aspect) {
  const cam = new THREE.PerspectiveCamera(view.fov, aspect, 0.05, 500);
  cam.position.set(0, view.eye, view.distance);
  cam.lookAt(0, view.target, 0);
  cam.updateMatrixWorld(true);
  return cam;
}

/**
 * The orthographic camera of `view` for the framing check: level, at the same scale as `view`'s
 * camera at the trees' distance (metres per pixel: 2 d tan(fov / 2) / height) and with the ground
 * under the trunk (the origin) on the same row as in `view`'s picture, so a point's row depends on
 * its height alone, not on how near the camera it stands.
 */
function profileCamera(view, aspect) {
  const foot = new THREE.Vector3(0, 0, 0).project(camera(view, aspect)).y;
  const half = view.distance * Math.tan(THREE.MathUtils.degToRad(view.fov) / 2);
  const cam = new THREE.OrthographicCamera(-half * aspect, half * aspect, half, -half, 0.05, 500);
  cam.position.set(0, -foot * half, view.distance);
  cam.lookAt(0, -foot * half, 0);
  cam.updateMatrixWorld(true);
  return cam;
}

/**
 * The least distance (in steps of 1 %) from which a camera at eye height, looking at `target`
 * metres up the trunk, sees every corner of every box inside `margin` of the frame's edges.
 */
function fitDistance(boxes, { fov, eye, target, aspect, margin = 0.95, from = 1 }) {
  const corners = [];
  for (const { min, max } of boxes) {
    for (const x of [min[0], max[0]])
      for (const y of [min[1], max[1]])
        for (const z of [min[2], max[2]]) {
          corners.push(new THREE.Vector3(x, y, z));
        }
  }
  for (let d = from; d < 1000; d *= 1.01) {
    const cam = camera({ fov, eye, target, distance: d }, aspect);
    const fits = corners.every((c) => {
      const p = c.clone().project(cam);
      return p.z < 1 && Math.abs(p.x) <= margin && Math.abs(p.y) <= margin;
    });
    if (fits) return d;
  }
  return null;
}

/**
 * Every mesh drawn flat white on black, for silhouettes: keeping its texture's alpha cut-out, or
 * with `cut` false every triangle whole (the geometry its box is measured from).
 */
function masked(tree, cut = true) {
  const saved = [];
  tree.traverse((o) => {
    if (!o.isMesh) return;
    const m = o.material;
    saved.push([o, m]);
    // The texture only for its alpha (the cut-out of a leaf card): every drawn pixel is white.
    o.material = new THREE.MeshBasicMaterial({
      color: 0xffffff,
      map: cut ? (m.map ?? null) : null,
      alphaTest: cut ? m.alphaTest || 0 : 0,
      side: m.side,
    });
    o.material.onBeforeCompile = (shader) => {
      tree.userData.wind?.vertex(shader);
      shader.fragmentShader = shader.fragmentShader.replace(
        '#include <map_fragment>',
        '#include <map_fragment>\n\tdiffuseColor.rgb = vec3(1.0);',
      );
    };
    // grove's tree gets the leaf level of detail's vertex patch, ez-tree's none: programs apart.
    o.material.customProgramCacheKey = () => (tree.userData.wind ? 'mask-leaf-detail' : 'mask');
  });
  return () =>
    saved.forEach(([o, m]) => {
      o.material.dispose();
      o.material = m;
    });
}

/**
 * Tree `handle` as a model of the page's view (trees.mjs's Models, which shades each tree it
 * places as grove does): the tree as it stands, its meshes multisampled with alpha-to-coverage as
 * in the headset, ez-tree's Phong materials made standard ones of the same maps and colours.
 */
function pageModels(handle) {
  const tree = trees.get(handle);
  tree.updateMatrixWorld(true);
  const source = new THREE.Group();
  source.userData.leafArea = tree.userData.leafArea ?? 0;
  tree.traverse((o) => {
    if (!o.isMesh) return;
    const m = o.material;
    const material = m.isMeshPhongMaterial
      ? new THREE.MeshStandardMaterial({
          name: m.name,
          color: m.color,
          map: m.map,
          normalMap: m.normalMap,
          aoMap: m.aoMap,
          side: m.side,
          alphaTest: m.alphaTest,
          flatShading: m.flatShading,
          roughness: 1,
          metalness: 0,
        })
      : m.clone();
    material.alphaToCoverage = material.alphaTest > 0;
    const mesh = new THREE.Mesh(o.geometry, material);
    mesh.applyMatrix4(o.matrixWorld);
    mesh.castShadow = mesh.receiveShadow = true;
    source.add(mesh);
  });
  const models = new Models('', { antialias: true });
  models.models.set('model', source);
  return models;
}

/**
 * Draws tree `handle` through the headset page's drawing: on grove's model stage for the box
 * `view.box` (both trees of a pair: the same ground), seen by a walker from `view.distance`.
 * Returns the stage's camera; the frame stays in the view's renderer.
 */
async function drawPage(handle, view, width, height) {
  const { grove, renderer } = await setUp({ antialias: true });
  const sim = grove.createSim({
    stage: { min: view.box.min, max: view.box.max, aspect: width / height, from: view.distance },
  });
  try {
    const snap = sim.snapshot();
    const { scene, camera } = show({ models: pageModels(handle), snap, ground: sim.ground(), width, height });
    renderer.setClearColor(0x000000, 1);
    renderer.render(scene, camera);
    return { renderer, eye: snap.head.position, fov: THREE.MathUtils.radToDeg(snap.fov_y) };
  } finally {
    sim.free();
  }
}

/**
 * Draws tree `handle` from `view` ({ fov, eye, target, distance, box }) into a width × height
 * frame. Mode 'beauty' draws it through the headset page's drawing (drawPage) and returns the
 * frame as a PNG data URL; 'mask' draws its silhouette and returns the rows and columns it spans
 * and its share of the frame; 'profile' does so with every triangle whole, through
 * `profileCamera(view)` (the leaves' level of detail still set from `view`'s camera).
 */
async function render(handle, view, width, height, mode = 'beauty') {
  const tree = trees.get(handle);
  const r = stage(width, height);
  const cam = camera(view, width / height);
  if (mode === 'mask' || mode === 'profile') {
    leafDetail(tree, cam, height);
    const restore = masked(tree, mode === 'mask');
    const s = new THREE.Scene();
    s.background = new THREE.Color(0x000000);
    s.add(tree);
    r.toneMapping = THREE.NoToneMapping;
    r.render(s, mode === 'profile' ? profileCamera(view, width / height) : cam);
    restore();
    s.remove(tree);
    const px = pixels(r, width, height);
    let top = -1,
      bottom = -1,
      left = width,
      right = -1,
      count = 0;
    for (let y = 0; y < height; y++) {
      const row = height - 1 - y; // readPixels starts at the bottom row
      for (let x = 0; x < width; x++) {
        if (px[(y * width + x) * 4] > 127) {
          count++;
          if (top < 0 || row < top) top = row;
          if (row > bottom) bottom = row;
          if (x < left) left = x;
          if (x > right) right = x;
        }
      }
    }
    return { top, bottom, left, right, count, share: count / (width * height) };
  }
  const page = await drawPage(handle, view, width, height);
  // The walker's camera is the module's (grove_systems::stage::walker_view): it must be the one
  // the framing was fitted for.
  if (Math.abs(page.eye[1] - view.eye) > 1e-4 || Math.abs(page.fov - view.fov) > 1e-3)
    throw new Error(
      `the stage's walker (eye ${page.eye}, ${page.fov}°) is not the framing's (${view.eye} m, ${view.fov}°)`,
    );
  return page.renderer.domElement.toDataURL('image/png');
}

function pixels(r, width, height) {
  const gl = r.getContext();
  const px = new Uint8Array(width * height * 4);
  gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, px);
  return px;
}

/**
 * The tree's pixels in the drawn frame (its silhouette found with `render`'s mask): their mean
 * sRGB colour and luma (0–255), and the share of them darker than luma 25 (near black).
 */
async function colours(handle, view, width, height) {
  await render(handle, view, width, height, 'mask');
  const mask = pixels(renderer, width, height);
  const px = pixels((await drawPage(handle, view, width, height)).renderer, width, height);
  let n = 0,
    dark = 0;
  const sum = [0, 0, 0];
  for (let i = 0; i < mask.length; i += 4) {
    if (mask[i] <= 127) continue;
    n++;
    for (let c = 0; c < 3; c++) sum[c] += px[i + c];
    if (0.2126 * px[i] + 0.7152 * px[i + 1] + 0.0722 * px[i + 2] < 25) dark++;
  }
  const mean = sum.map((v) => v / Math.max(n, 1));
  return { pixels: n, mean, luma: 0.2126 * mean[0] + 0.7152 * mean[1] + 0.0722 * mean[2], dark: dark / Math.max(n, 1) };
}

/**
 * The labelled grid: `cells` rows of [left, right] PNG data URLs, each cell w × h, with a title
 * per column and a label per row. Returns the grid as a PNG data URL.
 */
async function grid(cells, columns, rows, w, h, title) {
  const pad = 8,
    head = 56,
    side = 170;
  const c = document.createElement('canvas');
  c.width = side + columns.length * (w + pad) + pad;
  c.height = head + cells.length * (h + pad) + pad;
  const g = c.getContext('2d');
  g.fillStyle = '#ffffff';
  g.fillRect(0, 0, c.width, c.height);
  g.fillStyle = '#111111';
  g.font = '15px "DejaVu Sans", sans-serif';
  g.fillText(title, pad, 20);
  g.font = 'bold 20px "DejaVu Sans", sans-serif';
  columns.forEach((name, i) => g.fillText(name, side + i * (w + pad) + pad, head - 10));
  for (let r = 0; r < cells.length; r++) {
    const y = head + r * (h + pad);
    g.fillStyle = '#111111';
    g.font = 'bold 18px "DejaVu Sans", sans-serif';
    rows[r].forEach((line, k) => {
      g.font = k === 0 ? 'bold 18px "DejaVu Sans", sans-serif' : '14px "DejaVu Sans", sans-serif';
      g.fillText(line, pad, y + 24 + k * 20);
    });
    for (let i = 0; i < cells[r].length; i++) {
      const img = new Image();
      img.src = cells[r][i];
      await img.decode();
      g.drawImage(img, side + i * (w + pad) + pad, y);
    }
  }
  return c.toDataURL('image/png');
}

window.compare = { groveTree, ezTree, stand, fitDistance, render, colours, grid, ready: true };
