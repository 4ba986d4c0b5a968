// What the parity tests share (look.test.mjs, wind.test.mjs, web/page/test/look-pictures.mjs):
// the models grove's study and species bank ship, each drawn natively (`grove render --model
// FILE --background transparent`) and by the headset page's drawing (web/page/render.mjs), and
// the figures compared: the silhouettes' overlap, the tree's brightness, and how bright the top of
// its crown is against the bottom.

import { spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync, readdirSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { basename, join } from 'node:path';
import { PNG } from 'pngjs';
import { GROVE, ROOT } from './harness.mjs';

/** The study's 8 models (assets/trees, the catalogue) and the 6 species at level of detail 1 (assets/banks/species). */
export function models() {
  const trees = readdirSync(join(ROOT, 'assets/trees')).filter((f) => f.endsWith('.gltf')).sort().map((f) => join(ROOT, 'assets/trees', f));
  const species = readdirSync(join(ROOT, 'assets/banks/species')).filter((d) => d.endsWith('-lod1')).sort().map((d) => join(ROOT, 'assets/banks/species', d, `${d}.gltf`));
  return [...trees, ...species];
}

/** A model's short name: its file's stem. */
export const nameOf = (file) => basename(file).replace(/\.(gltf|glb)$/, '');

/** A PNG's pixels: { width, height, data (RGBA) }. */
export function readPng(path) {
  const png = PNG.sync.read(readFileSync(path));
  return { width: png.width, height: png.height, data: png.data };
}

/**
 * `grove render --model FILE --background transparent` at `width` × `height` (and `--tick T`
 * where given; `extra` arguments after), read back.
 */
export function native(file, { width, height, tick = null, background = 'transparent', extra = [] }) {
  const dir = mkdtempSync(join(tmpdir(), 'grove-look-'));
  try {
    const out = join(dir, 'native.png');
    const args = ['render', '--model', file, '--background', background, '--width', String(width), '--height', String(height), '--out', out];
    if (tick !== null) args.push('--tick', String(tick));
    args.push(...extra);
    const r = spawnSync(GROVE, args, { encoding: 'utf8', env: { ...process.env, XDG_RUNTIME_DIR: dir } });
    if (r.status !== 0) throw new Error(`grove ${args.join(' ')} failed: ${r.stderr.trim()}`);
    return readPng(out);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}

const luma = (d, i) => 0.2126 * d[i] + 0.7152 * d[i + 1] + 0.0722 * d[i + 2];

/** The tree's pixels (alpha above one half). */
export function mask(img) {
  const m = new Uint8Array(img.width * img.height);
  for (let i = 0; i < m.length; i++) m[i] = img.data[4 * i + 3] > 127 ? 1 : 0;
  return m;
}

/** Intersection over union of two masks. */
export function iou(a, b) {
  let both = 0;
  let either = 0;
  for (let i = 0; i < a.length; i++) {
    both += a[i] & b[i];
    either += a[i] | b[i];
  }
  return either ? both / either : 1;
}

/**
 * The tree's brightness: the mean luma (sRGB, 0–255) of its pixels, and of those in the top and
 * the bottom third of the rows its silhouette spans, with their ratio.
 */
export function tone(img) {
  const m = mask(img);
  let top = img.height;
  let bottom = -1;
  for (let i = 0; i < m.length; i++) {
    if (!m[i]) continue;
    const y = Math.floor(i / img.width);
    top = Math.min(top, y);
    bottom = Math.max(bottom, y);
  }
  const third = (bottom - top + 1) / 3;
  const sums = { all: [0, 0], top: [0, 0], bottom: [0, 0] };
  for (let i = 0; i < m.length; i++) {
    if (!m[i]) continue;
    const y = Math.floor(i / img.width);
    const l = luma(img.data, 4 * i);
    sums.all[0] += l;
    sums.all[1]++;
    if (y < top + third) (sums.top[0] += l), sums.top[1]++;
    if (y >= bottom + 1 - third) (sums.bottom[0] += l), sums.bottom[1]++;
  }
  const mean = ([s, n]) => (n ? s / n : 0);
  const t = { pixels: sums.all[1], luma: mean(sums.all), top: mean(sums.top), bottom: mean(sums.bottom) };
  return { ...t, ratio: t.bottom > 0 ? t.top / t.bottom : 0 };
}

/** The figures of one model: silhouettes' IoU, and native and page tone. */
export function compare(nativeImg, pageImg) {
  return { iou: iou(mask(nativeImg), mask(pageImg)), native: tone(nativeImg), page: tone(pageImg) };
}

/** The parity bounds (docs/headset.md): IoU ≥ 0.9, luma within 10 %, the top third not darker against the bottom than natively (5 % allowed). */
export const BOUNDS = { iou: 0.9, luma: 0.1, ratio: 0.95 };

/** What a model's figures break of BOUNDS (empty when none). */
export function failures(f) {
  const out = [];
  if (!(f.iou >= BOUNDS.iou)) out.push(`IoU ${f.iou.toFixed(3)} < ${BOUNDS.iou}`);
  const dl = Math.abs(f.page.luma - f.native.luma) / f.native.luma;
  if (!(dl <= BOUNDS.luma)) out.push(`luma ${f.page.luma.toFixed(1)} against ${f.native.luma.toFixed(1)} natively (${(dl * 100).toFixed(1)} % off)`);
  if (!(f.page.ratio >= BOUNDS.ratio * f.native.ratio)) out.push(`top/bottom ${f.page.ratio.toFixed(2)} against ${f.native.ratio.toFixed(2)} natively`);
  return out;
}

/** One row of the figures' table. */
export function row(name, f) {
  return `| ${name} | ${f.iou.toFixed(3)} | ${f.native.luma.toFixed(1)} / ${f.page.luma.toFixed(1)} | ${f.native.ratio.toFixed(2)} / ${f.page.ratio.toFixed(2)} |`;
}
