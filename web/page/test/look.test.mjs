// The headset page draws trees as grove's renderer does (docs/headset.md, "Parity with grove's
// renderer"): each of the study's 8 models and the 6 species, drawn natively (`grove render
// --model FILE --background transparent`) and by the page's own modules (web/page/render.mjs) at
// the same camera, tick and size.
//
// - With one sample a pixel, as grove draws: the silhouettes overlap (IoU ≥ 0.9), the tree's
//   pixels are as bright (mean luma within 10 %) and the top third of the crown is not darker
//   against the bottom third than natively (5 % allowed).
// - Multisampled, as the headset draws (alpha-to-coverage on the leaves): as bright, the crown's
//   top as bright against its bottom, and the leaves' edges covered in part.
//
// render.mjs --replay draws the world a recording made by a tick: the module's world hash there is
// the one grove's recorder wrote into the file at that tick.
//
// Also: render.mjs's errors are one line and exit status 2 (a bad --scene file and bad recordings
// among them, refused before a browser starts), and leave no file behind.

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { openStill, readRecording } from '../render.mjs';
import { BOUNDS, compare, failures, models, nameOf, native, row } from './look.mjs';
import { ROOT, WEB } from './harness.mjs';

const SIZE = { width: 480, height: 360 };

test('every study model and species is drawn by the page as grove draws it', { timeout: 1200000 }, async () => {
  const still = await openStill();
  const rows = { single: [], multi: [] };
  const broken = [];
  try {
    for (const file of models()) {
      const name = nameOf(file);
      const n = native(file, { ...SIZE, samples: 1 });
      const single = compare(n, await still.render(file, { ...SIZE, background: 'transparent', antialias: false }));
      const page = await still.render(file, { ...SIZE, background: 'transparent' });
      const multi = compare(n, page);
      rows.single.push(row(name, single));
      rows.multi.push(row(name, multi));
      broken.push(...failures(single).map((f) => `${name}, one sample a pixel: ${f}`));
      broken.push(
        ...failures(multi)
          .filter((f) => !f.startsWith('IoU'))
          .map((f) => `${name}, multisampled: ${f}`),
      );
      let edges = 0;
      for (let i = 3; i < page.data.length; i += 4) if (page.data[i] > 0 && page.data[i] < 255) edges++;
      if (!(edges > 0)) broken.push(`${name}, multisampled: no pixel is covered in part`);
    }
  } finally {
    await still.close();
  }
  const table = (r) =>
    ['| model | IoU | luma native / page | top/bottom native / page |', '|---|---|---|---|', ...r].join('\n');
  console.log(`One sample a pixel:\n${table(rows.single)}\n\nMultisampled (the headset):\n${table(rows.multi)}`);
  assert.deepEqual(broken, [], `models the page draws unlike grove (bounds: ${JSON.stringify(BOUNDS)})`);
});

test("render.mjs --replay draws the world a recording made by a tick, at the participant's head", async () => {
  const file = join(ROOT, 'replays/study/P01-ray-casting-7.jsonl');
  const checkpoints = readFileSync(file, 'utf8')
    .split('\n')
    .filter((l) => l.includes('"type":"checkpoint"'))
    .map((l) => JSON.parse(l));
  const still = await openStill();
  try {
    for (const tick of [600, 1800]) {
      const rec = readRecording(file, tick);
      const r = await still.renderScene(null, { ...SIZE, tick, header: rec.header, events: rec.events });
      const want = checkpoints.find((c) => c.tick === tick);
      assert.ok(want, `the recording has a checkpoint at tick ${tick}`);
      assert.equal(r.tick, tick);
      assert.equal(r.hash, want.hash, `the world drawn at tick ${tick} is the recorded one`);
      assert.ok(r.trees > 0);
    }
  } finally {
    await still.close();
  }
});

test('render.mjs refuses bad arguments and a bad scene file with one line and exit status 2', () => {
  const dir = mkdtempSync(join(tmpdir(), 'grove-still-args-'));
  try {
    const model = join(ROOT, 'assets/trees/shrub-mesh.gltf');
    const exists = join(dir, 'there.png');
    writeFileSync(exists, 'x');
    const bad = join(dir, 'bad.ron');
    writeFileSync(bad, 'not ( a scene');
    const notJson = join(dir, 'not.jsonl');
    writeFileSync(notJson, '{"type":"header"\n');
    const old = join(ROOT, 'tests/fixtures/replay-v1.jsonl');
    const study = join(ROOT, 'replays/study/P01-ray-casting-7.jsonl');
    const huge = join(dir, 'huge.ron');
    writeFileSync(huge, Buffer.alloc((1 << 20) + 1, 32));
    const cases = [
      [['--model', model, '--out', join(dir, 'a.png'), '--background', 'blue'], /--background blue/],
      [['--model', model, '--out', join(dir, 'a.png'), '--width', '0'], /--width 0/],
      [['--model', model, '--out', join(dir, 'a.png'), '--tick', '-3'], /--tick -3/],
      [['--model', model, '--out', join(dir, 'a.png'), '--from', '0'], /--from 0: metres/],
      [['--model', model, '--out', join(dir, 'a.png'), '--from', 'far'], /--from far: metres/],
      [['--scene', bad, '--out', join(dir, 'a.png')], /^error: scene "bad.ron": line 1, column 1/],
      [['--scene', huge, '--out', join(dir, 'a.png')], /at most 1048576 bytes/],
      [
        ['--scene', join(ROOT, 'assets/scenes/study.ron'), '--out', join(dir, 'a.png'), '--from', '3'],
        /go with --model/,
      ],
      [
        ['--scene', join(ROOT, 'assets/scenes/study.ron'), '--model', model, '--out', join(dir, 'a.png')],
        /--model FILE, --scene FILE or --replay FILE/,
      ],
      [['--replay', notJson, '--out', join(dir, 'a.png')], /line 1 is not JSON/],
      [
        ['--replay', old, '--out', join(dir, 'a.png')],
        /header line: format version 1 \(the recorder continues version 2\)/,
      ],
      [['--replay', study, '--out', join(dir, 'a.png'), '--tick', '200000'], /the recording ends at tick \d+/],
      [['--replay', study, '--model', model, '--out', join(dir, 'a.png')], /--model FILE, --scene FILE or --replay/],
      [['--replay', study, '--out', join(dir, 'a.png'), '--from', '3'], /go with --model/],
      [['--model', join(dir, 'missing.gltf'), '--out', join(dir, 'a.png')], /no such file/],
      [['--model', model, '--out', join(dir, 'a.jpg')], /must name a .png/],
      [['--model', model, '--out', exists], /already exists/],
      [['--model', model], /give --out/],
      [['--model', model, '--out', join(dir, 'a.png'), '--colour', 'red'], /unknown argument --colour/],
    ];
    for (const [args, message] of cases) {
      const r = spawnSync(process.execPath, [join(WEB, 'page/render.mjs'), ...args], { encoding: 'utf8' });
      assert.equal(r.status, 2, `${args.join(' ')}: ${r.stderr}`);
      const lines = r.stderr.trim().split('\n');
      assert.equal(lines.length, 1, `one line for ${args.join(' ')}: ${r.stderr}`);
      assert.match(lines[0], message);
    }
    assert.deepEqual(
      spawnSync('ls', ['-A', dir], { encoding: 'utf8' }).stdout.trim().split('\n').sort(),
      ['bad.ron', 'huge.ron', 'not.jsonl', 'there.png'],
      'no partial output',
    );
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});
