// The headset page's structure (web/page/, tests excepted): no import cycle between its modules
// or between its folders (a folder and the folders inside it do not count against each other),
// and no module over 400 lines. The static imports are read by esbuild's parser (its metafile),
// not by a pattern, so that an import in a comment or a string is none. A self-test on made-up
// folders shows that each rule finds what it is for. No browser: scripts/test runs it before the
// page's browser tests.

import assert from 'node:assert/strict';
import { mkdirSync, mkdtempSync, readFileSync, readdirSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, relative, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';
import { test } from 'node:test';
import { build } from 'esbuild';

const PAGE = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const MAX_LINES = 400;

/** The modules under `root` (relative paths with '/'), the tests' folder left out. */
function modules(root, dir = root) {
  return readdirSync(dir, { withFileTypes: true }).flatMap((e) => {
    const p = join(dir, e.name);
    if (e.isDirectory()) return e.name === 'test' || e.name === 'node_modules' ? [] : modules(root, p);
    return /\.m?js$/.test(e.name) ? [relative(root, p).split(sep).join('/')] : [];
  });
}

/** The modules' static imports among themselves: Map module -> Set of modules it imports. */
async function importGraph(root) {
  const files = modules(root);
  // Packages, node: builtins and files outside `root` are not the page's modules: left unresolved.
  const outside = {
    name: 'outside',
    setup(b) {
      b.onResolve({ filter: /^\.{1,2}\// }, (a) => {
        const p = resolve(a.resolveDir, a.path);
        return p.startsWith(root + sep) ? undefined : { path: p, external: true };
      });
    },
  };
  const { metafile } = await build({
    entryPoints: files.map((f) => join(root, f)),
    absWorkingDir: root,
    bundle: true,
    write: false,
    outdir: join(root, '.imports-check'),
    format: 'esm',
    packages: 'external',
    external: ['node:*'],
    metafile: true,
    logLevel: 'silent',
    plugins: [outside],
  });
  const graph = new Map(files.map((f) => [f, new Set()]));
  for (const [from, { imports }] of Object.entries(metafile.inputs)) {
    if (!graph.has(from)) continue;
    for (const i of imports) if (i.kind === 'import-statement' && !i.external && graph.has(i.path)) graph.get(from).add(i.path);
  }
  return graph;
}

/** The cycles of a graph (Map node -> Set of nodes): each strongly connected component of more than one node, or a node importing itself. */
function cycles(graph) {
  let n = 0;
  const index = new Map();
  const low = new Map();
  const stack = [];
  const out = [];
  const visit = (v) => {
    index.set(v, n);
    low.set(v, n++);
    stack.push(v);
    for (const w of graph.get(v) ?? []) {
      if (!index.has(w)) {
        visit(w);
        low.set(v, Math.min(low.get(v), low.get(w)));
      } else if (stack.includes(w)) low.set(v, Math.min(low.get(v), index.get(w)));
    }
    if (low.get(v) !== index.get(v)) return;
    const component = stack.splice(stack.indexOf(v));
    if (component.length > 1 || graph.get(v)?.has(v)) out.push(component.sort());
  };
  for (const v of graph.keys()) if (!index.has(v)) visit(v);
  return out;
}

/** The folders' graph: a folder imports another when a module in it imports one in the other, neither inside the other. */
function folderGraph(graph) {
  const folder = (f) => (f.includes('/') ? f.slice(0, f.lastIndexOf('/')) : '');
  const inside = (a, b) => a === '' || b === '' || a === b || b.startsWith(a + '/') || a.startsWith(b + '/');
  const out = new Map();
  for (const [from, to] of graph) {
    for (const t of to) {
      const [a, b] = [folder(from), folder(t)];
      if (!inside(a, b)) out.set(a, (out.get(a) ?? new Set()).add(b));
    }
  }
  return out;
}

/** The modules over `max` lines, with their lines. */
function tooLong(root, files, max = MAX_LINES) {
  const lines = (f) => readFileSync(join(root, f), 'utf8').split('\n').length - 1;
  return files.map((f) => [f, lines(f)]).filter(([, n]) => n > max);
}

/** What the check finds under `root`: { graph, cycles, folderCycles, long }. */
export async function check(root) {
  const graph = await importGraph(root);
  return { graph, cycles: cycles(graph), folderCycles: cycles(folderGraph(graph)), long: tooLong(root, [...graph.keys()]) };
}

test('web/page: no import cycle between its modules or its folders, no module over 400 lines', async () => {
  const found = await check(PAGE);
  assert.ok(found.graph.get('main.mjs')?.size >= 5, `main.mjs's imports were read: ${[...(found.graph.get('main.mjs') ?? [])]}`);
  assert.ok(found.graph.size >= 20, `the page's modules were found: ${[...found.graph.keys()]}`);
  const { cycles, folderCycles, long } = found;
  assert.deepEqual({ cycles, folderCycles, long }, { cycles: [], folderCycles: [], long: [] }, `modules, then folders, that import each other in a circle; modules over ${MAX_LINES} lines`);
});

test('the check finds a cycle of modules, a cycle of folders and a long module, and nothing else', async () => {
  const root = mkdtempSync(join(tmpdir(), 'grove-page-imports-'));
  try {
    const write = (f, text) => {
      mkdirSync(dirname(join(root, f)), { recursive: true });
      writeFileSync(join(root, f), text);
    };
    write('a.mjs', "import { b } from './b.mjs';\nexport const a = () => b;\n");
    write('b.mjs', "import { a } from './a.mjs';\nexport const b = () => a;\n");
    // Not imports: a comment, a string, a dynamic import; a package and a file outside the folder.
    write('c.mjs', "// import { a } from './a.mjs';\nimport * as THREE from 'three';\nimport { x } from '../elsewhere.mjs';\nexport const c = \"import './a.mjs'\";\nexport const d = () => import('./a.mjs');\n");
    write('x/one.mjs', "import { two } from '../y/two.mjs';\nexport const one = two;\n");
    write('x/four.mjs', 'export const four = 4;\n');
    write('y/two.mjs', 'export const two = 2;\n');
    write('y/three.mjs', "import { four } from '../x/four.mjs';\nexport const three = four;\n");
    // A folder and its subfolder import each other: allowed.
    write('x/inner/five.mjs', "import { four } from '../four.mjs';\nexport const five = four;\n");
    write('x/six.mjs', "import { five } from './inner/five.mjs';\nexport const six = five;\n");
    write('long.mjs', 'export const n = 1;\n' + '// a line\n'.repeat(400));
    write('fits.mjs', 'export const n = 1;\n' + '// a line\n'.repeat(399));
    write('test/long.test.mjs', "import { a } from '../a.mjs';\n" + '//\n'.repeat(500));
    const found = await check(root);
    assert.deepEqual([...found.graph.get('c.mjs')], [], 'no import read from a comment, a string or a dynamic import');
    assert.deepEqual(found.cycles, [['a.mjs', 'b.mjs']]);
    assert.deepEqual(found.folderCycles, [['x', 'y']]);
    assert.deepEqual(found.long, [['long.mjs', 401]]);
    assert.ok(!found.graph.has('test/long.test.mjs'), 'tests are not the page');
  } finally {
    rmSync(root, { recursive: true, force: true });
  }
});
