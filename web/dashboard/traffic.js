// The traffic plot: frames/s delivered and lost by all nodes over the last 30
// to 120 s (rates from consecutive snapshots' totals), and the totals line.
import { $, setText } from './dom.js';
import { clamp, niceStep } from './math.js';
import { drawValueGrid } from './plot-grid.js';
import { registerDrawer, requestDraw } from './scheduler.js';
import { Surface } from './surface.js';
import { state } from './state.js';

const trafficSurface = new Surface($('#traffic'), () => requestDraw('traffic'));
const totals = $('#traffic-totals');

function drawTraffic() {
  const ctx = trafficSurface.begin();
  const W = trafficSurface.w, H = trafficSurface.h;
  const h = state.history;
  const padL = 40, padR = 8, padT = 8, padB = 20;
  const rates = [];
  for (let k = 1; k < h.length; ++k) {
    const dt = h[k].t - h[k - 1].t;
    if (dt <= 0) continue;
    rates.push({ t: h[k].t, d: (h[k].delivered - h[k - 1].delivered) / dt,
      l: (h[k].lost - h[k - 1].lost) / dt });
  }
  const tNow = h.length ? h[h.length - 1].t : 0;
  const span = h.length ? clamp(Math.ceil((tNow - h[0].t) / 30) * 30, 30, 120) : 30;
  let ymax = 1;
  for (const r of rates) ymax = Math.max(ymax, r.d, r.l);
  const yStep = niceStep(ymax / 4);
  ymax = Math.ceil(ymax / yStep) * yStep;
  const X = (t) => padL + (W - padL - padR) * (1 - (tNow - t) / span);
  const Y = (v) => H - padB - (H - padT - padB) * (v / ymax);
  ctx.font = '10.5px system-ui, sans-serif';
  drawValueGrid(ctx, { from: 0, to: ymax, step: yStep, Y, left: padL, right: W - padR, digits: 3 });
  for (let a = 0; a <= span; a += span / 4) ctx.fillText(a === 0 ? 'now' : `-${a} s`, X(tNow - a), H - padB + 4);
  for (const [key, colour] of [['d', '#5fd38d'], ['l', '#ff6b6b']]) {
    ctx.beginPath();
    let started = false;
    for (const r of rates) {
      if (tNow - r.t > span) continue;
      if (!started) { ctx.moveTo(X(r.t), Y(r[key])); started = true; } else ctx.lineTo(X(r.t), Y(r[key]));
    }
    ctx.strokeStyle = colour;
    ctx.lineWidth = 1.6;
    ctx.stroke();
  }
  if (h.length) {
    const last = h[h.length - 1];
    const r = rates.length ? rates[rates.length - 1] : { d: 0, l: 0 };
    setText(totals, `total delivered ${last.delivered} · lost ${last.lost} · received ${last.received}`
      + ` · now ${r.d.toFixed(1)}/s delivered, ${r.l.toFixed(1)}/s lost`);
  }
}

registerDrawer('traffic', drawTraffic);
