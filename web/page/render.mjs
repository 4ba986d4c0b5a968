// Draws a model as the headset page draws it, headless, to a PNG (docs/headset.md, "The page's
// drawing, headless"):
//
//   node web/page/render.mjs --model FILE --out PNG [--width W] [--height H] [--tick T]
//                            [--background sky|transparent] [--from D] [--force]
//   node web/page/render.mjs --scene FILE --out PNG [--width W] [--height H] [--tick T] [--force]
//   node web/page/render.mjs --replay FILE [--scene FILE] --out PNG [--width W] [--height H] [--tick T] [--force]
//
// The picture is the one `grove render --model FILE` draws natively, at the same framing (the
// WebAssembly module builds grove's own model stage: camera, sun, wind), through the page's
// modules (web/page/still.mjs bundles them): its materials, light, environment, shadows and
// wind. --tick T: the model in the study's wind after T ticks (without it, calm at tick 0), as
// `grove render --model FILE --tick T`. --background transparent: the model alone, its alpha the
// coverage. --from D: a walker's view from D metres in place of that framing (the eye 1.7 m up,
// looking at 45 % of the model's height, the sun 40° up behind the left shoulder:
// grove_systems::stage::walker_view, the view of docs/species.md's sheets). Every error is one
// line on stderr and exit status 2. Needs the module (bash web/build.sh), `npm ci` in web/ and
// Chromium (/usr/bin/chromium, or CHROMIUM).
//
// --scene FILE: a scene's trees on its ground at its camera (as `grove render --scene FILE`
// draws it), after T ticks; the scene is built by the module, so it must be self-contained (no
// model banks, no aerial photographs: the study and pond scenes), and its models are the
// catalogue's (assets/trees).
//
// --replay FILE: the world a recording made by tick T (its end without --tick), at the
// participant's head, as `grove render --replay FILE --tick T` draws it: the module follows the
// recording's header (and refuses what it cannot follow: an older format version is brought up by
// `grove replay --upgrade`) and applies its events tick by tick. A scene that is not built in (a headset's room) is given by --scene.
//
// `openStill()` is the same drawing for scripts and tests that draw many models in one browser.

import { existsSync, readFileSync, renameSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { basename, dirname, extname, join, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';
import { PNG } from 'pngjs';
import { loadGrove } from '../sim/grove-sim.mjs';
import { CHROMIUM, bundleModule, launchChromium } from './headless.mjs';

const HERE = dirname(fileURLToPath(import.meta.url));
const WEB = resolve(HERE, '..');
const ROOT = resolve(WEB, '..');
const ORIGIN = 'http://still.invalid';
const WASM = join(resolve(ROOT, process.env.CARGO_TARGET_DIR ?? 'target'), 'wasm', 'grove_sim.wasm');
const TYPES = {
  '.gltf': 'model/gltf+json',
  '.glb': 'model/gltf-binary',
  '.bin': 'application/octet-stream',
  '.png': 'image/png',
  '.jpg': 'image/jpeg',
  '.jpeg': 'image/jpeg',
  '.webp': 'image/webp',
  '.wasm': 'application/wasm',
};

/** The longest tick --tick takes: an hour at 60 ticks a second (as `grove render --model`). */
export const MAX_TICK = 216000;

/** The largest scene file --scene reads, bytes (the module's rule: systems/src/scene_text.rs). */
const MAX_SCENE_BYTES = 1 << 20;

/** The largest recording --replay reads, bytes. */
const MAX_REPLAY_BYTES = 256 << 20;

/** The distances --from takes, metres (the module refuses others: web/sim/src/options.rs). */
export const [MIN_FROM, MAX_FROM] = [0.1, 1000];

/** A file served from inside `dir` only. */
function inside(dir, name) {
  const file = resolve(dir, '.' + sep + decodeURIComponent(name));
  return file.startsWith(dir + sep) && existsSync(file) && statSync(file).isFile() ? file : null;
}

/**
 * A headless browser with the still page open (or a test's `entry` that imports it): {
 * render(model, { width, height, tick, background }) → { width, height, data (RGBA, straight
 * alpha), ... }, call(name, model, options) (window[name](options with the model's URL) in the
 * page), close }.
 */
export async function openStill({ entry = join(HERE, 'still.mjs') } = {}) {
  if (!existsSync(WASM)) throw new Error(`${WASM} is missing: run bash web/build.sh first`);
  if (!existsSync(CHROMIUM))
    throw new Error(`${CHROMIUM}: no Chromium there (install Debian's chromium or set CHROMIUM)`);
  const script = await bundleModule(entry, WEB);
  const envDir = join(ROOT, 'assets/env');
  const modelsDir = join(ROOT, 'assets/trees');
  let modelDir = null;
  const browser = await launchChromium();
  const errors = [];
  try {
    const context = await browser.newContext({ viewport: { width: 64, height: 64 } });
    await context.route('**/*', async (route) => {
      const url = new URL(route.request().url());
      if (url.origin !== ORIGIN) return route.abort();
      const p = url.pathname;
      const file =
        p === '/grove_sim.wasm'
          ? WASM
          : p.startsWith('/env/')
            ? inside(envDir, p.slice(5))
            : p.startsWith('/models/')
              ? inside(modelsDir, p.slice(8))
              : p.startsWith('/model/') && modelDir
                ? inside(modelDir, p.slice(7))
                : null;
      if (p === '/')
        return route.fulfill({
          contentType: 'text/html',
          body: '<!doctype html><meta charset="utf-8"><title>grove still</title><body style="margin:0"><script type="module" src="/still.js"></script></body>',
        });
      if (p === '/still.js') return route.fulfill({ contentType: 'text/javascript', body: script });
      if (file)
        return route.fulfill({
          contentType: TYPES[extname(file).toLowerCase()] ?? 'application/octet-stream',
          body: readFileSync(file),
        });
      return route.fulfill({ status: 404, body: 'not found' });
    });
    const page = await context.newPage();
    page.on('pageerror', (e) => errors.push(String(e.message ?? e)));
    page.on('console', (m) => {
      if (m.type() === 'error') errors.push(m.text());
    });
    await page.goto(`${ORIGIN}/`);
    await page.waitForFunction(() => window.still?.ready, null, { timeout: 60000 });
    const render = async (
      model,
      { width = 640, height = 480, tick = null, background = 'sky', antialias = true, from = null } = {},
    ) => {
      const file = resolve(model);
      modelDir = dirname(file);
      errors.length = 0;
      let r;
      try {
        r = await page.evaluate((o) => window.still.render(o), {
          model: `/model/${encodeURIComponent(basename(file))}`,
          width,
          height,
          tick,
          background,
          antialias,
          from,
        });
      } catch (e) {
        throw new Error(
          `${model}: the page could not draw it (${e.message.split('\n')[0]}${errors.length ? `; ${errors[0]}` : ''})`,
        );
      }
      return { ...r, data: Buffer.from(r.pixels, 'base64'), pixels: undefined };
    };
    const call = async (name, model, options = {}) => {
      modelDir = dirname(resolve(model));
      return page.evaluate(
        ([n, o]) => window[n](o),
        [name, { ...options, model: `/model/${encodeURIComponent(basename(model))}` }],
      );
    };
    const renderScene = async (file, { width = 640, height = 480, tick = 0, header = null, events = [] } = {}) => {
      errors.length = 0;
      try {
        const r = await page.evaluate((o) => window.still.renderScene(o), {
          name: file ? basename(file) : null,
          text: file ? readFileSync(file, 'utf8') : null,
          width,
          height,
          tick: tick ?? 0,
          header,
          events,
        });
        return { ...r, data: Buffer.from(r.pixels, 'base64'), pixels: undefined };
      } catch (e) {
        throw new Error(
          `${file ?? 'the recording'}: the page could not draw it (${e.message.split('\n')[0]}${errors.length ? `; ${errors[0]}` : ''})`,
        );
      }
    };
    return { render, renderScene, call, close: () => browser.close() };
  } catch (e) {
    await browser.close();
    throw e;
  }
}

/** Writes an image ({ width, height, data: RGBA }) as PNG through a temporary file and a rename. */
export function writePng(path, { width, height, data }) {
  const png = new PNG({ width, height });
  data.copy(png.data);
  const bytes = PNG.sync.write(png);
  const tmp = join(dirname(path), `.${basename(path, '.png')}.tmp-${process.pid}.png`);
  try {
    writeFileSync(tmp, bytes);
    renameSync(tmp, path);
  } catch (e) {
    rmSync(tmp, { force: true });
    throw new Error(`${path}: cannot write (${e.message})`);
  }
  return bytes.length;
}

const USAGE =
  'usage: node web/page/render.mjs (--model FILE [--background sky|transparent] [--from D] | --scene FILE | --replay FILE [--scene FILE]) --out PNG [--width W] [--height H] [--tick T] [--force]';

/**
 * A recording's header line (its text: the module judges it, format version and all) and its
 * event lines (parsed) up to `tick` (all without it), and its last tick; throws an Error naming
 * what is wrong.
 */
export function readRecording(file, tick = null) {
  const lines = readFileSync(file, 'utf8')
    .split('\n')
    .filter((l) => l.trim());
  const events = [];
  let last = 0;
  lines.forEach((text, i) => {
    let l;
    try {
      l = JSON.parse(text);
    } catch {
      throw new Error(`${file}: line ${i + 1} is not JSON`);
    }
    if (i > 0 && Number.isSafeInteger(l.tick)) last = Math.max(last, l.tick);
    if (i > 0 && l.type === 'event' && (tick === null || l.tick < tick)) events.push(l);
  });
  if (tick !== null && tick > last) throw new Error(`--tick ${tick}: the recording ends at tick ${last}`);
  return { header: lines[0] ?? '', events, last };
}

/** The command line's options, or an Error naming what is wrong. */
export function parseArgs(args) {
  const o = {
    model: null,
    scene: null,
    replay: null,
    out: null,
    width: 1280,
    height: 720,
    tick: null,
    background: 'sky',
    from: null,
    force: false,
  };
  for (let i = 0; i < args.length; i++) {
    const flag = args[i];
    if (flag === '--force') {
      o.force = true;
      continue;
    }
    const value = args[i + 1];
    i++;
    if (
      !['--model', '--scene', '--replay', '--out', '--width', '--height', '--tick', '--background', '--from'].includes(
        flag,
      )
    )
      return new Error(`unknown argument ${flag}`);
    if (value === undefined) return new Error(`${flag} needs a value`);
    if (flag === '--model') o.model = resolve(value);
    else if (flag === '--scene') o.scene = resolve(value);
    else if (flag === '--replay') o.replay = resolve(value);
    else if (flag === '--out') o.out = resolve(value);
    else if (flag === '--background') {
      if (!['sky', 'transparent'].includes(value)) return new Error(`--background ${value}: sky or transparent`);
      o.background = value;
    } else if (flag === '--from') {
      const d = Number(value);
      if (!/^\d+(\.\d+)?$/.test(value) || d < MIN_FROM || d > MAX_FROM)
        return new Error(`--from ${value}: metres, from ${MIN_FROM} to ${MAX_FROM}`);
      o.from = d;
    } else {
      const n = Number(value);
      const [lo, hi] = flag === '--tick' ? [0, MAX_TICK] : [1, 4096];
      if (!/^\d+$/.test(value) || n < lo || n > hi)
        return new Error(`${flag} ${value}: a whole number from ${lo} to ${hi}`);
      o[flag.slice(2)] = n;
    }
  }
  if (o.model && (o.scene || o.replay)) return new Error('give --model FILE, --scene FILE or --replay FILE');
  if (!o.model && !o.scene && !o.replay) return new Error('give --model FILE, --scene FILE or --replay FILE');
  if (!o.model && (o.from !== null || args.includes('--background')))
    return new Error('--from and --background go with --model, not with --scene or --replay');
  if (!o.out) return new Error('give --out PNG');
  for (const input of [o.model, o.scene, o.replay].filter(Boolean))
    if (!existsSync(input) || !statSync(input).isFile()) return new Error(`${input}: no such file`);
  if (o.replay && statSync(o.replay).size > MAX_REPLAY_BYTES)
    return new Error(`${o.replay}: a recording is at most ${MAX_REPLAY_BYTES} bytes here`);
  if (o.scene && statSync(o.scene).size > MAX_SCENE_BYTES)
    return new Error(`${o.scene}: a scene file is at most ${MAX_SCENE_BYTES} bytes`);
  if (o.model && !['.gltf', '.glb'].includes(extname(o.model).toLowerCase()))
    return new Error(`${o.model}: --model must name a .gltf or .glb file`);
  if (extname(o.out).toLowerCase() !== '.png') return new Error(`${o.out}: --out must name a .png file`);
  if (existsSync(o.out) && statSync(o.out).isDirectory())
    return new Error(`${o.out}: is a directory; --out needs a PNG file name`);
  if (existsSync(o.out) && !o.force) return new Error(`${o.out}: already exists (use --force to overwrite)`);
  if (!existsSync(dirname(o.out))) return new Error(`${dirname(o.out)}: folder does not exist`);
  return o;
}

async function main() {
  const args = process.argv.slice(2);
  if (args.includes('--help') || args.includes('-h')) {
    console.log(
      `Draws a model as the headset page draws it, framed as grove render --model frames it (with --from D, as a walker sees it from D metres), or a self-contained scene at its camera.\n\n${USAGE}`,
    );
    return 0;
  }
  const o = parseArgs(args);
  if (o instanceof Error) {
    console.error(`error: ${o.message}\n${USAGE}`.split('\n')[0]);
    return 2;
  }
  let still;
  try {
    if (o.replay) {
      const rec = readRecording(o.replay, o.tick);
      const tick = o.tick ?? rec.last;
      // The header and scene checked by the module here, before a browser starts.
      const text = o.scene ? readFileSync(o.scene, 'utf8') : null;
      (await loadGrove(WASM)).createSim({ header: rec.header, scene_text: text }).free();
      still = await openStill();
      const img = await still.renderScene(o.scene, { ...o, tick, header: rec.header, events: rec.events });
      const bytes = writePng(o.out, img);
      console.log(
        `${o.out}: drew ${o.replay} at tick ${img.tick}, ${img.trees} trees (${o.width}x${o.height}) at the participant's head as the headset page draws it, ${bytes} bytes`,
      );
      return 0;
    }
    if (o.scene) {
      // The scene checked by the module here, before a browser starts: a bad one is one line.
      const sim = (await loadGrove(WASM)).createSim({
        scene: basename(o.scene),
        scene_text: readFileSync(o.scene, 'utf8'),
      });
      sim.free();
      still = await openStill();
      const img = await still.renderScene(o.scene, o);
      const bytes = writePng(o.out, img);
      console.log(
        `${o.out}: drew ${o.scene} at tick ${img.tick}, ${img.trees} trees (${o.width}x${o.height}) as the headset page draws it, ${bytes} bytes`,
      );
      return 0;
    }
    still = await openStill();
    const img = await still.render(o.model, o);
    const bytes = writePng(o.out, img);
    const at =
      (o.from === null ? '' : ` from ${o.from} m at eye height`) +
      (o.tick === null ? '' : ` at tick ${o.tick} in the study's wind`);
    console.log(
      `${o.out}: drew ${o.model}${at} (${o.width}x${o.height}, ${o.background}) as the headset page draws it, ${bytes} bytes`,
    );
    return 0;
  } catch (e) {
    console.error(`error: ${String(e.message ?? e).split('\n')[0]}`);
    return 2;
  } finally {
    await still?.close();
  }
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) process.exitCode = await main();
