// Builds the headset page into web/dist/, which `grove serve` ships at `/` (docs/headset.md):
// the page's ES modules bundled with three.js and the input-profile library by esbuild (from the
// pinned packages of web/package-lock.json), the simulation module and its loader, and the
// controller profiles the page draws, and the sky and ground grove ships (assets/env); and the
// modules of the protocol's form page and dashboard (docs/protocol.md). Nothing it ships loads
// from the network.
//
//   node web/page/build.mjs [--out DIR]
//
// The emulator the browser tests use (iwer, @iwer/sem) is bundled separately by
// web/page/test/harness.mjs, never into dist/.

import { build } from 'esbuild';
import { copyFileSync, cpSync, existsSync, mkdirSync, readFileSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { gzipSync } from 'node:zlib';

const here = dirname(fileURLToPath(import.meta.url));
const web = resolve(here, '..');
const root = resolve(web, '..');
const args = process.argv.slice(2);
const out = args.includes('--out') ? resolve(args[args.indexOf('--out') + 1]) : join(web, 'dist');

/** The files of assets/env the page draws: the sky's six faces and the ground. */
export const ENV_FILES = ['px.png', 'nx.png', 'py.png', 'ny.png', 'pz.png', 'nz.png', 'ground.png'];

/** The controller profiles the page ships: the devices docs/headset.md names, and their fallbacks. */
export const PROFILES = [
  'meta-quest-touch-plus',
  'meta-quest-touch-plus-v2',
  'oculus-touch-v3',
  'magicleap-one',
  'pico-4',
];

const wasm = join(resolve(root, process.env.CARGO_TARGET_DIR ?? 'target'), 'wasm', 'grove_sim.wasm');
if (!existsSync(wasm)) {
  console.error(`web/page/build.mjs: ${wasm} is missing; run bash web/build.sh first`);
  process.exit(2);
}

rmSync(out, { recursive: true, force: true });
mkdirSync(out, { recursive: true });
// ES modules for today's browsers, minified, their licences in a file beside each.
const bundled = {
  bundle: true,
  format: 'esm',
  target: 'es2022',
  minify: true,
  sourcemap: false,
  legalComments: 'linked',
  logLevel: 'warning',
};
const result = await build({
  ...bundled,
  entryPoints: [join(here, 'main.mjs')],
  outfile: join(out, 'page.js'),
  metafile: true,
  // The module's loader reads the file with node:fs under Node only; in a page it fetches it.
  external: ['node:*'],
});
// The protocol's form page and the dashboard (web/protocol/, web/dashboard/): their markup is
// built into grove serve, their modules are served from here as /protocol.js and /dashboard.js.
await build({
  ...bundled,
  entryPoints: { protocol: join(web, 'protocol', 'main.mjs'), dashboard: join(web, 'dashboard', 'main.mjs') },
  outdir: out,
});
copyFileSync(join(here, 'index.html'), join(out, 'index.html'));
copyFileSync(join(here, 'page.css'), join(out, 'page.css'));
copyFileSync(wasm, join(out, 'grove_sim.wasm'));
// The sky's cube faces and the ground's texture (draw/sky.mjs), as grove's renderer has them.
mkdirSync(join(out, 'env'));
for (const f of ENV_FILES) copyFileSync(join(root, 'assets/env', f), join(out, 'env', f));

// The profiles: their folders as the registry's assets package has them, and a profile list
// naming only these (the library reads it first and looks a device's profile ids up in it).
const assets = join(web, 'node_modules/@webxr-input-profiles/assets/dist/profiles');
const list = JSON.parse(readFileSync(join(assets, 'profilesList.json'), 'utf8'));
const kept = {};
for (const id of PROFILES) {
  cpSync(join(assets, id), join(out, 'profiles', id), { recursive: true });
  kept[id] = list[id];
}
writeFileSync(join(out, 'profiles', 'profilesList.json'), JSON.stringify(kept, null, 2));
copyFileSync(join(web, 'node_modules/@webxr-input-profiles/assets/LICENSE.md'), join(out, 'profiles', 'LICENSE.md'));

const size = (f) => statSync(f).size;
const js = readFileSync(join(out, 'page.js'));
const summary = {
  page_js_bytes: js.length,
  page_js_gzip_bytes: gzipSync(js, { level: 9 }).length,
  wasm_bytes: size(join(out, 'grove_sim.wasm')),
  wasm_gzip_bytes: gzipSync(readFileSync(join(out, 'grove_sim.wasm')), { level: 9 }).length,
};
summary.protocol_js_bytes = size(join(out, 'protocol.js'));
summary.dashboard_js_bytes = size(join(out, 'dashboard.js'));
writeFileSync(
  join(out, 'build.json'),
  JSON.stringify({ ...summary, inputs: Object.keys(result.metafile.inputs).length }, null, 2),
);
console.log(
  `${out}: page.js ${summary.page_js_bytes} bytes (${summary.page_js_gzip_bytes} gzipped), grove_sim.wasm ${summary.wasm_bytes} bytes (${summary.wasm_gzip_bytes} gzipped), profiles ${PROFILES.join(', ')}`,
);
