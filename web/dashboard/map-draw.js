// Draws the map: grid, links (coloured and sized by SNR, dashed by how many
// directions decode), the glow of links that carried or lost frames in the last
// ACTIVE_MS, the nodes with their ids and headings (faded when their position
// source went silent), and a scale bar.
//
// Performance: at 64 nodes there are 2016 node pairs, so links are batched by
// (style, colour, width) and a frame strokes a few dozen paths, not thousands.
import { LUT_CSS, phyColour } from './colour.js';
import { $, setText } from './dom.js';
import { fmtMetres } from './format.js';
import { LINK_COLOUR } from './link-plot.js';
import { fitView, mapSurface, nodeRadius, nodeWorld, toScreenX, toScreenY, toWorld } from './map-view.js';
import { niceStep } from './math.js';
import { registerDrawer, requestDraw } from './scheduler.js';
import { decodes } from './snapshot.js';
import { snrIndex } from './snr-scale.js';
import { ACTIVE_MS, state } from './state.js';

const linkFilter = $('#link-filter');
const mapInfo = $('#map-info');
let fadeTimer = 0;

// Where a node points, in radians clockwise from north (the screen's up): its
// reported yaw, else the direction of its velocity when it moves (> 0.2 m/s);
// null when neither is known.
function headingOf(node) {
  if (node.attitude) return node.attitude.yaw_rad;
  const v = node.velocity;
  if (v && Math.hypot(v.east_mps, v.north_mps) > 0.2) return Math.atan2(v.east_mps, v.north_mps);
  return null;
}

function drawMap() {
  const ctx = mapSurface.begin();
  const W = mapSurface.w, H = mapSurface.h;
  const s = state.snap;
  if (!s) {
    ctx.fillStyle = '#8793a4';
    ctx.font = '13px system-ui, sans-serif';
    ctx.fillText(state.conn === 'open' ? 'waiting for the first snapshot…' : 'connecting…', 16, 24);
    return;
  }
  if (state.autoFit && !state.drag) fitView();
  const N = s.links.n;
  const sx = new Float64Array(N), sy = new Float64Array(N), known = new Uint8Array(N);
  let nKnown = 0;
  for (let i = 0; i < N; ++i) {
    const p = nodeWorld(i);
    if (!p) continue;
    sx[i] = toScreenX(p.x);
    sy[i] = toScreenY(p.y);
    known[i] = 1;
    ++nKnown;
  }

  // Grid at the scale bar's step, origin axes a little brighter.
  const step = niceStep(110 / state.view.scale);
  const wx0 = toWorld(0, H).x, wx1 = toWorld(W, 0).x, wy0 = toWorld(0, H).y, wy1 = toWorld(W, 0).y;
  if ((wx1 - wx0) / step < 80 && (wy1 - wy0) / step < 80) {
    ctx.beginPath();
    for (let x = Math.ceil(wx0 / step) * step; x <= wx1; x += step) {
      const X = Math.round(toScreenX(x)) + 0.5;
      ctx.moveTo(X, 0); ctx.lineTo(X, H);
    }
    for (let y = Math.ceil(wy0 / step) * step; y <= wy1; y += step) {
      const Y = Math.round(toScreenY(y)) + 0.5;
      ctx.moveTo(0, Y); ctx.lineTo(W, Y);
    }
    ctx.strokeStyle = '#161d26';
    ctx.lineWidth = 1;
    ctx.stroke();
  }
  ctx.beginPath();
  ctx.moveTo(toScreenX(0), 0); ctx.lineTo(toScreenX(0), H);
  ctx.moveTo(0, toScreenY(0)); ctx.lineTo(W, toScreenY(0));
  ctx.strokeStyle = '#222c39';
  ctx.stroke();

  // Links: each undirected pair once, batched by (style, colour, width).
  const filter = linkFilter.value;
  const snr = s.links.snr_db;
  const dense = nKnown > 24;
  const now = performance.now();
  let decoding = 0;
  const drawnLinks = [];  // i, j and both ends on screen per pair, for clicks (map-view.js linkAt)
  if (filter !== 'none') {
    const buckets = new Map();
    for (let i = 0; i < N; ++i) {
      if (!known[i]) continue;
      for (let j = i + 1; j < N; ++j) {
        if (!known[j]) continue;
        const a = snr[i * N + j], b = snr[j * N + i];
        if (a == null && b == null) continue;
        const v = a == null ? b : b == null ? a : Math.max(a, b);
        const dij = decodes(i, j), dji = decodes(j, i);
        const ok = (dij !== false) + (dji !== false);
        if (ok > 0) ++decoding;
        if (filter === 'decoding' && ok === 0) continue;
        if (filter === 'active') {
          const t = Math.max(state.activeRx[i * N + j], state.activeRx[j * N + i],
            state.activeLost[i * N + j], state.activeLost[j * N + i]);
          if (!(now - t < ACTIVE_MS)) continue;
        }
        let cls;
        if (ok === 2) cls = 0;
        else if (ok === 1) cls = 1;
        else {
          // Far below sensitivity: not drawn at all (keeps big swarms readable).
          const need = Math.min(s.nodes[i].sensitivity_db ?? 0, s.nodes[j].sensitivity_db ?? 0);
          if (v < need - 20) continue;
          cls = 2;
        }
        const ci = snrIndex(v) >> 3;  // 32 colour steps
        const wi = cls === 2 ? 0 : Math.min(3, Math.floor((ci / 32) * 4));
        const key = (cls * 32 + ci) * 4 + wi;
        let bucket = buckets.get(key);
        if (!bucket) buckets.set(key, (bucket = { cls, ci, wi, pts: [] }));
        bucket.pts.push(sx[i], sy[i], sx[j], sy[j]);
        drawnLinks.push(i, j, sx[i], sy[i], sx[j], sy[j]);
      }
    }
    ctx.lineCap = 'round';
    for (const bucket of buckets.values()) {
      const { cls, ci, wi, pts } = bucket;
      ctx.beginPath();
      for (let k = 0; k < pts.length; k += 4) {
        ctx.moveTo(pts[k], pts[k + 1]);
        ctx.lineTo(pts[k + 2], pts[k + 3]);
      }
      ctx.strokeStyle = LUT_CSS[ci * 8 + 4];
      const width = (0.9 + wi * 0.9) * (dense ? 0.6 : 1);
      if (cls === 0) {
        ctx.setLineDash([]);
        ctx.globalAlpha = dense ? 0.4 : 0.9;
        ctx.lineWidth = width;
      } else if (cls === 1) {
        ctx.setLineDash([7, 5]);
        ctx.globalAlpha = dense ? 0.45 : 0.85;
        ctx.lineWidth = Math.max(1, width * 0.8);
      } else {
        ctx.setLineDash([1.5, 5]);
        ctx.globalAlpha = dense ? 0.18 : 0.4;
        ctx.lineWidth = 1.2;
      }
      ctx.stroke();
    }
    ctx.setLineDash([]);
    ctx.globalAlpha = 1;
  }

  // Links that carried (or lost) frames in the last ACTIVE_MS: a glow and an
  // arrowhead toward the receiver, fading with age (4 alpha steps, batched).
  const glow = [[], [], [], [], [], [], [], []];  // [kind * 4 + level] -> tx, rx pairs
  const Nn = N * N;
  for (let k = 0; k < Nn; ++k) {
    const tr = state.activeRx[k], tl = state.activeLost[k];
    if (tr === 0 && tl === 0) continue;
    const i = (k / N) | 0, j = k - i * N;
    if (!known[i] || !known[j]) continue;
    const ageR = now - tr, ageL = now - tl;
    if (ageR < ACTIVE_MS) glow[Math.min(3, Math.floor(ageR / ACTIVE_MS * 4))].push(i, j);
    if (ageL < ACTIVE_MS) glow[4 + Math.min(3, Math.floor(ageL / ACTIVE_MS * 4))].push(i, j);
  }
  let anyGlow = false;
  const r = nodeRadius();
  for (let g = 0; g < 8; ++g) {
    const list = glow[g];
    if (!list.length) continue;
    anyGlow = true;
    const alpha = (1 - (g % 4) / 4) * 0.75;
    const colour = g < 4 ? '255,255,255' : '255,90,90';
    ctx.beginPath();
    for (let k = 0; k < list.length; k += 2) {
      ctx.moveTo(sx[list[k]], sy[list[k]]);
      ctx.lineTo(sx[list[k + 1]], sy[list[k + 1]]);
    }
    ctx.strokeStyle = `rgba(${colour},${alpha * 0.45})`;
    ctx.lineWidth = 7;
    ctx.stroke();
    ctx.beginPath();
    for (let k = 0; k < list.length; k += 2) {
      const a = list[k], b = list[k + 1];
      const dx = sx[b] - sx[a], dy = sy[b] - sy[a];
      const len = Math.hypot(dx, dy);
      if (len < 3 * r) continue;
      const ux = dx / len, uy = dy / len;
      const tipX = sx[b] - ux * (r + 4), tipY = sy[b] - uy * (r + 4);
      ctx.moveTo(tipX, tipY);
      ctx.lineTo(tipX - ux * 10 - uy * 5, tipY - uy * 10 + ux * 5);
      ctx.lineTo(tipX - ux * 10 + uy * 5, tipY - uy * 10 - ux * 5);
      ctx.closePath();
    }
    ctx.fillStyle = `rgba(${colour},${alpha + 0.2})`;
    ctx.fill();
  }
  if (anyGlow && !fadeTimer) {  // keep fading between snapshots (one timer at a time)
    fadeTimer = setTimeout(() => { fadeTimer = 0; requestDraw('map'); }, 250);
  }
  state.mapLinks = drawnLinks;

  // The link whose gain is plotted: a band with an arrowhead toward its receiver.
  const lt = state.link ? state.indexOf.get(state.link[0]) : undefined;
  const lr = state.link ? state.indexOf.get(state.link[1]) : undefined;
  if (lt !== undefined && lr !== undefined && known[lt] && known[lr]) {
    ctx.beginPath();
    ctx.moveTo(sx[lt], sy[lt]);
    ctx.lineTo(sx[lr], sy[lr]);
    ctx.strokeStyle = 'rgba(255,214,90,.28)';
    ctx.lineWidth = 9;
    ctx.stroke();
    ctx.strokeStyle = LINK_COLOUR;
    ctx.lineWidth = 2;
    ctx.stroke();
    const dx = sx[lr] - sx[lt], dy = sy[lr] - sy[lt];
    const len = Math.hypot(dx, dy);
    if (len >= 3 * r) {
      const ux = dx / len, uy = dy / len;
      const tipX = sx[lr] - ux * (r + 4), tipY = sy[lr] - uy * (r + 4);
      ctx.beginPath();
      ctx.moveTo(tipX, tipY);
      ctx.lineTo(tipX - ux * 12 - uy * 6, tipY - uy * 12 + ux * 6);
      ctx.lineTo(tipX - ux * 12 + uy * 6, tipY - uy * 12 - ux * 6);
      ctx.closePath();
      ctx.fillStyle = LINK_COLOUR;
      ctx.fill();
    }
  }

  // Nodes and their ids.
  ctx.font = `600 ${N > 40 ? 10 : 11.5}px system-ui, sans-serif`;
  ctx.textBaseline = 'middle';
  for (let i = 0; i < N; ++i) {
    if (!known[i]) continue;
    const id = state.ids[i];
    const selected = id === state.selected;
    const node = s.nodes[i];
    // A node whose source went silent keeps its last position, drawn faded.
    const stale = node.source?.stale === true;
    const heading = headingOf(node);
    if (heading !== null) {  // a tick from the centre out along the heading
      ctx.beginPath();
      ctx.moveTo(sx[i], sy[i]);
      ctx.lineTo(sx[i] + Math.sin(heading) * (r + 8), sy[i] - Math.cos(heading) * (r + 8));
      ctx.strokeStyle = stale ? '#6b7685' : '#e8edf4';
      ctx.lineWidth = 2;
      ctx.stroke();
    }
    ctx.beginPath();
    ctx.arc(sx[i], sy[i], r, 0, 2 * Math.PI);
    ctx.globalAlpha = stale ? 0.4 : 1;
    ctx.fillStyle = phyColour(node.phy);
    ctx.fill();
    ctx.globalAlpha = 1;
    ctx.lineWidth = selected ? 3 : 1.5;
    ctx.strokeStyle = selected ? '#5cc8ff' : id === state.hover ? '#ffffff' : '#0b0f14';
    ctx.stroke();
    if (selected) {
      ctx.beginPath();
      ctx.arc(sx[i], sy[i], r + 5, 0, 2 * Math.PI);
      ctx.strokeStyle = 'rgba(92,200,255,.55)';
      ctx.lineWidth = 2;
      ctx.stroke();
    }
    if (state.overrides.has(id)) {
      ctx.beginPath();
      ctx.arc(sx[i], sy[i], r + 2.5, 0, 2 * Math.PI);
      ctx.setLineDash([3, 3]);
      ctx.strokeStyle = '#f0c05a';
      ctx.lineWidth = 1.5;
      ctx.stroke();
      ctx.setLineDash([]);
    }
    const label = String(id);
    const lx = sx[i] + r + 3, ly = sy[i] - r - 2;
    ctx.lineWidth = 3;
    ctx.strokeStyle = 'rgba(11,15,20,.85)';
    ctx.strokeText(label, lx, ly);
    ctx.fillStyle = selected ? '#9fe0ff' : '#e8edf4';
    ctx.fillText(label, lx, ly);
  }

  // Scale bar (bottom left).
  const barPx = step * state.view.scale;
  const bx = 14, by = H - 16;
  ctx.fillStyle = 'rgba(11,15,20,.75)';
  ctx.fillRect(bx - 6, by - 18, barPx + 12 + 60, 28);
  ctx.strokeStyle = '#d9dee7';
  ctx.lineWidth = 2;
  ctx.beginPath();
  ctx.moveTo(bx, by - 5); ctx.lineTo(bx, by); ctx.lineTo(bx + barPx, by); ctx.lineTo(bx + barPx, by - 5);
  ctx.stroke();
  ctx.fillStyle = '#d9dee7';
  ctx.font = '12px system-ui, sans-serif';
  ctx.textBaseline = 'alphabetic';
  ctx.fillText(fmtMetres(step), bx + barPx + 8, by);
  if (!nKnown) {
    ctx.fillStyle = '#8793a4';
    ctx.fillText('no node has a known position yet', 16, 24);
  }
  const mode = state.autoFit ? 'auto-fit' : 'manual view (Fit resets)';
  setText(mapInfo, `${N} nodes · ${decoding} of ${N * (N - 1) / 2} pairs decode · `
    + `${fmtMetres((W) / state.view.scale)} wide · ${mode}`);
}

registerDrawer('map', drawMap);
