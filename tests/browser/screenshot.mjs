#!/usr/bin/env node
// Makes the README's picture of the dashboard: scenarios/fifteen_uav.yaml with
// four ping flows, node 8 watched (spectrum, waterfall, constellation).
//
//   node tests/browser/screenshot.mjs [OUTPUT]     (default docs/dashboard.png)
import path from 'node:path';
import { spawn } from 'node:child_process';

import { chromium } from 'playwright-core';

import { REPO, RFSITL_BIN, freeBases, launchChromium, sleep, startEmulator } from './lib.mjs';

const output = path.resolve(process.argv[2] || path.join(REPO, 'docs', 'dashboard.png'));
const ids = Array.from({ length: 15 }, (_, i) => i + 1);
const { netBase, locBase } = await freeBases(ids);
const emu = await startEmulator([path.join(REPO, 'scenarios', 'fifteen_uav.yaml'), '--net-base', String(netBase),
  '--loc-base', String(locBase), '--dashboard-port', '0', '--dashboard-control', '--stats-interval', '0']);
const pings = [];
let browser;
try {
  browser = await launchChromium(chromium);
  const page = await browser.newPage({ viewport: { width: 1440, height: 1100 } });
  await page.goto(emu.url);
  await page.waitForFunction(() => window.rfsitlDashboard?.snapshot != null, null, { timeout: 15000 });
  await page.click('#node-table tr[data-node="8"]');
  await page.evaluate(() => window.scrollTo(0, 0));
  for (const [a, b, interval] of [[4, 8, 0.04], [1, 15, 0.07], [6, 12, 0.1], [11, 3, 0.13]]) {
    pings.push(spawn(RFSITL_BIN, ['ping', '--src', String(a), '--dst', String(b), '--count', '100000',
      '--interval', String(interval), '--net-base', String(netBase), '--quiet'], { stdio: 'ignore' }));
  }
  await sleep(15000);
  await page.mouse.move(5, 5);
  await page.screenshot({ path: output });
  console.log(`wrote ${output}`);
} finally {
  for (const p of pings) p.kill('SIGTERM');
  if (browser) await browser.close();
  await emu.stop();
}
