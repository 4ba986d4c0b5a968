// What the client tests share: a grove server in a temporary folder, a proxy that can stop
// forwarding (a network that drops), and the study's recordings.

import { spawn } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import net from 'node:net';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

export const ROOT = resolve(dirname(fileURLToPath(import.meta.url)), '../../..');
export const GROVE = process.env.GROVE_BIN ?? join(ROOT, 'target/debug/grove');

/** The lines of a recording in replays/study (without their newlines). */
export function studyLines(name) {
  const text = readFileSync(join(ROOT, 'replays/study', name), 'utf8');
  return text.split('\n').slice(0, -1);
}

/** Starts `grove serve --port 0` on a new folder; resolves to { url, dir, stop, log }. */
export async function startServer(extra = []) {
  const dir = mkdtempSync(join(tmpdir(), 'grove-client-test-'));
  const child = spawn(GROVE, ['serve', '--port', '0', '--out', dir, ...extra], {
    cwd: ROOT,
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  let log = '';
  const url = await new Promise((resolveUrl, reject) => {
    const timer = setTimeout(() => reject(new Error(`grove serve did not start: ${log}`)), 20000);
    child.stdout.on('data', (d) => {
      log += d;
      const m = log.match(/listening on (\S+)/);
      if (m) {
        clearTimeout(timer);
        resolveUrl(m[1]);
      }
    });
    child.stderr.on('data', (d) => (log += d));
    child.on('exit', (code) => reject(new Error(`grove serve ended (${code}): ${log}`)));
  });
  const stop = async () => {
    if (child.exitCode === null) {
      const ended = new Promise((r) => child.once('exit', r));
      child.kill('SIGTERM');
      await ended;
    }
    rmSync(dir, { recursive: true, force: true });
  };
  return { url, dir, stop, log: () => log };
}

/**
 * A TCP proxy to `target` (host:port). `drop()` stops forwarding: bytes on open connections go
 * nowhere and new connections are accepted but never connected, as on a network that is gone;
 * `restore()` closes those connections and forwards again.
 */
export async function startProxy(targetUrl) {
  const target = new URL(targetUrl);
  let dropped = false;
  const sockets = new Set();
  const server = net.createServer((client) => {
    sockets.add(client);
    client.on('close', () => sockets.delete(client));
    client.on('error', () => {});
    if (dropped) {
      client.pause();
      return;
    }
    const upstream = net.connect(Number(target.port), target.hostname);
    sockets.add(upstream);
    upstream.on('close', () => {
      sockets.delete(upstream);
      client.destroy();
    });
    upstream.on('error', () => client.destroy());
    client.on('close', () => upstream.destroy());
    client.on('data', (d) => {
      if (!dropped) upstream.write(d);
    });
    upstream.on('data', (d) => {
      if (!dropped) client.write(d);
    });
  });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  const url = `http://127.0.0.1:${server.address().port}/`;
  return {
    url,
    drop() {
      dropped = true;
    },
    restore() {
      for (const s of sockets) s.destroy();
      dropped = false;
    },
    close() {
      for (const s of sockets) s.destroy();
      return new Promise((r) => server.close(r));
    },
  };
}
