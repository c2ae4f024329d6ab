// The watched node's spectrum (the latest one, as a line) and waterfall (the
// last WATERFALL_ROWS spectra, newest on top), in dB re the noise floor.
//
// The waterfall lives in an offscreen canvas one pixel per bin and row: a new
// spectrum shifts it down by one row and paints the top row, and drawing it is
// a single scaled drawImage.
import { BG_RGB, LUT } from './colour.js';
import { $, setText } from './dom.js';
import { fmtClock, fmtHz } from './format.js';
import { clamp } from './math.js';
import { registerDrawer, requestDraw } from './scheduler.js';
import { onSelect } from './selection.js';
import { Surface } from './surface.js';
import { state } from './state.js';

const WATERFALL_ROWS = 80;  // 20 s at 4 spectra/s

const specSurface = new Surface($('#spectrum'), () => requestDraw('spectrum'));
const wfSurface = new Surface($('#waterfall'), () => requestDraw('waterfall'));
const specInfo = $('#spectrum-info');
const wf = { off: document.createElement('canvas'), rows: 0 };
wf.off.width = 256;
wf.off.height = WATERFALL_ROWS;
wf.ctx = wf.off.getContext('2d');

// The top of the dB scale only grows (state.specHi, reset per watched node),
// so the colours of older waterfall rows keep their meaning.
function specRange() {
  return { lo: -10, hi: state.specHi };
}

function clearWaterfall() {
  wf.ctx.fillStyle = `rgb(${BG_RGB.join(',')})`;
  wf.ctx.fillRect(0, 0, wf.off.width, wf.off.height);
  wf.rows = 0;
}
clearWaterfall();
onSelect(clearWaterfall);  // another node's history does not belong under this one

function pushWaterfall(bins) {
  if (!bins || !bins.length) return;
  let max = -Infinity;
  for (const b of bins) if (b > max) max = b;
  if (max + 5 > state.specHi) state.specHi = Math.min(150, Math.ceil((max + 5) / 10) * 10);
  if (wf.off.width !== bins.length) {
    wf.off.width = bins.length;
    clearWaterfall();
  }
  const { lo, hi } = specRange();
  wf.ctx.drawImage(wf.off, 0, 0, wf.off.width, WATERFALL_ROWS - 1, 0, 1, wf.off.width, WATERFALL_ROWS - 1);
  const row = wf.ctx.createImageData(bins.length, 1);
  for (let k = 0; k < bins.length; ++k) {
    const rgb = LUT[clamp(Math.round((bins[k] - lo) / (hi - lo) * 255), 0, 255)];
    row.data[k * 4] = rgb[0]; row.data[k * 4 + 1] = rgb[1]; row.data[k * 4 + 2] = rgb[2];
    row.data[k * 4 + 3] = 255;
  }
  wf.ctx.putImageData(row, 0, 0);
  wf.rows = Math.min(WATERFALL_ROWS, wf.rows + 1);
}

/** A 'spectrum' message: kept and drawn when it is the watched node's (a late one may not be). */
export function onSpectrum(m) {
  if (m.node !== state.selected) return;
  state.spectrum = m;
  pushWaterfall(m.bins_db);
  requestDraw('spectrum', 'waterfall');
}

function freqAxis(ctx, W, H, padL, padR, padB, fs) {
  ctx.fillStyle = '#8793a4';
  ctx.font = '10.5px system-ui, sans-serif';
  ctx.textAlign = 'center';
  ctx.textBaseline = 'top';
  for (let q = -2; q <= 2; ++q) {
    const x = padL + (W - padL - padR) * (q + 2) / 4;
    ctx.textAlign = q === -2 ? 'left' : q === 2 ? 'right' : 'center';
    ctx.fillText(fmtHz(q * fs / 4), x, H - padB + 3);
  }
}

function drawSpectrum() {
  const ctx = specSurface.begin();
  const W = specSurface.w, H = specSurface.h;
  const padL = 34, padR = 8, padT = 8, padB = 18;
  const m = state.spectrum;
  if (state.selected == null || !m || !m.bins_db || !m.bins_db.length) {
    ctx.fillStyle = '#8793a4';
    ctx.font = '12px system-ui, sans-serif';
    ctx.fillText(state.selected == null ? 'no node watched' : 'waiting for samples…', 12, 20);
    setText(specInfo, '');
    return;
  }
  const bins = m.bins_db;
  const { lo, hi } = specRange();
  const X = (k) => padL + (W - padL - padR) * k / (bins.length - 1);
  const Y = (v) => padT + (H - padT - padB) * (1 - (clamp(v, lo, hi) - lo) / (hi - lo));
  ctx.strokeStyle = '#1f2833';
  ctx.lineWidth = 1;
  ctx.fillStyle = '#8793a4';
  ctx.font = '10.5px system-ui, sans-serif';
  ctx.textAlign = 'right';
  ctx.textBaseline = 'middle';
  const step = hi - lo > 60 ? 20 : 10;
  ctx.beginPath();
  for (let v = Math.ceil(lo / step) * step; v <= hi; v += step) {
    const y = Math.round(Y(v)) + 0.5;
    ctx.moveTo(padL, y); ctx.lineTo(W - padR, y);
    ctx.fillText(String(v), padL - 4, y);
  }
  ctx.stroke();
  freqAxis(ctx, W, H, padL, padR, padB, m.sample_rate_hz);
  ctx.beginPath();
  ctx.moveTo(X(0), Y(lo));
  for (let k = 0; k < bins.length; ++k) ctx.lineTo(X(k), Y(bins[k]));
  ctx.lineTo(X(bins.length - 1), Y(lo));
  ctx.closePath();
  ctx.fillStyle = 'rgba(92,200,255,.12)';
  ctx.fill();
  ctx.beginPath();
  for (let k = 0; k < bins.length; ++k) {
    if (k === 0) ctx.moveTo(X(k), Y(bins[k])); else ctx.lineTo(X(k), Y(bins[k]));
  }
  ctx.strokeStyle = '#5cc8ff';
  ctx.lineWidth = 1.3;
  ctx.stroke();
  let peak = -Infinity;
  for (const b of bins) peak = Math.max(peak, b);
  setText(specInfo, `node ${m.node} · t ${fmtClock(m.virtual_s)} · peak ${peak.toFixed(1)} dB · `
    + `fs ${fmtHz(m.sample_rate_hz)} · dB re noise floor`);
}

function drawWaterfall() {
  const ctx = wfSurface.begin();
  const W = wfSurface.w, H = wfSurface.h;
  if (state.selected == null || !wf.rows) {
    ctx.fillStyle = '#8793a4';
    ctx.font = '12px system-ui, sans-serif';
    ctx.fillText(state.selected == null ? 'no node watched' : 'waiting for samples…', 12, 20);
    return;
  }
  const padL = 34, padR = 8, padB = 18;
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(wf.off, padL, 0, W - padL - padR, H - padB);
  ctx.fillStyle = '#8793a4';
  ctx.font = '10.5px system-ui, sans-serif';
  ctx.textAlign = 'right';
  ctx.textBaseline = 'top';
  ctx.fillText('now', padL - 4, 0);
  ctx.textBaseline = 'bottom';
  ctx.fillText(`-${(WATERFALL_ROWS * 0.25).toFixed(0)} s`, padL - 4, H - padB);
  freqAxis(ctx, W, H, padL, padR, padB, state.spectrum?.sample_rate_hz ?? state.hello?.sample_rate_hz ?? 1);
}

registerDrawer('spectrum', drawSpectrum);
registerDrawer('waterfall', drawWaterfall);
