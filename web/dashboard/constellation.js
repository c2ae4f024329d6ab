// The constellation (I/Q points) of the last frame the watched node decoded,
// green when its CRC passed and red when it failed, with the frame's details.
import { $, setText } from './dom.js';
import { fmtClock } from './format.js';
import { registerDrawer, requestDraw } from './scheduler.js';
import { onSelect } from './selection.js';
import { Surface } from './surface.js';
import { state } from './state.js';

const constSurface = new Surface($('#constellation'), () => requestDraw('constellation'));
const metaCells = {};
for (const k of ['src', 'dst', 'serial', 'valid', 'time', 'points']) {
  metaCells[k] = $(`dd.${k}`, $('#constellation-meta'));
}

function updateConstellationMeta() {
  const c = state.constellation;
  setText(metaCells.src, c ? String(c.src) : '–');
  setText(metaCells.dst, c ? String(c.dst) : '–');
  setText(metaCells.serial, c ? String(c.serial) : '–');
  setText(metaCells.valid, c ? (c.valid ? 'yes (CRC ok)' : 'no (CRC failed)') : '–');
  metaCells.valid.classList.toggle('yes', !!c && c.valid);
  metaCells.valid.classList.toggle('no', !!c && !c.valid);
  setText(metaCells.time, c ? fmtClock(c.virtual_s) : '–');
  setText(metaCells.points, c ? String(c.points.length) : '–');
}
onSelect(updateConstellationMeta);  // select() has just dropped the old node's frame

/** A 'constellation' message: shown when it is the watched node's (a late one may not be). */
export function onConstellation(m) {
  if (m.node !== state.selected) return;
  state.constellation = m;
  updateConstellationMeta();
  requestDraw('constellation');
}

function drawConstellation() {
  const ctx = constSurface.begin();
  const W = constSurface.w, H = constSurface.h;
  const c = state.constellation;
  const cx = W / 2, cy = H / 2;
  ctx.strokeStyle = '#1f2833';
  ctx.lineWidth = 1;
  ctx.beginPath();
  ctx.moveTo(cx + 0.5, 0); ctx.lineTo(cx + 0.5, H);
  ctx.moveTo(0, cy + 0.5); ctx.lineTo(W, cy + 0.5);
  ctx.stroke();
  if (!c || !c.points.length) {
    ctx.fillStyle = '#8793a4';
    ctx.font = '12px system-ui, sans-serif';
    ctx.textAlign = 'center';
    ctx.fillText(state.selected == null ? 'no node watched' : 'no frame decoded yet', cx, cy - 12);
    return;
  }
  const mags = c.points.map(([i, q]) => Math.max(Math.abs(i), Math.abs(q))).sort((a, b) => a - b);
  const ref = mags[Math.floor(mags.length * 0.98)] || 1;
  const range = ref * 1.3;
  const scale = (Math.min(W, H) / 2 - 6) / range;
  ctx.beginPath();
  ctx.arc(cx, cy, ref * scale, 0, 2 * Math.PI);
  ctx.strokeStyle = '#26303d';
  ctx.setLineDash([3, 4]);
  ctx.stroke();
  ctx.setLineDash([]);
  ctx.fillStyle = c.valid ? 'rgba(95,211,141,.8)' : 'rgba(255,107,107,.8)';
  for (const [i, q] of c.points) ctx.fillRect(cx + i * scale - 1.2, cy - q * scale - 1.2, 2.4, 2.4);
  ctx.fillStyle = '#8793a4';
  ctx.font = '10.5px system-ui, sans-serif';
  ctx.textAlign = 'left';
  ctx.textBaseline = 'top';
  ctx.fillText(`I/Q · ±${Number(range.toPrecision(2))}`, 4, 4);
}

registerDrawer('constellation', drawConstellation);
