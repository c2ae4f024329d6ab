// The map's geometry: where each node is in local metres, and the view (centre
// and pixels per metre) that maps metres to canvas CSS pixels, y pointing north.
// Drawing, pointer handling, the tooltip and the test hook all go through here.
import { $ } from './dom.js';
import { requestDraw } from './scheduler.js';
import { posOk } from './snapshot.js';
import { Surface } from './surface.js';
import { state } from './state.js';

export const mapSurface = new Surface($('#map'), () => requestDraw('map'));
export const mapCanvas = mapSurface.canvas;

/// Where node i is drawn: the viewer's own placement while it holds, else the snapshot's.
export function nodeWorld(i) {
  const id = state.ids[i];
  const o = state.overrides.get(id);
  if (o) return o;
  const p = state.snap?.nodes[i]?.position;
  return posOk(p) ? p : null;
}

export const toScreenX = (x) => mapSurface.w / 2 + (x - state.view.cx) * state.view.scale;
export const toScreenY = (y) => mapSurface.h / 2 - (y - state.view.cy) * state.view.scale;
export const toWorld = (sx, sy) => ({
  x: state.view.cx + (sx - mapSurface.w / 2) / state.view.scale,
  y: state.view.cy - (sy - mapSurface.h / 2) / state.view.scale,
});

/** Centres the view on the known nodes and zooms to fit them with a margin. */
export function fitView() {
  let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
  for (let i = 0; i < state.ids.length; ++i) {
    const p = nodeWorld(i);
    if (!p) continue;
    x0 = Math.min(x0, p.x); x1 = Math.max(x1, p.x);
    y0 = Math.min(y0, p.y); y1 = Math.max(y1, p.y);
  }
  if (x0 === Infinity) return;
  const pad = 46;
  const w = Math.max(10, x1 - x0), h = Math.max(10, y1 - y0);
  const scale = Math.min((mapSurface.w - 2 * pad) / w, (mapSurface.h - 2 * pad) / h);
  state.view = { cx: (x0 + x1) / 2, cy: (y0 + y1) / 2, scale: Math.max(scale, 1e-6) };
}

/** Smaller dots for bigger swarms, so they do not cover each other. */
export function nodeRadius() {
  const n = state.ids.length;
  return n <= 16 ? 9 : n <= 40 ? 7 : 5.5;
}

/** The id of the node drawn nearest canvas point (px, py), within a few pixels; else null. */
export function nodeAt(px, py) {
  if (!state.snap) return null;
  const r = nodeRadius() + 5;
  let best = null, bestD = r * r;
  for (let i = 0; i < state.ids.length; ++i) {
    const p = nodeWorld(i);
    if (!p) continue;
    const dx = toScreenX(p.x) - px, dy = toScreenY(p.y) - py;
    const d = dx * dx + dy * dy;
    if (d <= bestD) { bestD = d; best = state.ids[i]; }
  }
  return best;
}

/** A node's centre in the map canvas, CSS pixels from its top left (null if not drawn). */
export function nodeCanvasPosition(id) {
  const i = state.indexOf.get(id);
  if (i === undefined) return null;
  const p = nodeWorld(i);
  if (!p) return null;
  return { x: toScreenX(p.x), y: toScreenY(p.y) };
}

/** The link drawn nearest canvas point (px, py), within a few pixels: {i, j} with i the
 *  end nearer the point (indices), or null. Only links the map draws now count. */
export function linkAt(px, py) {
  const L = state.mapLinks;
  let best = null, bestD = 5 * 5;
  for (let k = 0; k < L.length; k += 6) {
    const x1 = L[k + 2], y1 = L[k + 3], x2 = L[k + 4], y2 = L[k + 5];
    const dx = x2 - x1, dy = y2 - y1;
    const len2 = dx * dx + dy * dy;
    const f = len2 > 0 ? Math.max(0, Math.min(1, ((px - x1) * dx + (py - y1) * dy) / len2)) : 0;
    const ex = x1 + f * dx - px, ey = y1 + f * dy - py;
    const d = ex * ex + ey * ey;
    if (d < bestD) {
      bestD = d;
      best = f <= 0.5 ? { i: L[k], j: L[k + 1] } : { i: L[k + 1], j: L[k] };
    }
  }
  return best;
}
