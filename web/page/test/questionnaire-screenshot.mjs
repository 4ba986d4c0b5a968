// docs/questionnaire-headset.png: the protocol's questionnaire panel in immersive-vr (IWER's
// Quest 3, the study scene), on the seven questions' first item with 8 chosen and the ray on 9.
// Run after the page is built (node web/page/build.mjs):
//
//   node web/page/test/questionnaire-screenshot.mjs OUT.png
//
// It uses the tests' server, browser and emulator (harness.mjs).

import { resolve } from 'node:path';
import { start } from './harness.mjs';
import { aimAt, enterStudy, frames, pressPanel, toTheQuestions } from './participant.mjs';

const out = process.argv[2];
if (!out) {
  console.error('usage: node web/page/test/questionnaire-screenshot.mjs OUT.png');
  process.exit(2);
}
const h = await start(['--protocol', 'assets/protocols/tree-planting.ron']);
try {
  await toTheQuestions(h.server.url, 'P03');
  const { page } = await h.open('participant=P03&quality=low', { xr: true, room: false, width: 900, height: 700 });
  await enterStudy(page);
  await pressPanel(page, 'opt:8');
  // The hand lower and to the right, so that the ray crosses the view to the panel.
  await aimAt(page, await page.evaluate(() => window.grove.panelPoint('opt:9')), { x: 0.25, y: -0.3, z: -0.55 }, (p) =>
    frames(p, 10),
  );
  await page.evaluate(() => (document.getElementById('overlay').style.display = 'none'));
  await frames(page, 5);
  await page.screenshot({ path: resolve(out) });
  console.log(`${out}: the questionnaire panel in immersive-vr`);
  if (h.errors.length) console.error(h.errors.join('\n'));
} finally {
  await h.close();
}
