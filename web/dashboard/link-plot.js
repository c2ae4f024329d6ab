// The link plot: the gain of one directed link over the last few minutes
// (its reverse beside it, thinner), from the SNR of every snapshot the page
// received (snapshot.js keeps them): gain dB = SNR dB + the noise floor's
// noise_db, so it is 10 log10 |c|^2, fading included. A dashed line marks
// the gain above which the receiver decodes (only its label, with an arrow,
// when it is far off the gains, so that the fades keep the plot's height). A
// link is picked by clicking its matrix cell or the link on the map; the same
// click again, Clear or Escape drops it.
import { $, setText } from './dom.js';
import { niceStep } from './math.js';
import { drawValueGrid } from './plot-grid.js';
import { registerDrawer, requestDraw } from './scheduler.js';
import { snrSeries } from './snapshot.js';
import { Surface } from './surface.js';
import { state } from './state.js';

export const LINK_COLOUR = '#ffd65a';
const REVERSE_COLOUR = '#93a3b8';
const NEED_COLOUR = '#ff6b6b';

const surface = new Surface($('#link-gain'), () => requestDraw('link'));
const nameText = $('#link-name');
const infoText = $('#link-info');
const clear = $('#link-clear');
// The time axis grows through these spans (s), so its labels do not change
// with every snapshot; beyond them, in round steps.
const SPANS = [10, 30, 60, 120, 180, 300];
// The decode threshold widens the dB axis only when it is this close to the gains.
const NEED_REACH_DB = 15;
let drawn = null;  // what the last drawing showed, for the test hook

/** Plots link tx -> rx (node ids); null: none. */
export function selectLink(txId, rxId = null) {
  const link = txId == null || rxId == null || txId === rxId ? null : [txId, rxId];
  state.link = link;
  clear.disabled = !link;
  setText(nameText, link ? `${link[0]} → ${link[1]}` : '');
  showInfo();
  requestDraw('link', 'matrix', 'map');
}

/** Plots tx -> rx, or drops it when it is the link plotted now. */
export function toggleLink(txId, rxId) {
  const same = state.link && state.link[0] === txId && state.link[1] === rxId;
  selectLink(same ? null : txId, same ? null : rxId);
  return !same;
}

/** Drops the link when one of its nodes left the node set. */
export function keepLinkIfKnown() {
  if (state.link && !(state.indexOf.has(state.link[0]) && state.indexOf.has(state.link[1]))) selectLink(null);
}

clear.addEventListener('click', () => selectLink(null));
document.addEventListener('keydown', (e) => { if (e.key === 'Escape' && !state.drag) selectLink(null); });

/** The line beside the title: the gain now, its SNR and what the receiver needs. */
export function showInfo() {
  const s = state.snap;
  if (!state.link) {
    setText(infoText, 'click a cell (or a link on the map) to plot its gain over time');
    return;
  }
  if (!s) return;
  const tx = state.indexOf.get(state.link[0]), rx = state.indexOf.get(state.link[1]);
  const snr = s.links.snr_db?.[tx * s.links.n + rx];
  const sens = s.nodes[rx].sensitivity_db;
  const need = sens != null ? ` (needs ${sens.toFixed(1)})` : '';
  setText(infoText, snr == null ? 'no link now'
    : `now ${(snr + (s.noise_db ?? 0)).toFixed(1)} dB · SNR ${snr.toFixed(1)} dB${need}`);
}

/** "now", "-20 s", "-4 min": how long before the newest point, in minutes on long axes. */
const ago = (a, minutes) => (a === 0 ? 'now' : minutes ? `-${+(a / 60).toFixed(1)} min` : `-${+a.toFixed(1)} s`);

function drawLink() {
  const ctx = surface.begin();
  const W = surface.w, H = surface.h;
  const s = state.snap;
  const h = state.snrHistory;
  ctx.font = '10.5px system-ui, sans-serif';
  const tx = state.link ? state.indexOf.get(state.link[0]) : undefined;
  const rx = state.link ? state.indexOf.get(state.link[1]) : undefined;
  if (!s || !h || tx === undefined || rx === undefined) {
    drawn = null;
    ctx.fillStyle = '#8793a4';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'middle';
    ctx.fillText(state.link ? 'waiting for a snapshot…' : 'no link chosen', W / 2, H / 2);
    return;
  }
  const N = h.n;
  const noise = s.noise_db ?? 0;
  const series = [snrSeries(rx * N + tx), snrSeries(tx * N + rx)];  // reverse first: drawn under
  const fwd = series[1];
  const sens = s.nodes[rx].sensitivity_db;
  const need = sens != null ? sens + noise : null;

  const padL = 46, padR = 10, padT = 20, padB = 20;  // the key above the top line
  const tNow = fwd.t.length ? fwd.t[fwd.t.length - 1] : s.virtual_s;
  const extent = fwd.t.length ? tNow - fwd.t[0] : 0;
  let span = SPANS.find((x) => x >= extent);
  if (span === undefined) span = Math.ceil(extent / niceStep(extent / 4)) * niceStep(extent / 4);
  const minutes = span >= 180;
  const tStep = minutes ? 60 * niceStep(span / 240) : niceStep(span / 4);
  let lo = Infinity, hi = -Infinity;
  for (const { db } of series) {
    for (const v of db) {
      if (v == null) continue;
      lo = Math.min(lo, v + noise);
      hi = Math.max(hi, v + noise);
    }
  }
  const needShown = need != null && lo !== Infinity && need >= lo - NEED_REACH_DB && need <= hi + NEED_REACH_DB;
  if (needShown) {
    lo = Math.min(lo, need);
    hi = Math.max(hi, need);
  }
  if (lo === Infinity) { lo = noise - 10; hi = noise + 40; }
  if (hi - lo < 10) { const mid = (hi + lo) / 2; lo = mid - 5; hi = mid + 5; }
  const yStep = niceStep((hi - lo) / 4);
  lo = Math.floor(lo / yStep) * yStep;
  hi = Math.ceil(hi / yStep) * yStep;
  const X = (t) => padL + (W - padL - padR) * (1 - (tNow - t) / span);
  const Y = (v) => H - padB - (H - padT - padB) * ((v - lo) / (hi - lo));

  // Grid, dB labels on the left, time before now along the bottom.
  drawValueGrid(ctx, { from: lo, to: hi, step: yStep, Y, left: padL, right: W - padR, digits: 4 });
  for (let a = 0; a <= span + 1e-9; a += tStep) {
    const x = X(tNow - a);
    ctx.textAlign = a === 0 ? 'right' : x - padL < 20 ? 'left' : 'center';
    ctx.fillText(ago(a, minutes), a === 0 ? W - padR : x, H - padB + 4);
  }
  ctx.save();
  ctx.translate(8, padT + (H - padT - padB) / 2);
  ctx.rotate(-Math.PI / 2);
  ctx.textAlign = 'center';
  ctx.textBaseline = 'middle';
  ctx.fillText('gain dB', 0, 0);
  ctx.restore();

  // The gain above which the receiver decodes: a dashed line, named top right
  // (or only named there, with an arrow, when it is far off the gains).
  if (needShown) {
    const y = Math.round(Y(need)) + 0.5;
    ctx.beginPath();
    ctx.moveTo(padL, y); ctx.lineTo(W - padR, y);
    ctx.setLineDash([4, 4]);
    ctx.strokeStyle = NEED_COLOUR;
    ctx.globalAlpha = 0.8;
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.globalAlpha = 1;
  }
  if (need != null) {
    ctx.font = '10.5px system-ui, sans-serif';
    ctx.fillStyle = NEED_COLOUR;
    ctx.textAlign = 'right';
    ctx.textBaseline = 'middle';
    const arrow = needShown ? '' : need < lo ? '↓ ' : '↑ ';
    const text = `${arrow}rx ${state.link[1]} decodes above ${need.toFixed(1)} dB`;
    ctx.fillText(text, W - padR, 9);
    if (needShown) {
      const x = W - padR - ctx.measureText(text).width - 6;
      ctx.beginPath();
      ctx.moveTo(x - 14, 9.5); ctx.lineTo(x, 9.5);
      ctx.setLineDash([4, 3]);
      ctx.strokeStyle = NEED_COLOUR;
      ctx.stroke();
      ctx.setLineDash([]);
    }
  }

  // Which line is which, above the plot.
  ctx.textAlign = 'left';
  ctx.textBaseline = 'middle';
  ctx.font = '10.5px ui-monospace, "DejaVu Sans Mono", monospace';
  let kx = padL + 6;
  for (const [label, colour, width] of [[`${state.link[0]} → ${state.link[1]}`, LINK_COLOUR, 2],
    [`${state.link[1]} → ${state.link[0]}`, REVERSE_COLOUR, 1]]) {
    ctx.beginPath();
    ctx.moveTo(kx, 9); ctx.lineTo(kx + 14, 9);
    ctx.strokeStyle = colour;
    ctx.lineWidth = width;
    ctx.stroke();
    ctx.fillStyle = colour;
    ctx.fillText(label, kx + 18, 9);
    kx += 18 + ctx.measureText(label).width + 12;
  }
  ctx.lineWidth = 1;

  // The reverse link, then the link itself on top; a gap where there was no link.
  ctx.save();
  ctx.beginPath();
  ctx.rect(padL, padT - 2, W - padL - padR, H - padT - padB + 4);
  ctx.clip();
  let points = 0;
  series.forEach(({ t, db }, which) => {
    ctx.beginPath();
    let pen = false;
    for (let k = 0; k < t.length; ++k) {
      if (db[k] == null) { pen = false; continue; }
      const x = X(t[k]), y = Y(db[k] + noise);
      if (pen) ctx.lineTo(x, y); else ctx.moveTo(x, y);
      pen = true;
      if (which === 1) ++points;
    }
    ctx.strokeStyle = which === 1 ? LINK_COLOUR : REVERSE_COLOUR;
    ctx.lineWidth = which === 1 ? 1.6 : 1;
    ctx.globalAlpha = which === 1 ? 1 : 0.7;
    ctx.lineJoin = 'round';
    ctx.stroke();
  });
  ctx.globalAlpha = 1;
  // Dots while the points are, on average, far enough apart to tell them from the line.
  const gap = fwd.t.length > 1 ? (fwd.t[fwd.t.length - 1] - fwd.t[0]) / (fwd.t.length - 1) : 0;
  if (gap > 0 && (W - padL - padR) * gap / span > 5) {
    ctx.fillStyle = LINK_COLOUR;
    for (let k = 0; k < fwd.t.length; ++k) {
      if (fwd.db[k] == null) continue;
      ctx.beginPath();
      ctx.arc(X(fwd.t[k]), Y(fwd.db[k] + noise), 1.8, 0, 2 * Math.PI);
      ctx.fill();
    }
  }
  ctx.restore();
  const values = fwd.db.filter((v) => v != null);
  drawn = { link: state.link.slice(), points, distinct: new Set(values).size, lo, hi,
    last: values.length ? values[values.length - 1] + noise : null };
}
registerDrawer('link', drawLink);

/** What the plot showed last: the link, its points, distinct values and the dB range (null: nothing). */
export const linkPlotDrawn = () => (drawn ? { ...drawn, link: drawn.link.slice() } : null);

selectLink(null);
