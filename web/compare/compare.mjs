// grove's species beside ez-tree's presets at the same framing (docs/species.md, "Beside
// ez-tree"): grove's trees are written by `grove trees generate` into a scratch folder, the page
// (web/compare/page.mjs, bundled here by esbuild from web/node_modules: three.js and
// @dgreenheck/ez-tree) is opened in headless Chromium (playwright-core, SwiftShader) on an origin
// that only this script answers, and every other request is refused, so nothing loads from the
// network. Used by web/compare/run.mjs (the picture) and web/compare/test (the framing check).

import { spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, extname, join, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

export const HERE = dirname(fileURLToPath(import.meta.url));
export const WEB = resolve(HERE, '..');
export const ROOT = resolve(WEB, '..');
import { bundleModule, launchChromium } from '../page/headless.mjs';
const ORIGIN = 'http://compare.invalid';

/** The pairs: grove's species, ez-tree's preset, and the views they are drawn from. */
export const PAIRS = [
  { grove: 'oak', ez: 'Oak Medium', label: ['oak', 'ez-tree Oak Medium'] },
  { grove: 'beech', ez: 'Ash Medium', label: ['beech', 'ez-tree Ash Medium'] },
  { grove: 'shrub', ez: 'Bush 1', distance: 3, label: ['shrub, 3 m', 'ez-tree Bush 1'] },
  { grove: 'shrub', ez: 'Bush 1', distance: 10, label: ['shrub, 10 m', 'ez-tree Bush 1'] },
];

/**
 * The camera: 50° vertical field of view at eye height (1.7 m), looking at 45 % of the tree's
 * height: grove_systems::stage::walker_view's, which draws the pictures (page.mjs checks that the
 * module's walker is this one); here to fit the distance and for the framing check.
 */
export const FOV = 50;
export const EYE = 1.7;
export const TARGET = 0.45;

/** grove's binary: GROVE_BIN, else the release build, else the debug build. */
export function groveBin() {
  if (process.env.GROVE_BIN) return process.env.GROVE_BIN;
  for (const p of ['release', 'debug']) {
    const bin = join(ROOT, process.env.CARGO_TARGET_DIR ?? 'target', p, 'grove');
    if (existsSync(bin)) return bin;
  }
  throw new Error('no grove binary: build it (cargo build --release) or set GROVE_BIN');
}

/** Writes `species` (seed 1) into a fresh folder under `dir` with `grove trees generate`. */
export function generate(species, dir, bin = groveBin()) {
  const out = join(dir, species);
  if (existsSync(join(out, `${species}.gltf`))) return out;
  const r = spawnSync(bin, ['trees', 'generate', '--species', species, '--seed', '1', '--out', out], {
    encoding: 'utf8',
  });
  if (r.status !== 0) throw new Error(`grove trees generate --species ${species} failed: ${r.stderr.trim()}`);
  return out;
}

const TYPES = {
  '.gltf': 'model/gltf+json',
  '.bin': 'application/octet-stream',
  '.png': 'image/png',
  '.hdr': 'application/octet-stream',
  '.wasm': 'application/wasm',
};
/** The simulation module and grove's sky, which the headset page's drawing loads. */
const WASM = join(resolve(ROOT, process.env.CARGO_TARGET_DIR ?? 'target'), 'wasm', 'grove_sim.wasm');
const ENV = join(ROOT, 'assets/env');

/**
 * A browser with the page open: { call(name, ...args), trees, close }. `call` runs
 * window.compare[name](...args) in the page; grove's trees are served from `trees` (a scratch
 * folder, removed by close) at ORIGIN/trees/.
 */
export async function open({ width = 480, height = 400 } = {}) {
  if (!existsSync(WASM)) throw new Error(`${WASM} is missing: run bash web/build.sh first`);
  const script = await bundleModule(join(HERE, 'page.mjs'), WEB);
  const trees = mkdtempSync(join(tmpdir(), 'grove-compare-'));
  const browser = await launchChromium();
  const errors = [];
  const foreign = [];
  try {
    const context = await browser.newContext({ viewport: { width, height } });
    await context.route('**/*', async (route) => {
      const url = new URL(route.request().url());
      if (url.origin !== ORIGIN) {
        foreign.push(url.href);
        return route.abort();
      }
      if (url.pathname === '/') {
        return route.fulfill({
          contentType: 'text/html',
          body: '<!doctype html><meta charset="utf-8"><title>grove beside ez-tree</title><body style="margin:0"><script type="module" src="/page.js"></script></body>',
        });
      }
      if (url.pathname === '/page.js') return route.fulfill({ contentType: 'text/javascript', body: script });
      const [dir, rest] = url.pathname.startsWith('/env/')
        ? [ENV, url.pathname.slice(4)]
        : [trees, url.pathname.slice(6)];
      const file = url.pathname === '/grove_sim.wasm' ? WASM : resolve(dir, '.' + decodeURIComponent(rest));
      const served =
        url.pathname === '/grove_sim.wasm' || url.pathname.startsWith('/env/') || url.pathname.startsWith('/trees/');
      if (served && (file === WASM || file.startsWith(dir + sep)) && existsSync(file)) {
        return route.fulfill({
          contentType: TYPES[extname(file)] ?? 'application/octet-stream',
          body: readFileSync(file),
        });
      }
      return route.fulfill({ status: 404, body: 'not found' });
    });
    const page = await context.newPage();
    page.on('pageerror', (e) => errors.push(String(e.stack ?? e)));
    page.on('console', (m) => {
      if (m.type() === 'error') errors.push(m.text());
    });
    await page.goto(`${ORIGIN}/`);
    await page.waitForFunction(() => window.compare?.ready, null, { timeout: 60000 });
    const call = async (name, ...args) => {
      try {
        return await page.evaluate(([n, a]) => window.compare[n](...a), [name, args]);
      } catch (e) {
        throw new Error(`${name} failed in the page: ${e.message}; ${errors.join(' / ')}`);
      }
    };
    const close = async () => {
      await browser.close();
      rmSync(trees, { recursive: true, force: true });
    };
    return { call, trees, errors, foreign, close };
  } catch (e) {
    await browser.close();
    rmSync(trees, { recursive: true, force: true });
    throw e;
  }
}

/**
 * Loads pair `pair` into the page (grove's tree generated if missing) as handles 'grove' and
 * 'ez', both standing at the grove tree's height; returns their boxes and the view both are
 * drawn from: the pair's distance, or the least that fits both boxes.
 */
export async function loadPair(session, pair, { aspect, bin } = {}) {
  generate(pair.grove, session.trees, bin);
  const own = await session.call('groveTree', 'grove', `${ORIGIN}/trees/${pair.grove}/${pair.grove}.gltf`);
  const height = own.max[1] - own.min[1];
  const grove = await session.call('stand', 'grove', height);
  await session.call('ezTree', 'ez', pair.ez);
  const ez = await session.call('stand', 'ez', height);
  const view = {
    fov: FOV,
    eye: EYE,
    target: TARGET * height,
    box: { min: grove.min.map((v, i) => Math.min(v, ez.min[i])), max: grove.max.map((v, i) => Math.max(v, ez.max[i])) },
  };
  view.distance = pair.distance ?? (await session.call('fitDistance', [grove, ez], { ...view, aspect }));
  if (!view.distance) throw new Error(`no distance fits ${pair.grove} and ${pair.ez}`);
  return { height, grove, ez, view };
}
