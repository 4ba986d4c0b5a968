// What a headset holds (docs/headset.md): each model kind the page draws (the study's billboards
// and low-poly meshes in assets/trees, the species bank's level 1 and level 2 in
// assets/banks/species; the page draws no impostors) drawn by the page's own view with 1 tree and
// with N, and three.js's counts of each frame (renderer.info.render) split into the cost of a
// tree (the slope between 1 and N) and the frame's fixed cost (sky, ground, the shadow map's
// set-up), with the sun's shadows on and off. Beside them, each model's own primitives and
// triangles read from its glTF's accessors, and how many trees fit Meta's WebXR budget.
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
 * and their triangles (an index accessor's count, else the positions', per primitive's mode).
 */
export function gltfCounts(file) {
  const g = JSON.parse(readFileSync(file, 'utf8'));
  let primitives = 0;
  let triangles = 0;
  const visit = (n) => {
    const node = g.nodes[n];
    for (const p of node.mesh === undefined ? [] : g.meshes[node.mesh].primitives) {
      const count = g.accessors[p.indices ?? p.attributes.POSITION].count;
      const mode = p.mode ?? 4;
      if (mode < 4) throw new Error(`${file}: a primitive of mode ${mode} (points or lines)`);
      primitives++;
      triangles += mode === 4 ? count / 3 : count - 2;
    }
    for (const c of node.children ?? []) visit(c);
  };
  for (const n of g.scenes[g.scene ?? 0].nodes) visit(n);
  return { primitives, triangles };
}

/** The cost of a tree and the fixed cost from the counts at 1 and `n` trees. */
export function split(one, many, n) {
  const calls = (many.calls - one.calls) / (n - 1);
  const triangles = (many.triangles - one.triangles) / (n - 1);
  return { calls, triangles, fixed_calls: one.calls - calls, fixed_triangles: one.triangles - triangles };
}

/** How many trees of a cost fit `BUDGET` beside the fixed cost. */
export function fit({ calls, triangles, fixed_calls, fixed_triangles }) {
  return Math.min(
    Math.floor((BUDGET.calls - fixed_calls) / calls),
    Math.floor((BUDGET.triangles - fixed_triangles) / triangles),
  );
}

/**
 * Every model drawn by the page's view (one browser): [{ model, kind, own: gltfCounts, shadows:
 * { one, many, ...split }, plain: the same without shadows }].
 */
export async function measure(list = models()) {
  const still = await openStill({ entry: join(HERE, 'capacity-probe.mjs') });
  const rows = [];
  try {
    for (const { file, model, kind } of list) {
      const frames = await still.call('capacity', file, { counts: [1, N] });
      const of = (shadows) => {
        const [one, many] = [1, N].map((t) => frames.find((f) => f.shadows === shadows && f.trees === t));
        return { one, many, ...split(one, many, N) };
      };
      rows.push({ model, kind, own: gltfCounts(file), shadows: of(true), plain: of(false) });
    }
  } finally {
    await still.close();
  }
  return rows;
}

/** The rows of docs/benchmarks/capacity.json: one a model, its counts per tree and per eye. */
export function table(rows) {
  return rows.map(({ model, kind, own, shadows, plain }) => ({
    model,
    kind,
    primitives: own.primitives,
    model_triangles: own.triangles,
    calls_per_tree: shadows.calls,
    triangles_per_tree: shadows.triangles,
    fixed_calls: shadows.fixed_calls,
    fixed_triangles: shadows.fixed_triangles,
    trees_in_budget: fit(shadows),
    calls_per_tree_low: plain.calls,
    triangles_per_tree_low: plain.triangles,
    fixed_calls_low: plain.fixed_calls,
    trees_in_budget_low: fit(plain),
  }));
}

async function main() {
  const at = process.argv.indexOf('--json');
  const out = at > 0 ? resolve(process.argv[at + 1] ?? '') : null;
  const rows = table(await measure());
  console.table(rows);
  if (!out) return;
  const json = {
    command:
      'bash web/build.sh (the module, if missing); npm ci (web/); node web/page/test/capacity.mjs --json docs/benchmarks/capacity.json',
    machine: 'any machine (counts of what is drawn, not timings; headless Chromium, SwiftShader)',
    date: new Date().toISOString().slice(0, 10),
    note: `counts, not timings: three.js renderer.info.render of one frame drawn by the page's view (web/page/still.mjs) in headless Chromium, 1 and ${N} trees of each model where the stage's one stands; per tree = the slope, fixed = sky, ground and the shadow map's set-up; a single-view frame = one eye; *_low: the page's quality=low (no shadow map); trees_in_budget: Meta's WebXR guidance for Quest, ${BUDGET.calls} draw calls and ${BUDGET.triangles} triangles per eye (docs/headset.md, What a headset holds); no instancing, no impostors`,
    headset_capacity: rows,
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
