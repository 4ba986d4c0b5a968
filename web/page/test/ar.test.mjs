// A scripted participant in immersive-ar (IWER's Quest 3 in a small office from @iwer/sem). By
// default the task is laid out in the room (`layout: room`): the 7 targets lie on the office's
// detected floor at least 0.5 m from its edges, in the task file's order and spacing ratios, the
// trees are planted at the layout's scale, the task completes, the file verifies with `grove
// replay`, `grove study` reports its layout and device, and the final hash is the one the same
// events give natively. With `layout=file` the task file's layout stays, its terrace target moved
// onto the floor. Every request the page made went to the server.

import assert from 'node:assert/strict';
import { copyFileSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { ROOT, WEB, fileLines, grove, start, studyRows, until } from './harness.mjs';
import { aimAt, click, enterAndStart, plantAll } from './participant.mjs';

let h;
before(async () => {
  h = await start();
});
after(async () => {
  await h?.close();
});

/** The distance from a point [x, z] to the polygon's nearest edge, and whether it lies inside. */
function placeIn(poly, [x, z]) {
  let inside = false;
  let d = Infinity;
  for (let i = 0; i < poly.length; i++) {
    const [ax, az] = poly[i];
    const [bx, bz] = poly[(i + 1) % poly.length];
    if (az > z !== bz > z && x < ax + ((z - az) / (bz - az)) * (bx - ax)) inside = !inside;
    const [dx, dz] = [bx - ax, bz - az];
    const len2 = dx * dx + dz * dz; // an outline may repeat a point
    const t = len2 > 0 ? Math.max(0, Math.min(1, ((x - ax) * dx + (z - az) * dz) / len2)) : 0;
    d = Math.min(d, Math.hypot(x - (ax + t * dx), z - (az + t * dz)));
  }
  return { inside, d };
}

const area = (poly) => Math.abs(poly.reduce((s, [x, z], i) => s + x * poly[(i + 1) % poly.length][1] - poly[(i + 1) % poly.length][0] * z, 0)) / 2;

/** The task file's targets: [[x, y, z], model] in order (assets/tasks/ray-casting-7.ron). */
function fileTargets() {
  const text = readFileSync(join(ROOT, 'assets/tasks/ray-casting-7.ron'), 'utf8');
  return [...text.matchAll(/position: \(([-\d.]+), ([-\d.]+), ([-\d.]+)\), model: "([a-z-]+)"/g)].map((m) => [[+m[1], +m[2], +m[3]], m[4]]);
}

test('immersive-ar, laid out in the room: 7 targets on the office floor 0.5 m from its edges, planted, verified, in the study with layout and device, same hash as native', async (t) => {
  const scratch = [];
  t.after(() => scratch.forEach((d) => rmSync(d, { recursive: true, force: true })));
  const { page } = await h.open('participant=P61&task=ray-casting-7&seed=2019061&quality=low&render_every=4', { xr: true, room: true });
  await enterAndStart(page, 'ar');
  await until(page, () => window.grove.snapshot?.task);
  const start = await page.evaluate(() => ({ floor: window.grove.floor, outline: window.grove.floorOutline, snap: window.grove.snapshot, device: window.grove.device }));
  assert.match(start.floor.source, /^plane detection/, 'the office has a floor plane');
  // The outline the page sent is the office's floor as @iwer/sem's capture has it.
  const office = JSON.parse(readFileSync(join(WEB, 'node_modules/@iwer/sem/captures/office_small.json'), 'utf8'));
  const extent = office.spatialEntities.find((e) => e.semanticLabel_META === 'FLOOR').bounded2D_META.extent;
  assert.ok(Math.abs(area(start.outline) - extent.width * extent.height) < 0.01, `${area(start.outline)} m² against ${extent.width} x ${extent.height}`);
  // Every target on it, 0.5 m or more from its edges, in the file's order, models and spacing ratios.
  const targets = start.snap.task.targets;
  const file = fileTargets();
  assert.deepEqual(targets.map((x) => x.model), file.map((f) => f[1]));
  for (const x of targets) {
    const { inside, d } = placeIn(start.outline, [x.position[0], x.position[2]]);
    assert.ok(inside && d >= 0.5, `${x.model} at ${x.position}: inside ${inside}, ${d.toFixed(3)} m from an edge`);
    assert.equal(x.position[1], 0, 'on the floor');
    assert.equal(x.moved_to, null);
  }
  const flat = (p, q) => Math.hypot(p[0] - q[0], p[2] - q[2]);
  const scale = flat(targets[0].position, targets[1].position) / flat(file[0][0], file[1][0]);
  assert.ok(scale > 0.03 && scale < 0.2, `scale ${scale}`);
  for (let i = 0; i < 7; i++) for (let j = i + 1; j < 7; j++) assert.ok(Math.abs(flat(targets[i].position, targets[j].position) - scale * flat(file[i][0], file[j][0])) < 2e-3, `${i}-${j}`);
  assert.deepEqual(start.device, { profile: 'meta-quest-touch-plus', target_ray_mode: 'tracked-pointer', mapping: 'controller' });

  assert.equal(await plantAll(page), 7);
  await until(page, () => window.grove.state === 'done' && window.grove.verification, null, 60000);
  const done = await page.evaluate(() => ({ v: window.grove.verification, file: window.grove.file, s: window.grove.snapshot }));
  assert.equal(done.v.status, 'verified', JSON.stringify(done.v));
  assert.equal(done.s.trees.length, 7, 'the room has no trees of its own: the 7 planted');
  assert.ok(done.s.trees.every((x) => Math.abs(x.scale - scale) < 1e-3), `the trees at the layout's scale: ${done.s.trees.map((x) => x.scale)}`);
  assert.deepEqual(h.foreign(), [], 'every request went to the server');
  assert.deepEqual(h.errors, []);

  const path = join(h.server.dir, done.file);
  const lines = fileLines(path);
  const header = JSON.parse(lines[0]);
  assert.match(header.scene, /^room-[0-9a-f]{16}\.ron$/);
  assert.deepEqual(header.device, start.device);
  const startTask = lines.map((l) => JSON.parse(l)).find((l) => l.event?.kind === 'start_task');
  assert.deepEqual(startTask.event.layout.room.floor.map((p) => p.map(Math.fround)), start.outline, 'the floor travels with the start of the task (as f32)');
  const replay = grove(['replay', path, '--json']);
  assert.equal(replay.status, 0, replay.stderr);
  const report = JSON.parse(replay.stdout);
  assert.equal(report.task.completed, true);
  assert.ok(Math.abs(report.task.layout.scale - scale) < 1e-4 && report.task.layout.edge_m >= 0.5, JSON.stringify(report.task.layout));
  assert.deepEqual(report.device, start.device);
  t.diagnostic(`the office's room layout: ${JSON.stringify(report.task.layout)}; targets ${JSON.stringify(targets.map((x) => x.position))}`);

  const row = studyRows(h.server.dir).find((r) => r.file === done.file);
  assert.ok(row, `${done.file} in the study`);
  assert.deepEqual([row.completed, row.trees, row.status, row.device, row.target_ray_mode, row.input_profile], ['true', '7', 'verified', 'controller', 'tracked-pointer', 'meta-quest-touch-plus']);
  assert.match(row.layout, /^room:0\.\d{4}:2\.\d\dx2\.\d\d$/);
  assert.ok(Math.abs(+row.layout.split(':')[1] - scale) < 1e-3, row.layout);

  // The same events re-simulated natively: `grove replay --seal` checks the file, runs its events
  // on a fresh native simulation and writes its own checkpoints and footer. (Its second simulation
  // looks the room's scene up in the working directory: run it where a copy of the scene is.)
  const sealed = mkdtempSync(join(tmpdir(), 'grove-page-seal-'));
  scratch.push(sealed);
  copyFileSync(join(h.server.dir, header.scene), join(sealed, header.scene));
  const seal = grove(['replay', '--seal', path, '--out', join(sealed, 'sealed.jsonl')], sealed);
  assert.equal(seal.status, 0, seal.stderr);
  const footer = (ls) => JSON.parse(ls[ls.length - 1]);
  const native = footer(fileLines(join(sealed, 'sealed.jsonl')));
  assert.deepEqual([native.final_tick, native.final_hash], [footer(lines).final_tick, footer(lines).final_hash]);
  await page.close();
});

test("immersive-ar with layout=file: the task file's layout, its terrace target moved onto the floor, as the study reports it", async () => {
  const { page } = await h.open('participant=P66&task=ray-casting-7&seed=5&quality=low&render_every=4&layout=file', { xr: true, room: true });
  await enterAndStart(page, 'ar');
  await until(page, () => window.grove.snapshot?.task);
  const snap = await page.evaluate(() => window.grove.snapshot);
  assert.equal(await page.evaluate(() => window.grove.floorOutline), null);
  const moved = snap.task.targets.filter((x) => x.moved_to);
  assert.deepEqual(moved.map((x) => [x.model, x.position[1], x.moved_to[1]]), [['birch-billboard', 0.8, 0]], 'the terrace target lies on the floor');
  assert.deepEqual(snap.task.targets.map((x) => x.position), fileTargets().map((f) => f[0]));
  assert.equal(await plantAll(page, { limit: 1 }), 1);
  // Finish task, from the menu.
  await click(page, 'b-button', 40);
  await until(page, () => window.grove.snapshot.menu.open);
  await aimAt(page, await page.evaluate(() => window.grove.menuItemPoint('finish')));
  await click(page, 'trigger');
  await until(page, () => window.grove.state === 'done' && window.grove.verification, null, 60000);
  const done = await page.evaluate(() => ({ v: window.grove.verification, file: window.grove.file }));
  assert.equal(done.v.status, 'verified', JSON.stringify(done.v));
  const path = join(h.server.dir, done.file);
  const header = JSON.parse(fileLines(path)[0]);
  const scene = readFileSync(join(h.server.dir, header.scene), 'utf8');
  assert.match(scene, /Target 6 \(birch-billboard\) has no plane at 0\.8 m/);
  const report = JSON.parse(grove(['replay', path, '--json']).stdout);
  assert.deepEqual(report.task.moved_targets.map((m) => m.target), [6]);
  assert.equal(report.task.layout, null);
  assert.equal(studyRows(h.server.dir).find((r) => r.file === done.file).layout, '6:0.80>0.00');
  assert.deepEqual(h.errors, []);
});
