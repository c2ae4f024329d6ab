#!/usr/bin/env node
// Browser test of the rfsitl live dashboard, in real headless Chromium.
//
// It starts the real emulator twice on loopback with random free ports:
//   1. with --dashboard-control: the page lists exactly the scenario's nodes,
//      its counters change when traffic flows (rfsitl ping and a raw UB-ANC
//      agent), the watched node's spectrum and constellation arrive, and
//      dragging a node far away on the map moves it in the emulator (its links'
//      SNR drop below sensitivity and the heat-map cells change colour);
//   2. without it: the page says moving nodes is off, a drag moves nothing and
//      sends no move, and the server's refusal of a move is shown;
//   3. on a scenario with a fading stage and a moving node: every snapshot
//      carries a new link matrix, clicking a heat-map cell plots that link's
//      gain and the plot gains points (that vary) over time, clicking the cell
//      again drops it, and clicking a link on the map picks that link.
// No console errors are allowed. Full-page screenshots go to $RFSITL_ARTIFACTS
// (default tests/browser/artifacts/).
//
//   RFSITL_BIN=build-dev/apps/rfsitl node tests/browser/dashboard_test.mjs
// Exit code 0 = pass, 1 = fail (the reason is printed).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

import { chromium } from 'playwright-core';

import {
  ARTIFACTS, RFSITL_BIN, TestFailure, check, connectAgent, freeBases, launchChromium, runPing,
  sleep, startEmulator, within,
} from './lib.mjs';

const OVERALL_MS = 150000;
const VERBOSE = !!process.env.VERBOSE;
const started = Date.now();
const log = (...a) => console.log(`[${((Date.now() - started) / 1000).toFixed(1).padStart(5)} s]`, ...a);
const debug = (...a) => { if (VERBOSE) log(...a); };

// Non-contiguous ids, and node 8 without a position (listed beside the map).
const SCENARIO_IDS = [1, 2, 3, 5, 8];
const SCENARIO = `# written by tests/browser/dashboard_test.mjs
name: browser-test
seed: 7
time: {mode: realtime, sample_rate_hz: 1e6, tick_samples: 250}
phy: {type: gmsk}
nodes:
  - {id: 1, position: {x: 0, y: 0, z: 10}}
  - {id: 2, position: {x: 8, y: 0, z: 10}}
  - {id: 3, position: {x: 0, y: 8, z: 10}}
  - {id: 5, position: {x: 8, y: 8, z: 10}}
  - {id: 8}
`;

// Rayleigh fading on every link, 2 to 2.5 km long (a mean SNR near 15 dB, so
// fades cross the receivers' 5.3 dB); node 2 flies a small circle, so its
// links fade as it flies, while 1 <-> 3 rest (and keep their fade).
const FADING_IDS = [1, 2, 3];
const FADING_SCENARIO = `# written by tests/browser/dashboard_test.mjs
name: browser-fading
seed: 11
time: {mode: realtime, sample_rate_hz: 1e6, tick_samples: 250}
phy: {type: gmsk}
channel:
  stages: [{type: path_loss, model: free_space}, {type: fading}]
nodes:
  - {id: 1, position: {x: 0, y: 0, z: 10}}
  - {id: 2, mobility: {type: orbit, centre_x_m: 2000, centre_y_m: 1500, radius_m: 40, speed_mps: 10, altitude_m: 10}}
  - {id: 3, position: {x: 0, y: 2500, z: 10}}
`;

const cleanups = [];
const consoleErrors = [];

function watchConsole(page, label) {
  page.on('console', (m) => {
    debug(`[${label} console.${m.type()}] ${m.text()}`);
    if (m.type() === 'error') consoleErrors.push(`${label}: console.error: ${m.text()}`);
  });
  page.on('pageerror', (e) => consoleErrors.push(`${label}: uncaught: ${e.message}`));
  page.on('requestfailed', (r) => consoleErrors.push(`${label}: request failed: ${r.url()}`));
}

function checkNoConsoleErrors(when) {
  check(consoleErrors.length === 0, `console errors (${when}):\n  ${consoleErrors.join('\n  ')}`);
}

async function screenshot(page, name) {
  await page.evaluate(() => window.scrollTo(0, 0));
  const file = path.join(ARTIFACTS, name);
  await page.screenshot({ path: file, fullPage: true });
  log(`screenshot ${file}`);
}

const dash = (page, fn, arg) => page.evaluate(fn, arg);
const snapshot = (page) => dash(page, () => window.rfsitlDashboard.snapshot);
const cellText = (page, id, cls) => page.textContent(`#node-table tr[data-node="${id}"] td.${cls}`);

async function waitFor(page, what, fn, arg, timeout = 15000) {
  try {
    await page.waitForFunction(fn, arg, { timeout, polling: 100 });
  } catch (e) {
    throw new TestFailure(`timed out after ${timeout / 1000} s waiting for ${what}`);
  }
}

async function openPage(browser, url, label) {
  const context = await browser.newContext({ viewport: { width: 1440, height: 1000 } });
  cleanups.push(() => context.close().catch(() => {}));
  const page = await context.newPage();
  watchConsole(page, label);
  return { context, page };
}

async function gotoLive(page, url) {
  await page.goto(url, { timeout: 15000 });
  await waitFor(page, 'the WebSocket to be live', () =>
    document.querySelector('#conn-state')?.dataset.state === 'open'
    && window.rfsitlDashboard?.snapshot != null);
}

/// The RGBA of the middle of heat-map cell tx -> rx, as drawn now.
async function matrixPixel(page, tx, rx) {
  return dash(page, ([t, r]) => {
    const cell = window.rfsitlDashboard.matrixCell(t, r);
    const canvas = document.querySelector('#matrix canvas');
    const px = canvas.getContext('2d').getImageData(Math.round(cell.x * cell.dpr), Math.round(cell.y * cell.dpr), 1, 1).data;
    return [px[0], px[1], px[2], px[3]];
  }, [tx, rx]);
}
const colourDistance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

/// Mouse-drags node `id` on the map to the viewport point (x, y) in steps.
async function dragNode(page, id, x, y) {
  const from = await dash(page, (n) => window.rfsitlDashboard.nodeClientPosition(n), id);
  check(from, `node ${id} is not on the map`);
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  const steps = 12;
  for (let k = 1; k <= steps; ++k) {
    await page.mouse.move(from.x + (x - from.x) * k / steps, from.y + (y - from.y) * k / steps);
    await sleep(30);
  }
  await page.mouse.up();
  return from;
}

// ---- part 1: control on ----------------------------------------------------------------
async function controlOn(browser, scenarioFile) {
  log('part 1: emulator with --dashboard-control');
  const { netBase, locBase } = await freeBases(SCENARIO_IDS);
  const emu = await startEmulator([scenarioFile, '--net-base', String(netBase), '--loc-base',
    String(locBase), '--dashboard-port', '0', '--dashboard-control', '--stats-interval', '0'],
  { label: 'emulator 1', log: debug });
  cleanups.push(() => emu.stop());
  log(`emulator 1 at ${emu.url} (net base ${netBase})`);

  const { page } = await openPage(browser, emu.url, 'page 1');
  await gotoLive(page, emu.url);

  // The table lists exactly the scenario's nodes, in order; node 8 has no position.
  const ids = await page.$$eval('#node-table tbody tr[data-node]', (rows) => rows.map((r) => Number(r.dataset.node)));
  check(JSON.stringify(ids) === JSON.stringify(SCENARIO_IDS),
    `node table lists ${JSON.stringify(ids)}, the scenario has ${JSON.stringify(SCENARIO_IDS)}`);
  check(await page.$('#unknown-nodes li[data-node="8"]'), 'node 8 (no position) is not listed as unknown');
  check(!(await page.$('#unknown-nodes li[data-node="1"]')), 'node 1 is listed as position unknown');
  check(await dash(page, () => window.rfsitlDashboard.nodeClientPosition(8)) === null, 'node 8 is drawn on the map');
  const control = await page.getAttribute('#control-state', 'data-control');
  check(control === 'on', `#control-state says data-control="${control}" with --dashboard-control`);
  check((await page.textContent('#scenario')) === 'browser-test', 'the header does not name the scenario');
  log(`table lists nodes ${ids.join(', ')}; control on`);

  // Watch node 2: its spectrum arrives (256 bins).
  await page.click('#node-table tr[data-node="2"]');
  await waitFor(page, 'the spectrum of node 2', () => {
    const s = window.rfsitlDashboard.spectrum;
    return window.rfsitlDashboard.selected === 2 && s && s.node === 2 && s.bins_db.length === 256;
  });
  check(await page.$('#node-table tr[data-node="2"].selected'), 'row of node 2 is not marked selected');
  log('watching node 2: spectrum arrives');

  // Traffic: rfsitl ping 1 -> 2, and a raw UB-ANC agent on node 3 sending to 5.
  const before1 = Number(await cellText(page, 1, 'delivered'));
  const before3 = Number(await cellText(page, 3, 'delivered'));
  const agent3 = await connectAgent(netBase, 3);
  cleanups.push(() => agent3.close());
  const ping = runPing(['--src', '1', '--dst', '2', '--count', '40', '--interval', '0.05', '--net-base',
    String(netBase), '--quiet'], 30000);
  for (let k = 0; k < 10; ++k) {
    agent3.send(5, `hello 5 from 3, frame ${k}`);
    await sleep(60);
  }
  await waitFor(page, 'delivered of node 1 to increase in the table', (b) =>
    Number(document.querySelector('#node-table tr[data-node="1"] td.delivered').textContent) > b, before1);
  await waitFor(page, 'the map to highlight link 1 <-> 2 as carrying frames', () =>
    window.rfsitlDashboard.activeLinks().some(([a, b]) => (a === 1 && b === 2) || (a === 2 && b === 1)), undefined, 5000);
  await waitFor(page, 'delivered of node 3 (raw UB-ANC frames) to increase in the table', (b) =>
    Number(document.querySelector('#node-table tr[data-node="3"] td.delivered').textContent) > b, before3);
  await waitFor(page, 'a constellation of a frame 1 -> 2 at node 2', () => {
    const c = window.rfsitlDashboard.constellation;
    return c && c.node === 2 && c.src === 1 && c.dst === 2 && c.valid && c.points.length > 0;
  });
  check((await page.textContent('#constellation-meta dd.src')) === '1', 'constellation src is not shown');
  const pingOut = await ping;
  debug(pingOut.trim());
  await waitFor(page, 'received counts per link in the snapshot', () => {
    const s = window.rfsitlDashboard.snapshot;
    const i = s.nodes.findIndex((n) => n.id === 1), j = s.nodes.findIndex((n) => n.id === 2);
    return s.links.received[i * s.links.n + j] > 0;
  });
  // Hovering heat-map cell 1 -> 2 names the link, its SNR and its counts.
  await page.locator('#matrix').scrollIntoViewIfNeeded();
  const cell = await dash(page, () => window.rfsitlDashboard.matrixCell(1, 2));
  await page.mouse.move(cell.clientX, cell.clientY);
  await waitFor(page, 'the heat-map tooltip of 1 -> 2', () => {
    const t = document.querySelector('#matrix-tooltip');
    const s = window.rfsitlDashboard.snapshot;
    const k = 0 * s.links.n + 1;
    return !t.hidden && t.textContent.includes('tx 1 → rx 2') && t.textContent.includes('SNR')
      && t.textContent.includes(`received ${s.links.received[k]}`);
  }, undefined, 5000);
  await page.mouse.move(2, 2);
  const after1 = Number(await cellText(page, 1, 'delivered'));
  const received2 = Number(await cellText(page, 2, 'received'));
  check(received2 > 0, 'node 2 received nothing according to the table');
  log(`traffic: node 1 delivered ${before1} -> ${after1}, node 3 delivered ${before3} -> `
    + `${await cellText(page, 3, 'delivered')}; constellation 1 -> 2 shown`);
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => r())));
  await screenshot(page, '01-traffic.png');

  // Drag node 5 far away: zoom the map out until a corner is > 400 m from node 1,
  // then drag node 5 to that corner with the mouse.
  const N = SCENARIO_IDS.length;
  const i5 = SCENARIO_IDS.indexOf(5), i1 = SCENARIO_IDS.indexOf(1);
  let snap = await snapshot(page);
  const sens1 = snap.nodes[i1].sensitivity_db;
  const snrBefore = snap.links.snr_db[i5 * N + i1];
  check(snrBefore >= sens1, `link 5 -> 1 does not decode at the start (${snrBefore} dB)`);
  const pixelBefore = await matrixPixel(page, 5, 1);
  await page.locator('#map').scrollIntoViewIfNeeded();
  const box = await page.locator('#map canvas').boundingBox();
  const corner = { x: box.x + box.width - 30, y: box.y + 30 };
  for (let k = 0; k < 40; ++k) {
    const w = await dash(page, (c) => window.rfsitlDashboard.worldAtClient(c.x, c.y), corner);
    if (Math.hypot(w.x, w.y) > 400) break;
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    await page.mouse.wheel(0, 300);
    await sleep(40);
  }
  const target = await dash(page, (c) => window.rfsitlDashboard.worldAtClient(c.x, c.y), corner);
  check(Math.hypot(target.x, target.y) > 400, 'could not zoom the map out far enough');
  await dragNode(page, 5, corner.x, corner.y);
  await waitFor(page, 'node 5 to be far away in the snapshot', (t) => {
    const s = window.rfsitlDashboard.snapshot;
    const p = s.nodes.find((n) => n.id === 5).position;
    return p && Math.hypot(p.x - t.x, p.y - t.y) < 20;
  }, target);
  snap = await snapshot(page);
  const p5 = snap.nodes[i5].position;
  const snrAfter = snap.links.snr_db[i5 * N + i1];
  const snrBack = snap.links.snr_db[i1 * N + i5];
  check(snrAfter < sens1 && snrBack < snap.nodes[i5].sensitivity_db,
    `after the drag, link 5 <-> 1 still decodes (${snrAfter} / ${snrBack} dB)`);
  check(Math.abs(p5.z - 10) < 0.5, `the drag changed node 5's altitude to ${p5.z} m`);
  // Let the page draw the new snapshot, then compare the heat-map cell.
  let pixelAfter;
  for (let k = 0; k < 20; ++k) {
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => r())));
    pixelAfter = await matrixPixel(page, 5, 1);
    if (colourDistance(pixelBefore, pixelAfter) > 60) break;
    await sleep(100);
  }
  check(colourDistance(pixelBefore, pixelAfter) > 60,
    `heat-map cell 5 -> 1 kept its colour: ${pixelBefore} -> ${pixelAfter}`);
  log(`dragged node 5 to x ${p5.x.toFixed(0)} y ${p5.y.toFixed(0)} m: SNR 5 -> 1 ${snrBefore} -> ${snrAfter} dB `
    + `(needs ${sens1}); cell colour rgb(${pixelBefore.slice(0, 3)}) -> rgb(${pixelAfter.slice(0, 3)})`);
  await page.click('#map-fit');
  await sleep(400);
  await screenshot(page, '02-dragged.png');

  const perf = await dash(page, () => window.rfsitlDashboard.perf());
  debug('perf', JSON.stringify(perf));
  checkNoConsoleErrors('control on');
  agent3.close();
  await page.context().close();
  await emu.stop();
}

// ---- part 2: control off ---------------------------------------------------------------
async function controlOff(browser, scenarioFile) {
  log('part 2: emulator without --dashboard-control');
  const { netBase, locBase } = await freeBases(SCENARIO_IDS);
  const emu = await startEmulator([scenarioFile, '--net-base', String(netBase), '--loc-base',
    String(locBase), '--dashboard-port', '0', '--stats-interval', '0'], { label: 'emulator 2', log: debug });
  cleanups.push(() => emu.stop());
  log(`emulator 2 at ${emu.url}`);

  const { page } = await openPage(browser, emu.url, 'page 2');
  // Pass the WebSocket through, recording what the page sends.
  const sent = [];
  let toServer = null;
  await page.routeWebSocket(/\/ws$/, (ws) => {
    const server = ws.connectToServer();
    toServer = server;
    ws.onMessage((m) => {
      sent.push(String(m));
      server.send(m);
    });
  });
  await gotoLive(page, emu.url);
  check(toServer, 'the page did not open its WebSocket');
  const controlText = await page.textContent('#control-state');
  check(controlText.includes('moving nodes is off; start with --dashboard-control'),
    `#control-state says "${controlText}" without --dashboard-control`);
  check((await page.getAttribute('#control-state', 'data-control')) === 'off', '#control-state data-control is not "off"');

  const i2 = SCENARIO_IDS.indexOf(2);
  const before = (await snapshot(page)).nodes[i2].position;
  await page.locator('#map').scrollIntoViewIfNeeded();
  const from = await dash(page, (n) => window.rfsitlDashboard.nodeClientPosition(n), 2);
  await dragNode(page, 2, from.x - 250, from.y - 150);
  await waitFor(page, 'the "moving nodes is off" hint on the map', () => {
    const h = document.querySelector('#map-hint');
    return !h.hidden && h.textContent.includes('--dashboard-control');
  }, undefined, 3000);
  const nowDrawn = await dash(page, (n) => window.rfsitlDashboard.nodeClientPosition(n), 2);
  check(Math.hypot(nowDrawn.x - from.x, nowDrawn.y - from.y) < 2, 'the page drew node 2 somewhere else after the drag');
  await sleep(1500);  // six snapshots
  const after = (await snapshot(page)).nodes[i2].position;
  check(after.x === before.x && after.y === before.y, `node 2 moved without control: ${JSON.stringify(before)} -> ${JSON.stringify(after)}`);
  const moves = sent.filter((m) => JSON.parse(m).type === 'move');
  check(moves.length === 0, `the page sent move messages without control: ${moves.join(' ')}`);
  log('drag without control: hint shown, no move sent, node 2 stayed');

  // Clicking a node on the map (no drag) still selects it for watching.
  const p3 = await dash(page, (n) => window.rfsitlDashboard.nodeClientPosition(n), 3);
  await page.mouse.click(p3.x, p3.y);
  await waitFor(page, 'node 3 to be watched after a click on the map', () =>
    window.rfsitlDashboard.selected === 3
    && document.querySelector('#node-table tr[data-node="3"]').classList.contains('selected')
    && window.rfsitlDashboard.spectrum?.node === 3, undefined, 5000);
  check(sent.some((m) => m === JSON.stringify({ type: 'watch', node: 3 })), 'no watch message for node 3 was sent');

  // The server refuses a move (sent around the page) and the page shows why.
  toServer.send(JSON.stringify({ type: 'move', node: 2, x: 100, y: 100, z: 10 }));
  await waitFor(page, 'the server\'s refusal to be shown', () =>
    [...document.querySelectorAll('#messages .msg')].some((m) => m.textContent.includes('control is off')), undefined, 5000);
  const res = await fetch(new URL('/api/nodes/2/position', emu.url), { method: 'POST', body: '{"x":1,"y":2,"z":3}' });
  check(res.status === 403, `POST /api/nodes/2/position without control answered ${res.status}, not 403`);
  log('server refusal shown on the page; POST answers 403');
  await screenshot(page, '03-control-off.png');
  checkNoConsoleErrors('control off');
  await page.context().close();
  await emu.stop();
}

// ---- part 3: a fading channel and the link plot -------------------------------------------
/// How many pixels of the link plot are drawn in the link's colour (#ffd65a).
async function linkPlotPixels(page) {
  return dash(page, () => {
    const canvas = document.querySelector('#link-gain canvas');
    const px = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
    let n = 0;
    for (let k = 0; k < px.length; k += 4) {
      if (Math.abs(px[k] - 255) + Math.abs(px[k + 1] - 214) + Math.abs(px[k + 2] - 90) < 60 && px[k + 3] > 200) ++n;
    }
    return n;
  });
}

async function fadingLinkPlot(browser, scenarioFile) {
  log('part 3: a fading channel, the link plot');
  const { netBase, locBase } = await freeBases(FADING_IDS);
  const emu = await startEmulator([scenarioFile, '--net-base', String(netBase), '--loc-base',
    String(locBase), '--dashboard-port', '0', '--stats-interval', '0'], { label: 'emulator 3', log: debug });
  cleanups.push(() => emu.stop());
  log(`emulator 3 at ${emu.url}`);

  const { page } = await openPage(browser, emu.url, 'page 3');
  // Whether each snapshot the server sends carries the link matrix (it is sent
  // only when a gain changed since the previous one).
  const withMatrix = [];
  await page.routeWebSocket(/\/ws$/, (ws) => {
    const server = ws.connectToServer();
    server.onMessage((m) => {
      const msg = JSON.parse(String(m));
      if (msg.type === 'snapshot') withMatrix.push(Array.isArray(msg.links?.snr_db));
      ws.send(m);
    });
  });
  await gotoLive(page, emu.url);
  check((await page.textContent('#link-info')).includes('click a cell'), 'the link plot does not say how to pick a link');
  check(await dash(page, () => window.rfsitlDashboard.linkPlot()) === null, 'a link is plotted before any click');

  // Click heat-map cell 1 -> 2: the plot names the link, its receiver is watched.
  await page.locator('#matrix').scrollIntoViewIfNeeded();
  const cell = await dash(page, () => window.rfsitlDashboard.matrixCell(1, 2));
  await page.mouse.click(cell.clientX, cell.clientY);
  await waitFor(page, 'link 1 -> 2 to be plotted after a click on its cell', () => {
    const d = window.rfsitlDashboard;
    const p = d.linkPlot();
    return JSON.stringify(d.link) === '[1,2]' && p && p.points > 0
      && document.querySelector('#link-name').textContent === '1 → 2' && d.selected === 2;
  }, undefined, 5000);
  const first = await dash(page, () => window.rfsitlDashboard.linkPlot());
  const info = await page.textContent('#link-info');
  check(/now -?\d+\.\d dB · SNR -?\d+\.\d dB/.test(info), `the link plot's line says "${info}"`);
  log(`clicked cell 1 -> 2: plotted with ${first.points} points; "${info}"`);

  // Over time the plot gets more points, and they differ: the gain fades.
  await waitFor(page, 'the link plot to get 12 more points, of at least 6 gains', (n) => {
    const p = window.rfsitlDashboard.linkPlot();
    return p && p.points >= n + 12 && p.distinct >= 6;
  }, first.points, 15000);
  const later = await dash(page, () => window.rfsitlDashboard.linkPlot());
  const pixels = await linkPlotPixels(page);
  check(pixels > 100, `the link plot has ${pixels} pixels in the link's colour`);
  check(later.hi - later.lo >= 10, `the link plot's dB axis spans ${later.lo}..${later.hi}`);
  // Every snapshot after the first carried a new matrix: the gains fade between publications.
  const sent = withMatrix.slice(1);
  const carried = sent.filter(Boolean).length;
  check(sent.length >= 12 && carried >= sent.length - 1,
    `only ${carried} of ${sent.length} snapshots carried the link matrix with fading on`);
  log(`link plot: ${later.points} points, ${later.distinct} distinct gains, ${later.lo}..${later.hi} dB; `
    + `${carried} of ${sent.length} snapshots carried the matrix`);
  await page.mouse.move(2, 2);
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => r())));
  await screenshot(page, '04-link-gain.png');
  await page.locator('#matrix-panel').screenshot({ path: path.join(ARTIFACTS, '04b-link-gain-panel.png') });

  // The same cell again drops the plot.
  await page.locator('#matrix').scrollIntoViewIfNeeded();
  const again = await dash(page, () => window.rfsitlDashboard.matrixCell(1, 2));
  await page.mouse.click(again.clientX, again.clientY);
  await waitFor(page, 'the link plot to be dropped by a second click', () =>
    window.rfsitlDashboard.link === null && window.rfsitlDashboard.linkPlot() === null
    && document.querySelector('#link-clear').disabled, undefined, 3000);

  // A link on the map, clicked nearer node 3: link 3 -> 1. Clear drops it.
  await page.locator('#map').scrollIntoViewIfNeeded();
  const a = await dash(page, (n) => window.rfsitlDashboard.nodeClientPosition(n), 3);
  const b = await dash(page, (n) => window.rfsitlDashboard.nodeClientPosition(n), 1);
  check(a && b && Math.hypot(a.x - b.x, a.y - b.y) > 80, 'nodes 1 and 3 are not drawn far enough apart');
  await page.mouse.click(a.x + (b.x - a.x) * 0.3, a.y + (b.y - a.y) * 0.3);
  await waitFor(page, 'link 3 -> 1 to be plotted after a click on the map', () =>
    JSON.stringify(window.rfsitlDashboard.link) === '[3,1]' && window.rfsitlDashboard.linkPlot()?.points > 0,
  undefined, 3000);
  await page.click('#link-clear');
  await waitFor(page, 'Clear to drop the plot', () => window.rfsitlDashboard.link === null, undefined, 3000);
  log('second click on the cell drops the plot; a click on map link 1 - 3 near 3 plots 3 -> 1; Clear drops it');
  checkNoConsoleErrors('fading');
  await page.context().close();
  await emu.stop();
}

// ---- main ------------------------------------------------------------------------------
async function main() {
  fs.mkdirSync(ARTIFACTS, { recursive: true });
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'rfsitl-browser-'));
  cleanups.push(() => fs.rmSync(tmp, { recursive: true, force: true }));
  const scenarioFile = path.join(tmp, 'browser_test.yaml');
  fs.writeFileSync(scenarioFile, SCENARIO);
  const fadingFile = path.join(tmp, 'browser_fading.yaml');
  fs.writeFileSync(fadingFile, FADING_SCENARIO);
  log(`emulator ${RFSITL_BIN}; artifacts in ${ARTIFACTS}`);
  const browser = await launchChromium(chromium);
  cleanups.push(() => browser.close().catch(() => {}));
  log(`Chromium ${browser.version()}`);
  await controlOn(browser, scenarioFile);
  await controlOff(browser, scenarioFile);
  await fadingLinkPlot(browser, fadingFile);
}

async function cleanup() {
  for (const f of cleanups.reverse()) {
    try {
      await within(8000, 'cleanup', Promise.resolve().then(f));
    } catch { /* keep going: the process exit kills the rest */ }
  }
}

const overall = setTimeout(async () => {
  console.error(`FAIL: the test took longer than ${OVERALL_MS / 1000} s`);
  await cleanup();
  process.exit(1);
}, OVERALL_MS);

try {
  await main();
  await cleanup();
  clearTimeout(overall);
  log('PASS');
  process.exit(0);
} catch (e) {
  console.error(`FAIL: ${e instanceof TestFailure ? e.message : e.stack || e}`);
  await cleanup();
  clearTimeout(overall);
  process.exit(1);
}
