// docs/protocol-form.png: the form page (/protocol) on an instrument with an item of every kind
// (tests/fixtures/questionnaires/every-kind.ron), some answered. Run after `cargo build` and the
// pages' build (node web/page/build.mjs):
//
//   node web/protocol/test/form-screenshot.mjs OUT.png

import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';

import { GROVE, ROOT } from '../../client/test/helpers.mjs';

const out = process.argv[2];
if (!out) {
  console.error('usage: node web/protocol/test/form-screenshot.mjs OUT.png');
  process.exit(2);
}
const dir = mkdtempSync(join(tmpdir(), 'grove-form-shot-'));
const server = spawn(GROVE, ['serve', '--port', '0', '--out', dir, '--protocol', 'tests/fixtures/questionnaires/every-kind.ron'], { cwd: ROOT, stdio: ['ignore', 'pipe', 'pipe'] });
let browser = null;
try {
  const url = await new Promise((ok, fail) => {
    let log = '';
    const seen = (d) => {
      log += d;
      const m = log.match(/listening on (\S+)/);
      if (m) ok(m[1]);
    };
    server.stdout.on('data', seen);
    server.stderr.on('data', seen);
    server.on('exit', (code) => fail(new Error(`grove serve ended (${code}): ${log}`)));
  });
  await fetch(new URL('/api/protocol/participants', url), { method: 'POST', body: '{}' });
  const { chromium } = await import('playwright-core');
  browser = await chromium.launch({ executablePath: '/usr/bin/chromium', args: ['--no-sandbox', '--disable-background-networking'] });
  const page = await browser.newPage({ viewport: { width: 760, height: 1000 } });
  await page.goto(new URL('/protocol?participant=P01', url).href);
  await page.locator("form#questionnaire[data-instrument='every-kind']").waitFor();
  await page.check('fieldset[data-item=rating] input[value="8"]');
  await page.check('fieldset[data-item=scale] input[value="15"]');
  await page.check('fieldset[data-item=likert_words] input[value="4"]');
  await page.check('fieldset[data-item=single] input[value="Green"]');
  await page.check('fieldset[data-item=several] input[value="a"]');
  await page.check('fieldset[data-item=several] input[value="c"]');
  await page.fill('fieldset[data-item=short_text] textarea', 'at most twelve characters');
  await page.screenshot({ path: resolve(out), fullPage: true });
  console.log(`${out}: the form page on every kind of item`);
} finally {
  await browser?.close();
  server.kill('SIGTERM');
  rmSync(dir, { recursive: true, force: true });
}
