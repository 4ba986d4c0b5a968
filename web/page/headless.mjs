// Headless Chromium as grove's scripts and tests drive it: Debian's /usr/bin/chromium (or
// CHROMIUM), drawing through SwiftShader's GL and fetching nothing of its own; and an ES module
// bundled in memory by esbuild for a page it opens. Used by render.mjs, web/compare and the
// page's test harness.

import { build } from 'esbuild';
import { chromium } from 'playwright-core';

export const CHROMIUM = process.env.CHROMIUM ?? '/usr/bin/chromium';

/** Launches headless Chromium with SwiftShader's GL, and `args` besides. */
export function launchChromium(args = []) {
  return chromium.launch({
    executablePath: CHROMIUM,
    args: [
      '--no-sandbox',
      '--use-angle=swiftshader',
      '--enable-unsafe-swiftshader',
      '--disable-background-networking',
      '--ignore-gpu-blocklist',
      ...args,
    ],
  });
}

/** `entry` and what it imports bundled into one ES module's text (node: imports left out), paths from `dir`. */
export async function bundleModule(entry, dir) {
  const out = await build({
    entryPoints: [entry],
    bundle: true,
    format: 'esm',
    target: 'es2022',
    write: false,
    logLevel: 'error',
    external: ['node:*'],
    absWorkingDir: dir,
  });
  return out.outputFiles[0].text;
}
