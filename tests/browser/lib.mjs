// Shared helpers of the browser tests: free ports, the emulator as a child
// process (always killed), traffic through the UB-ANC net ports, Chromium.
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import net from 'node:net';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

export const HERE = path.dirname(fileURLToPath(import.meta.url));
export const REPO = path.resolve(HERE, '..', '..');
export const RFSITL_BIN = process.env.RFSITL_BIN || path.join(REPO, 'build-dev', 'apps', 'rfsitl');
export const CHROMIUM = process.env.CHROMIUM_PATH || '/usr/bin/chromium';
export const ARTIFACTS = path.resolve(process.env.RFSITL_ARTIFACTS || path.join(HERE, 'artifacts'));

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

export class TestFailure extends Error {}
export function check(cond, message) {
  if (!cond) throw new TestFailure(message);
}

/// Resolves with `promise` or rejects after `ms` with a message naming `what`.
export function within(ms, what, promise) {
  let timer;
  return Promise.race([
    promise,
    new Promise((_, reject) => {
      timer = setTimeout(() => reject(new TestFailure(`timed out after ${ms / 1000} s: ${what}`)), ms);
    }),
  ]).finally(() => clearTimeout(timer));
}

function portFree(port) {
  return new Promise((resolve) => {
    const s = net.createServer();
    s.once('error', () => resolve(false));
    s.listen({ port, host: '127.0.0.1', exclusive: true }, () => s.close(() => resolve(true)));
  });
}

/// A net base and a location base (ports base + 10 * id) whose ports are all free now.
export async function freeBases(ids) {
  for (let attempt = 0; attempt < 200; ++attempt) {
    const maxId = Math.max(...ids);
    const span = 10 * maxId + 10;
    // Below the ephemeral range (32768+), where the dashboard port 0 lands.
    const netBase = 20000 + 10 * Math.floor(Math.random() * ((32000 - 20000 - span) / 10));
    const locBase = netBase + 3;  // interleaved: net n = base + 10 n, loc n = base + 3 + 10 n
    const ports = ids.flatMap((id) => [netBase + 10 * id, locBase + 10 * id]);
    let ok = true;
    for (const p of ports) {
      if (!(await portFree(p))) { ok = false; break; }
    }
    if (ok) return { netBase, locBase };
  }
  throw new TestFailure('found no free block of ports on 127.0.0.1');
}

const children = new Set();
function killAllSync() {
  for (const c of children) {
    try { c.kill('SIGKILL'); } catch { /* already gone */ }
  }
}
process.on('exit', killAllSync);
for (const sig of ['SIGINT', 'SIGTERM', 'SIGHUP']) {
  process.on(sig, () => {
    console.error(`interrupted (${sig}): stopping the emulator`);
    killAllSync();
    process.exit(1);
  });
}

/// Starts `rfsitl run ARGS`; resolves once it printed its dashboard URL.
export async function startEmulator(args, { label = 'emulator', log = () => {} } = {}) {
  check(fs.existsSync(RFSITL_BIN), `no emulator at ${RFSITL_BIN} (build it or set RFSITL_BIN)`);
  const child = spawn(RFSITL_BIN, ['run', ...args], { stdio: ['ignore', 'pipe', 'pipe'] });
  children.add(child);
  let out = '';
  let err = '';
  const emu = {
    child,
    url: null,
    get stdout() { return out; },
    get stderr() { return err; },
    exited: new Promise((resolve) => child.once('exit', (code, signal) => {
      children.delete(child);
      resolve({ code, signal });
    })),
    async stop() {
      if (child.exitCode !== null || child.signalCode !== null) return;
      child.kill('SIGTERM');
      const done = await Promise.race([emu.exited, sleep(4000).then(() => null)]);
      if (!done) {
        child.kill('SIGKILL');
        await emu.exited;
      }
    },
  };
  child.stdout.setEncoding('utf8');
  child.stderr.setEncoding('utf8');
  child.stderr.on('data', (d) => { err += d; log(`[${label} stderr] ${d.trimEnd()}`); });
  const url = await within(20000, `${label} printing its dashboard URL`, new Promise((resolve, reject) => {
    child.stdout.on('data', (d) => {
      out += d;
      const m = /dashboard (http:\/\/\S+)/.exec(out);
      if (m && /ready, listening/.test(out)) resolve(m[1]);
    });
    child.once('exit', (code, signal) => reject(new TestFailure(
      `${label} exited (code ${code}, signal ${signal}) before it was ready:\n${out}\n${err}`)));
    child.once('error', (e) => reject(new TestFailure(`cannot start ${RFSITL_BIN}: ${e.message}`)));
  }));
  emu.url = url;
  return emu;
}

/// Runs `rfsitl ping ...` to completion (bounded); resolves with its stdout.
export function runPing(args, timeoutMs = 30000) {
  return within(timeoutMs, `rfsitl ping ${args.join(' ')}`, new Promise((resolve, reject) => {
    const child = spawn(RFSITL_BIN, ['ping', ...args], { stdio: ['ignore', 'pipe', 'pipe'] });
    children.add(child);
    let out = '';
    child.stdout.on('data', (d) => { out += d; });
    child.stderr.on('data', (d) => { out += d; });
    child.once('exit', (code) => {
      children.delete(child);
      if (code === 0) resolve(out);
      else reject(new TestFailure(`rfsitl ping exited with ${code}:\n${out}`));
    });
  }));
}

/// An agent speaking the UB-ANC framing on node `id`'s net port:
/// [src][dst][payload]\r\r\n\n per frame.
export async function connectAgent(netBase, id) {
  const sock = await within(5000, `connecting to net port of node ${id}`, new Promise((resolve, reject) => {
    const s = net.connect({ host: '127.0.0.1', port: netBase + 10 * id }, () => resolve(s));
    s.once('error', reject);
  }));
  sock.on('data', () => {});  // frames handed to this agent: not needed
  return {
    send(dst, payload) {
      const body = Buffer.concat([Buffer.from([id, dst]), Buffer.from(payload), Buffer.from('\r\r\n\n')]);
      sock.write(body);
    },
    close() { sock.destroy(); },
  };
}

export async function launchChromium(chromium) {
  check(fs.existsSync(CHROMIUM), `no Chromium at ${CHROMIUM}: apt-get install -y chromium (or set CHROMIUM_PATH)`);
  return chromium.launch({ executablePath: CHROMIUM, headless: true, timeout: 20000,
    args: ['--disable-gpu', '--no-first-run', '--disable-dev-shm-usage'] });
}
