// The comparison of grove's species with ez-tree's presets (web/compare, docs/species.md): both
// trees of each pair are drawn at the same framing (drawn through an orthographic camera of the
// picture's scale and ground row, their silhouettes equally tall within rounding, standing on the
// same row), each covers a plausible share of the frame, the page loads nothing from the
// network, ez-tree stays out of the headset page's bundle, and run.mjs writes its grid or refuses
// bad arguments with exit 2. grove's trees come from GROVE_BIN (else target/release or debug).

import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { build } from 'esbuild';
import { HERE, PAIRS, WEB, loadPair, open } from '../compare.mjs';

const W = 320;
const H = 260;
let session;
const silhouettes = [];

before(async () => {
  session = await open({ width: W, height: H });
  for (const pair of PAIRS) {
    const { view, height } = await loadPair(session, pair, { aspect: W / H });
    const grove = await session.call('render', 'grove', view, W, H, 'mask');
    const ez = await session.call('render', 'ez', view, W, H, 'mask');
    // The framing itself: the same trees through an orthographic camera of the same scale and
    // ground row (page.mjs's profileCamera), where a treetop's row no longer depends on how near
    // the camera it stands, every triangle drawn whole (a leaf card's transparent corner may set
    // its tree's box yet draw nothing).
    const profile = {
      grove: await session.call('render', 'grove', view, W, H, 'profile'),
      ez: await session.call('render', 'ez', view, W, H, 'profile'),
    };
    silhouettes.push({ pair, view, height, grove, ez, profile });
  }
});

after(async () => {
  await session?.close();
});

/** Silhouette `s` of `who`'s tree is drawn and stays inside the frame. */
function drawnInFrame(name, who, s) {
  assert.ok(s.count > 0, `${name}: ${who}'s tree is not drawn`);
  assert.ok(
    s.top > 0 && s.bottom < H - 1 && s.left > 0 && s.right < W - 1,
    `${name}: ${who}'s tree leaves the frame (${JSON.stringify(s)})`,
  );
}

test('each pair away from the shrub close up: drawn in the middle of the picture, each tree covering a plausible share of it', (t) => {
  for (const { pair, view, grove, ez } of silhouettes.filter((s) => s.pair.distance !== 3)) {
    const name = `${pair.grove} / ${pair.ez} from ${view.distance.toFixed(1)} m`;
    for (const [who, s] of [
      ['grove', grove],
      ['ez-tree', ez],
    ]) {
      drawnInFrame(name, who, s);
      assert.ok(
        s.share > 0.01 && s.share < 0.6,
        `${name}: ${who}'s tree covers ${(s.share * 100).toFixed(1)} % of the frame`,
      );
      const middle = (s.left + s.right) / 2;
      assert.ok(
        Math.abs(middle - W / 2) < W * 0.1,
        `${name}: ${who}'s tree stands ${middle} px across, not in the middle`,
      );
    }
    t.diagnostic(
      `${name}, in perspective: ${grove.bottom - grove.top + 1} and ${ez.bottom - ez.top + 1} px tall, feet on rows ${grove.bottom} and ${ez.bottom}, ${(grove.share * 100).toFixed(1)} % and ${(ez.share * 100).toFixed(1)} % of the frame`,
    );
  }
});

test('each pair away from the shrub close up, at the same scale without depth: the two silhouettes are equally tall, stand on the same row and fit the frame', (t) => {
  for (const { pair, view, height, profile } of silhouettes.filter((s) => s.pair.distance !== 3)) {
    const name = `${pair.grove} / ${pair.ez} from ${view.distance.toFixed(1)} m`;
    const { grove, ez } = profile;
    drawnInFrame(name, 'grove', grove);
    drawnInFrame(name, 'ez-tree', ez);
    // Both trees are scaled to one height and stood on one ground, so through this camera each
    // spans `rows` rows (the scale: 2 d tan(fov / 2) metres over H rows) up to rounding: a span
    // of L rows covers the centres of floor(L) or ceil(L) pixels, and a treetop that is a
    // triangle's narrow tip may miss its top row's centres, hence 1.5 rows; the two trees within
    // 2 rows of each other (1.2 % of the beech's 164, 2.4 % of the shrub's 86), feet within 1.
    const rows = (height * H) / (2 * view.distance * Math.tan((view.fov * Math.PI) / 360));
    const [hg, he] = [grove.bottom - grove.top + 1, ez.bottom - ez.top + 1];
    for (const [who, h] of [
      ['grove', hg],
      ['ez-tree', he],
    ]) {
      assert.ok(
        Math.abs(h - rows) <= 1.5,
        `${name}: ${who}'s silhouette is ${h} px tall, its height ${rows.toFixed(1)}`,
      );
    }
    assert.ok(Math.abs(hg - he) <= 2, `${name}: silhouettes ${hg} px and ${he} px tall`);
    assert.ok(
      Math.abs(grove.bottom - ez.bottom) <= 1,
      `${name}: the trees stand on rows ${grove.bottom} and ${ez.bottom}`,
    );
    if (pair.distance === undefined) assert.ok(hg > 0.5 * H, `${name}: the trees fill only ${hg} of ${H} rows`);
    t.diagnostic(
      `${name}, orthographic: ${hg} and ${he} px tall (height ${rows.toFixed(1)} rows), feet on rows ${grove.bottom} and ${ez.bottom}`,
    );
  }
});

test('the shrub pair is seen from 3 m and 10 m, and from 3 m fills much of the frame', () => {
  assert.deepEqual(
    silhouettes.filter((s) => s.pair.distance).map((s) => s.view.distance),
    [3, 10],
  );
  const close = silhouettes.find((s) => s.pair.distance === 3);
  for (const [who, s] of [
    ['grove', close.grove],
    ['ez-tree', close.ez],
  ]) {
    assert.ok(s.share > 0.25, `the ${who} shrub from 3 m covers only ${(s.share * 100).toFixed(1)} % of the frame`);
    assert.ok(
      s.bottom >= H - 1 || s.bottom > 0.8 * H,
      `the ${who} shrub from 3 m does not reach the ground near the frame's foot (${s.bottom})`,
    );
  }
});

test('the page asked for nothing outside its own origin and raised no error', () => {
  assert.deepEqual(session.foreign, []);
  assert.deepEqual(session.errors, []);
});

test("ez-tree is not in the headset page's bundle", async () => {
  const out = await build({
    entryPoints: [join(WEB, 'page/main.mjs')],
    bundle: true,
    format: 'esm',
    write: false,
    metafile: true,
    external: ['node:*'],
    logLevel: 'silent',
    absWorkingDir: WEB,
  });
  const inputs = Object.keys(out.metafile.inputs);
  assert.ok(
    inputs.some((p) => p.includes('node_modules/three/')),
    'the headset page should bundle three.js (is the entry right?)',
  );
  assert.deepEqual(
    inputs.filter((p) => p.includes('ez-tree')),
    [],
  );
});

test('run.mjs refuses bad arguments with one line and exit 2, and writes nothing', () => {
  const dir = mkdtempSync(join(tmpdir(), 'grove-compare-run-'));
  try {
    for (const args of [
      ['--width', 'wide'],
      ['--height', '10'],
      ['--out', join(dir, 'grid.jpg')],
      ['--colour', 'red'],
      ['--out'],
    ]) {
      const r = spawnSync(
        process.execPath,
        [join(HERE, 'run.mjs'), ...args, ...(args[0] === '--out' ? [] : ['--out', join(dir, 'grid.png')])],
        { encoding: 'utf8' },
      );
      assert.equal(r.status, 2, `${args.join(' ')}: exit ${r.status}, ${r.stderr}`);
      assert.match(r.stderr, /^error: /, `${args.join(' ')}: ${r.stderr}`);
    }
    assert.ok(!existsSync(join(dir, 'grid.png')));
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});

test('run.mjs writes the labelled grid: two columns of four rows', () => {
  const dir = mkdtempSync(join(tmpdir(), 'grove-compare-run-'));
  try {
    const out = join(dir, 'grid.png');
    const r = spawnSync(process.execPath, [join(HERE, 'run.mjs'), '--out', out, '--width', '160', '--height', '120'], {
      encoding: 'utf8',
    });
    assert.equal(r.status, 0, r.stderr);
    const png = readFileSync(out);
    assert.equal(png.subarray(1, 4).toString(), 'PNG');
    const [w, h] = [png.readUInt32BE(16), png.readUInt32BE(20)];
    // 170 px of labels, then two 160 px cells; a 56 px heading, then four 120 px rows (8 px gaps).
    assert.equal(w, 170 + 2 * (160 + 8) + 8);
    assert.equal(h, 56 + 4 * (120 + 8) + 8);
    assert.deepEqual(spawnSync('ls', ['-A', dir], { encoding: 'utf8' }).stdout.trim().split('\n'), ['grid.png']);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});
