#!/usr/bin/env node
// Measures the dashboard's JavaScript time with a big swarm (not a pass/fail
// test): runs `rfsitl run --nodes N` (default 64), opens the page in headless
// Chromium, watches a node, makes some traffic, waits, and prints the page's
// own timings (window.rfsitlDashboard.perf(): performance.now() around each
// message handler and each drawing). Also saves artifacts/perf-<N>.png.
//
//   node tests/browser/perf.mjs [--nodes 64] [--seconds 12]
import path from 'node:path';
import { spawn } from 'node:child_process';

import { chromium } from 'playwright-core';

import { ARTIFACTS, RFSITL_BIN, freeBases, launchChromium, sleep, startEmulator } from './lib.mjs';

const arg = (name, dflt) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? Number(process.argv[i + 1]) : dflt;
};
const nodes = arg('--nodes', 64);
const seconds = arg('--seconds', 12);
const ids = Array.from({ length: nodes }, (_, i) => i + 1);

const { netBase, locBase } = await freeBases(ids);
const emu = await startEmulator(['--nodes', String(nodes), '--net-base', String(netBase), '--loc-base',
  String(locBase), '--dashboard-port', '0', '--dashboard-control', '--stats-interval', '0']);
const pings = [];
let browser;
try {
  browser = await launchChromium(chromium);
  const page = await browser.newPage({ viewport: { width: 1440, height: 1000 } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  await page.goto(emu.url);
  await page.waitForFunction(() => window.rfsitlDashboard?.snapshot != null, null, { timeout: 15000 });
  await page.click(`#node-table tr[data-node="${Math.min(2, nodes)}"]`);
  await page.evaluate(() => window.scrollTo(0, 0));
  for (const [a, b] of [[1, nodes], [3, Math.max(4, nodes - 9)]]) {
    if (a >= b || b > nodes) continue;
    pings.push(spawn(RFSITL_BIN, ['ping', '--src', String(a), '--dst', String(b), '--count', '100000',
      '--interval', '0.05', '--net-base', String(netBase), '--quiet'], { stdio: 'ignore' }));
  }
  await sleep(seconds * 1000);
  const perf = await page.evaluate(() => window.rfsitlDashboard.perf());
  const snap = await page.evaluate(() => window.rfsitlDashboard.snapshot);
  const bytes = await page.evaluate(() => JSON.stringify(window.rfsitlDashboard.snapshot).length);
  await page.screenshot({ path: path.join(ARTIFACTS, `perf-${nodes}.png`), fullPage: true });
  console.log(`nodes ${nodes}, ${seconds} s, snapshot ${bytes} bytes of JSON, late_ticks ${snap.late_ticks}`);
  console.log('ms per item (mean / p95 / max, n):');
  for (const [k, v] of Object.entries(perf)) {
    console.log(`  ${k.padEnd(22)} ${String(v.mean).padStart(7)} ${String(v.p95).padStart(7)} ${String(v.max).padStart(7)}  n=${v.n}`);
  }
  const m = (k) => perf[k]?.mean ?? 0;
  console.log(`per snapshot: parse+handle ${(m('parse') + m('handle_snapshot')).toFixed(2)} ms, `
    + `draw map ${m('draw_map').toFixed(2)} ms, matrix ${m('draw_matrix').toFixed(2)} ms, `
    + `traffic ${m('draw_traffic').toFixed(2)} ms`);
  if (errors.length) console.log(`console errors: ${errors.join(' | ')}`);
} finally {
  for (const p of pings) p.kill('SIGTERM');
  if (browser) await browser.close();
  await emu.stop();
}
