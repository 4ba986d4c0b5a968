// What a headset holds (docs/headset.md): each model kind the page draws (the study's billboards
// and low-poly meshes in assets/trees, the species bank's level 1 and level 2 in
// assets/banks/species; the page draws no impostors) drawn by the page's own view with no tree,
// 1 tree and N, and three.js's counts of each frame (renderer.info.render) split into the frame's
// fixed cost (sky, ground: no tree), the cost of a model in view (its instanced draw calls: 1
// tree less none) and the cost of a tree (the triangles' slope between 1 and N), with the sun's
// shadows on and off; and MIX_TREES trees of the study's mix in one frame. Beside them, each
// model's own primitives and triangles read from its glTF's accessors, and how many trees fit
// Meta's WebXR budget.
//
//   node web/page/test/capacity.mjs [--json FILE]   (prints the table; writes the JSON for
//                                                     docs/benchmarks/capacity.json)
//
// capacity.test.mjs holds the counts against the models' own.

import { readFileSync, readdirSync, renameSync, writeFileSync } from 'node:fs';
import { basename, dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { openStill } from '../render.mjs';

const HERE = dirname(fileURLToPath(import.meta.url));
const ROOT = resolve(HERE, '../../..');

/** Meta's WebXR guidance for Quest, per eye (docs/headset.md, "What a headset holds"). */
export const BUDGET = { calls: 100, triangles: 750000 };
/** The trees drawn beside the one. */
export const N = 10;
/** The trees of the study's mix drawn in one frame (docs/headset.md: at least 100 within the budget). */
export const MIX_TREES = 100;

/** [{ file, model, kind }]: every model of each kind the page draws. */
export function models() {
  const trees = join(ROOT, 'assets/trees');
  const study = readdirSync(trees)
    .filter((f) => f.endsWith('.gltf'))
    .sort()
    .map((f) => ({
      file: join(trees, f),
      model: basename(f, '.gltf'),
      kind: f.includes('-billboard') ? 'billboard' : 'low-poly mesh',
    }));
  const bank = join(ROOT, 'assets/banks/species');
  const species = readdirSync(bank, { withFileTypes: true })
    .filter((d) => d.isDirectory())
    .map((d) => d.name)
    .sort()
    .map((d) => ({
      file: join(bank, d, `${d}.gltf`),
      model: d,
      kind: d.endsWith('-lod1') ? 'species level 1' : 'species level 2',
    }));
  return [...study, ...species];
}

/**
 * A glTF file's own counts, from its JSON alone: the primitives its default scene's nodes draw
 * and their triangles (an index accessor's count, else the positions', per primitive's mode),
 * and `parts`: each primitive's { triangles, clipped (alpha mode MASK: leaves) }.
 */
export function gltfCounts(file) {
  const g = JSON.parse(readFileSync(file, 'utf8'));
  const parts = [];
  const visit = (n) => {
    const node = g.nodes[n];
    for (const p of node.mesh === undefined ? [] : g.meshes[node.mesh].primitives) {
      const count = g.accessors[p.indices ?? p.attributes.POSITION].count;
      const mode = p.mode ?? 4;
      if (mode < 4) throw new Error(`${file}: a primitive of mode ${mode} (points or lines)`);
      const clipped = g.materials?.[p.material]?.alphaMode === 'MASK';
      parts.push({ triangles: mode === 4 ? count / 3 : count - 2, clipped });
    }
    for (const c of node.children ?? []) visit(c);
  };
  for (const n of g.scenes[g.scene ?? 0].nodes) visit(n);
  return { primitives: parts.length, triangles: parts.reduce((a, p) => a + p.triangles, 0), parts };
}

/**
 * The frame's fixed cost (`zero` trees), a model's (its draw calls: `one` tree less none) and a
 * tree's (the triangles' slope to `many`, `n` trees); `calls`: the draw calls a tree adds once
 * its model is in view (0 when instanced).
 */
export function split(zero, one, many, n) {
  return {
    calls: (many.calls - one.calls) / (n - 1),
    triangles: (many.triangles - one.triangles) / (n - 1),
    model_calls: one.calls - zero.calls,
    fixed_calls: zero.calls,
    fixed_triangles: zero.triangles,
  };
}

/** How many trees of one model fit `BUDGET` beside the fixed cost and its model's draw calls. */
export function fit({ calls, triangles, model_calls, fixed_calls, fixed_triangles }) {
  const room = BUDGET.calls - fixed_calls - model_calls;
  if (room < 0) return 0;
  return Math.min(
    calls > 0 ? 1 + Math.floor(room / calls) : Infinity,
    Math.floor((BUDGET.triangles - fixed_triangles) / triangles),
  );
}

/**
 * The study's mix of MIX_TREES trees: its 8 models (assets/trees) in equal shares, the
 * remainder to the heaviest (the low-poly meshes): { model: count }.
 */
export function studyMix(list = models()) {
  const study = list
    .filter((m) => m.kind === 'billboard' || m.kind === 'low-poly mesh')
    .map((m) => ({ ...m, triangles: gltfCounts(m.file).triangles }))
    .sort((a, b) => b.triangles - a.triangles || a.model.localeCompare(b.model));
  const each = Math.floor(MIX_TREES / study.length);
  const rest = MIX_TREES - each * study.length;
  return Object.fromEntries(study.map((m, i) => [m.model, each + (i < rest ? 1 : 0)]));
}

/** The far model of each model of a bank's catalogue.ron that has one (its `far: Some(...)`). */
export function farModels(catalogue) {
  const far = {};
  let name = null;
  for (const m of readFileSync(catalogue, 'utf8').matchAll(/\bname: "([^"]+)"|\bfar: Some\("([^"]+)"\)/g)) {
    if (m[1]) name = m[1];
    else if (name) far[name] = m[2];
  }
  return far;
}

/**
 * Every model drawn by the page's view (one browser): { rows: [{ model, kind, own: gltfCounts,
 * shadows: { zero, one, many, ...split }, plain: the same without shadows }], mix: { trees, of:
 * studyMix, shadows: { calls, triangles }, plain }, levels (where `levels` names a model with its
 * far model, `{ file, far, pixels }`): the still's frames of it at those sizes on screen }.
 */
export async function measure(list = models(), { levels = null } = {}) {
  const still = await openStill({ entry: join(HERE, 'capacity-probe.mjs') });
  const rows = [];
  let mix = null;
  let drawn = null;
  try {
    for (const { file, model, kind } of list) {
      const frames = await still.call('capacity', file, { counts: [0, 1, N] });
      const of = (shadows) => {
        const [zero, one, many] = [0, 1, N].map((t) => frames.find((f) => f.shadows === shadows && f.trees === t));
        return { zero, one, many, ...split(zero, one, many, N) };
      };
      rows.push({ model, kind, own: gltfCounts(file), shadows: of(true), plain: of(false) });
    }
    const of = studyMix(list);
    const first = list.find((m) => m.model in of);
    if (first) {
      const frames = await still.call('mix', first.file, { dir: '/model/', mix: of });
      const pick = (shadows) => {
        const { calls, triangles } = frames.find((f) => f.shadows === shadows);
        return { calls, triangles };
      };
      mix = { trees: MIX_TREES, of, shadows: pick(true), plain: pick(false) };
    }
    if (levels) {
      const [near, far] = [levels.file, levels.far];
      // Both files served from the folder above theirs (a bank's).
      const url = (f) => `/model/${basename(dirname(f))}/${basename(f)}`;
      drawn = await still.call('levels', join(dirname(dirname(near)), 'x'), {
        near: url(near),
        far: url(far),
        pixels: levels.pixels,
      });
    }
  } finally {
    await still.close();
  }
  return { rows, mix, levels: drawn };
}

/** The rows of docs/benchmarks/capacity.json: one a model, its counts per tree and per eye. */
export function table(rows) {
  return rows.map(({ model, kind, own, shadows, plain }) => ({
    model,
    kind,
    primitives: own.primitives,
    model_triangles: own.triangles,
    calls_per_model: shadows.model_calls,
    calls_per_tree: shadows.calls,
    triangles_per_tree: shadows.triangles,
    fixed_calls: shadows.fixed_calls,
    fixed_triangles: shadows.fixed_triangles,
    trees_in_budget: fit(shadows),
    calls_per_model_low: plain.model_calls,
    calls_per_tree_low: plain.calls,
    triangles_per_tree_low: plain.triangles,
    fixed_calls_low: plain.fixed_calls,
    trees_in_budget_low: fit(plain),
  }));
}

async function main() {
  const at = process.argv.indexOf('--json');
  const out = at > 0 ? resolve(process.argv[at + 1] ?? '') : null;
  const { rows: measured, mix } = await measure();
  const rows = table(measured);
  console.table(rows);
  console.log(`${mix.trees} trees of the study's mix:`, mix);
  if (!out) return;
  const json = {
    command:
      'bash web/build.sh (the module, if missing); npm ci (web/); node web/page/test/capacity.mjs --json docs/benchmarks/capacity.json',
    machine: 'any machine (counts of what is drawn, not timings; headless Chromium, SwiftShader)',
    date: new Date().toISOString().slice(0, 10),
    note: `counts, not timings: three.js renderer.info.render of one frame drawn by the page's view (web/page/still.mjs) in headless Chromium, 0, 1 and ${N} trees of each model where the stage's one stands; fixed = no tree (sky, ground); per model = the draw calls of its instanced meshes (1 tree less none), the same whatever its count; per tree = the slope; a single-view frame = one eye; *_low: the page's quality=low (no shadow map); trees_in_budget: Meta's WebXR guidance for Quest, ${BUDGET.calls} draw calls and ${BUDGET.triangles} triangles per eye (docs/headset.md, What a headset holds); study_mix: ${MIX_TREES} trees of the study's 8 models in equal shares (the remainder to the heaviest) in one frame; each species level 1 drawn alone, as if near (its far model, level 2, takes over below 400 pixels on screen); no impostors`,
    headset_capacity: rows,
    study_mix: mix,
  };
  const tmp = `${out}.tmp-${process.pid}`;
  writeFileSync(tmp, `${JSON.stringify(json, null, 2)}\n`);
  renameSync(tmp, out);
  console.log(`${out}: ${rows.length} models`);
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  try {
    await main();
  } catch (e) {
    console.error(`error: ${String(e.message ?? e).split('\n')[0]}`);
    process.exitCode = 2;
  }
}
