// The link matrix: a heat map of SNR, tx rows -> rx columns, dimmed where the
// receiver does not decode, outlined where frames were decoded (white) or lost
// (red) in the last ACTIVE_MS. Hovering a cell explains it; clicking one
// plots its link's gain over time (link-plot.js) and watches its receiver;
// clicking it again stops the plot.
//
// Performance: the N x N cells are one ImageData (a pixel per link) scaled up
// by drawImage without smoothing, not N^2 fillRects.
import { LUT, dimRgb } from './colour.js';
import { $, el } from './dom.js';
import { LINK_COLOUR, toggleLink } from './link-plot.js';
import { clamp } from './math.js';
import { registerDrawer, requestDraw } from './scheduler.js';
import { select } from './selection.js';
import { decodes } from './snapshot.js';
import { snrIndex } from './snr-scale.js';
import { Surface } from './surface.js';
import { ACTIVE_MS, state } from './state.js';

const panel = $('#matrix-panel');
const matrixBox = $('#matrix');
const tip = $('#matrix-tooltip');
// `off` holds one pixel per link; cell / left / top: the on-screen layout in CSS pixels.
const mx = { surface: null, off: document.createElement('canvas'), img: null, cell: 8, left: 30, top: 30 };
mx.offCtx = mx.off.getContext('2d');
// Sized by layoutMatrix (from the panel and the node count), not by its box.
mx.surface = new Surface(matrixBox, () => {});
new ResizeObserver(() => layoutMatrix()).observe(panel);

/** Sizes the matrix for the panel's width and the node count. */
export function layoutMatrix() {
  const N = state.ids.length;
  // As wide as the panel allows, about as tall as the map beside it.
  const avail = Math.min(panel.clientWidth - 24, 470);
  const label = N > 99 ? 34 : 28;
  const cell = N ? clamp(Math.floor((avail - label - 4) / N), 3, 56) : 8;
  const size = N ? label + N * cell + 2 : 60;
  mx.cell = cell;
  mx.left = label;
  mx.top = label;
  matrixBox.style.width = `${size}px`;
  matrixBox.style.height = `${size}px`;
  mx.surface.canvas.style.width = `${size}px`;
  mx.surface.canvas.style.height = `${size}px`;
  mx.surface.fit(size, size);
  if (mx.off.width !== Math.max(1, N)) {
    mx.off.width = Math.max(1, N);
    mx.off.height = Math.max(1, N);
    mx.img = mx.offCtx.createImageData(Math.max(1, N), Math.max(1, N));
  }
  requestDraw('matrix');
}

function drawMatrix() {
  const s = state.snap;
  const ctx = mx.surface.begin();
  const N = state.ids.length;
  if (!s || !N || s.links.n !== N || !mx.img) return;
  const { cell, left, top } = mx;
  const data = mx.img.data;
  const snr = s.links.snr_db;
  for (let tx = 0; tx < N; ++tx) {
    for (let rx = 0; rx < N; ++rx) {
      const k = tx * N + rx;
      const o = k * 4;
      const v = snr[k];
      let rgb;
      if (tx === rx) rgb = [44, 50, 60];
      else if (v == null) rgb = [22, 25, 30];
      else {
        rgb = LUT[snrIndex(v)];
        if (decodes(tx, rx) === false) rgb = dimRgb(rgb);
      }
      data[o] = rgb[0]; data[o + 1] = rgb[1]; data[o + 2] = rgb[2]; data[o + 3] = 255;
    }
  }
  mx.offCtx.putImageData(mx.img, 0, 0);
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(mx.off, left, top, N * cell, N * cell);

  if (cell >= 9) {
    ctx.beginPath();
    for (let i = 0; i <= N; ++i) {
      ctx.moveTo(left + i * cell + 0.5, top); ctx.lineTo(left + i * cell + 0.5, top + N * cell);
      ctx.moveTo(left, top + i * cell + 0.5); ctx.lineTo(left + N * cell, top + i * cell + 0.5);
    }
    ctx.strokeStyle = 'rgba(11,15,20,.55)';
    ctx.lineWidth = 1;
    ctx.stroke();
  }

  // Cells whose link decoded (white) or lost (red, inside) frames recently.
  const now = performance.now();
  const lw = cell >= 10 ? 2 : 1;
  for (const [arr, colour, inner] of [[state.activeRx, '#ffffff', 0], [state.activeLost, '#ff5a5a', 1]]) {
    const inset = (cell >= 6 ? 1 : 0) + (inner && cell >= 12 ? lw + 1 : 0);
    ctx.beginPath();
    let any = false;
    for (let k = 0; k < arr.length; ++k) {
      if (arr[k] === 0 || now - arr[k] >= ACTIVE_MS) continue;
      const tx = (k / N) | 0, rx = k - tx * N;
      ctx.rect(left + rx * cell + inset + lw / 2, top + tx * cell + inset + lw / 2,
        cell - 2 * inset - lw, cell - 2 * inset - lw);
      any = true;
    }
    if (any) {
      ctx.strokeStyle = colour;
      ctx.lineWidth = lw;
      ctx.stroke();
    }
  }

  // Selected node: its row (what it sends) and column (what it hears).
  const si = state.selected != null ? state.indexOf.get(state.selected) : undefined;
  if (si !== undefined) {
    ctx.strokeStyle = 'rgba(92,200,255,.9)';
    ctx.lineWidth = 1.5;
    ctx.strokeRect(left - 0.5, top + si * cell - 0.5, N * cell + 1, cell + 1);
    ctx.strokeRect(left + si * cell - 0.5, top - 0.5, cell + 1, N * cell + 1);
  }
  // The plotted link, and its reverse (drawn thinner in the plot too).
  const lt = state.link ? state.indexOf.get(state.link[0]) : undefined;
  const lr = state.link ? state.indexOf.get(state.link[1]) : undefined;
  if (lt !== undefined && lr !== undefined) {
    ctx.strokeStyle = LINK_COLOUR;
    ctx.setLineDash([2, 2]);
    ctx.lineWidth = 1;
    ctx.strokeRect(left + lt * cell + 0.5, top + lr * cell + 0.5, cell - 1, cell - 1);
    ctx.setLineDash([]);
    ctx.lineWidth = 2.5;
    ctx.strokeRect(left + lr * cell - 0.25, top + lt * cell - 0.25, cell + 0.5, cell + 0.5);
  }
  if (state.matrixHover) {
    const [tx, rx] = state.matrixHover;
    ctx.strokeStyle = '#ffffff';
    ctx.lineWidth = 1.5;
    ctx.strokeRect(left + rx * cell - 1, top + tx * cell - 1, cell + 2, cell + 2);
  }

  // Labels: tx ids down the left, rx ids across the top.
  ctx.fillStyle = '#8793a4';
  ctx.font = `${cell >= 12 ? 11 : 9.5}px system-ui, sans-serif`;
  const stepY = Math.max(1, Math.ceil(11 / cell));
  ctx.textAlign = 'right';
  ctx.textBaseline = 'middle';
  for (let i = 0; i < N; i += stepY) ctx.fillText(String(state.ids[i]), left - 4, top + (i + 0.5) * cell);
  const horizontal = cell >= 18;
  const stepX = horizontal ? 1 : Math.max(1, Math.ceil(11 / cell));
  for (let i = 0; i < N; i += stepX) {
    const x = left + (i + 0.5) * cell;
    if (horizontal) {
      ctx.textAlign = 'center';
      ctx.textBaseline = 'bottom';
      ctx.fillText(String(state.ids[i]), x, top - 3);
    } else {
      ctx.save();
      ctx.translate(x, top - 3);
      ctx.rotate(-Math.PI / 2);
      ctx.textAlign = 'left';
      ctx.textBaseline = 'middle';
      ctx.fillText(String(state.ids[i]), 0, 0);
      ctx.restore();
    }
  }
  ctx.textAlign = 'left';
  ctx.textBaseline = 'top';
  ctx.fillStyle = '#5cc8ff';
  ctx.font = '600 10px system-ui, sans-serif';
  ctx.fillText('tx↓ rx→', 1, 1);
}
registerDrawer('matrix', drawMatrix);

/** [tx, rx, x, y] of the cell under a pointer event (x, y: canvas CSS pixels); null outside. */
function matrixCellAt(e) {
  const rect = mx.surface.canvas.getBoundingClientRect();
  const x = e.clientX - rect.left - mx.left, y = e.clientY - rect.top - mx.top;
  const N = state.ids.length;
  const rx = Math.floor(x / mx.cell), tx = Math.floor(y / mx.cell);
  if (x < 0 || y < 0 || rx >= N || tx >= N) return null;
  return [tx, rx, e.clientX - rect.left, e.clientY - rect.top];
}
mx.surface.canvas.addEventListener('pointermove', (e) => {
  const c = matrixCellAt(e);
  const key = c ? `${c[0]},${c[1]}` : '';
  const oldKey = state.matrixHover ? state.matrixHover.join(',') : '';
  state.matrixHover = c ? [c[0], c[1]] : null;
  if (key !== oldKey) requestDraw('matrix');
  state.matrixHoverAt = c ? [c[2], c[3]] : null;
  if (!c) {
    tip.hidden = true;
    return;
  }
  showMatrixTooltip(c[0], c[1], c[2], c[3]);
});
mx.surface.canvas.addEventListener('pointerleave', () => {
  state.matrixHover = null;
  tip.hidden = true;
  requestDraw('matrix');
});
mx.surface.canvas.addEventListener('click', (e) => {
  const c = matrixCellAt(e);
  if (!c) return;
  const txId = state.ids[c[0]], rxId = state.ids[c[1]];
  // The diagonal is no link: a click there only watches the node. A second
  // click on the plotted link only stops the plot.
  if (c[0] !== c[1] && !toggleLink(txId, rxId)) {
    refreshMatrixTooltip();
    return;
  }
  select(rxId);
  refreshMatrixTooltip();
});

function showMatrixTooltip(tx, rx, px, py) {
  const s = state.snap;
  if (!s) return;
  const N = s.links.n;
  const k = tx * N + rx;
  const v = s.links.snr_db[k];
  const rxNode = s.nodes[rx], txNode = s.nodes[tx];
  tip.replaceChildren();
  tip.append(el('b', {}, `tx ${state.ids[tx]} → rx ${state.ids[rx]}`), el('br'));
  if (tx === rx) {
    tip.append(el('span', { class: 'muted' }, 'same node'));
  } else {
    const d = decodes(tx, rx);
    const sens = rxNode.sensitivity_db;
    tip.append(v == null ? 'SNR: no link' : `SNR ${v.toFixed(1)} dB`,
      sens != null ? el('span', { class: 'muted' }, ` (rx needs ${sens.toFixed(1)} dB)`) : '', el('br'),
      d === null ? el('span', { class: 'muted' }, 'decodes: unknown (external receiver)')
        : el('span', { class: d ? 'good' : 'bad' }, d ? 'decodes' : 'does not decode'), el('br'),
      `received ${s.links.received[k]} · lost ${s.links.lost[k]}`);
    if (txNode.phy !== rxNode.phy) {
      tip.append(el('br'), el('span', { class: 'muted' }, `${txNode.phy} → ${rxNode.phy}: different PHY types`));
    }
    const plotted = state.link && state.link[0] === state.ids[tx] && state.link[1] === state.ids[rx];
    tip.append(el('br'), el('span', { class: 'muted' },
      plotted ? 'click: stop plotting its gain' : 'click: plot its gain, watch the receiver'));
  }
  tip.hidden = false;
  const boxW = matrixBox.clientWidth;
  tip.style.left = `${Math.max(0, Math.min(px + 14, boxW - tip.offsetWidth - 2))}px`;
  tip.style.top = `${py + 16}px`;
}

/** Re-renders the tooltip under a still pointer, so it follows new data. */
export function refreshMatrixTooltip() {
  if (state.matrixHover && state.matrixHoverAt) {
    showMatrixTooltip(...state.matrixHover, ...state.matrixHoverAt);
  }
}

/** Centre of the cell at indices tx -> rx: canvas CSS pixels and viewport coordinates. */
export function matrixCellCentre(tx, rx) {
  const x = mx.left + (rx + 0.5) * mx.cell, y = mx.top + (tx + 0.5) * mx.cell;
  const r = mx.surface.canvas.getBoundingClientRect();
  return { x, y, clientX: r.left + x, clientY: r.top + y, cell: mx.cell, dpr: mx.surface.dpr };
}
