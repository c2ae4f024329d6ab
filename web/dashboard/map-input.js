// Pointer input on the map: hover (tooltip), click to watch a node, click a
// link to plot its gain (the end nearer the click transmits; link-plot.js),
// drag a node to move it in the emulator (with --dashboard-control), drag the
// background to pan, wheel to zoom, double-click or Fit to fit all nodes.
//
// A dragged node is drawn where the pointer put it (state.overrides) until a
// snapshot agrees, so it does not jump back while the move is in flight.
import { controlOffText } from './control.js';
import { send } from './connection.js';
import { $ } from './dom.js';
import { hideMapTooltip, showMapTooltip } from './map-tooltip.js';
import { toggleLink } from './link-plot.js';
import { linkAt, mapCanvas, nodeAt, nodeWorld, toScreenX, toScreenY, toWorld } from './map-view.js';
import { clamp } from './math.js';
import { showMessage } from './messages.js';
import { requestDraw } from './scheduler.js';
import { select } from './selection.js';
import { posOk } from './snapshot.js';
import { state } from './state.js';

// Moves are sent at most this often during a drag (the last one always is).
const MOVE_SEND_INTERVAL_MS = 100;

const hint = $('#map-hint');
let hintTimer = 0;

function showHint(text, ms = 3500) {
  hint.textContent = text;
  hint.hidden = false;
  clearTimeout(hintTimer);
  hintTimer = setTimeout(() => { hint.hidden = true; }, ms);
}

const localPoint = (e) => {
  const rect = mapCanvas.getBoundingClientRect();
  return { x: e.clientX - rect.left, y: e.clientY - rect.top };
};

function sendMove(id, p, force = false) {
  const d = state.drag;
  const now = performance.now();
  if (!force && d && now - d.lastSent < MOVE_SEND_INTERVAL_MS) return;
  if (d) d.lastSent = now;
  const msg = { type: 'move', node: id, x: +p.x.toFixed(2), y: +p.y.toFixed(2), z: +p.z.toFixed(2) };
  if (!send(msg)) showMessage('not connected: the move was not sent');
}

mapCanvas.addEventListener('pointerdown', (e) => {
  if (e.button !== 0) return;
  const p = localPoint(e);
  const id = nodeAt(p.x, p.y);
  mapCanvas.setPointerCapture(e.pointerId);
  if (id != null) {
    const i = state.indexOf.get(id);
    const w = nodeWorld(i);
    state.drag = { kind: 'node', id, start: p, moved: false, lastSent: 0, z: w ? w.z : 0,
      offX: toScreenX(w.x) - p.x, offY: toScreenY(w.y) - p.y };
  } else {
    state.drag = { kind: 'pan', start: p, moved: false, view: { ...state.view } };
  }
});

mapCanvas.addEventListener('pointermove', (e) => {
  const p = localPoint(e);
  const d = state.drag;
  if (!d) {
    const id = nodeAt(p.x, p.y);
    if (id !== state.hover) {
      state.hover = id;
      mapCanvas.classList.toggle('over-node', id != null);
      requestDraw('map');
    }
    mapCanvas.classList.toggle('over-link', id == null && linkAt(p.x, p.y) != null);
    state.hoverAt = p;
    showMapTooltip(id, p);
    return;
  }
  // A few pixels of jitter is still a click, not a drag.
  const moved = Math.hypot(p.x - d.start.x, p.y - d.start.y) > 3;
  if (!d.moved && !moved) return;
  if (!d.moved) {
    d.moved = true;
    hideMapTooltip();
    if (d.kind === 'node' && !state.control) {
      showHint(state.control === false ? controlOffText() : 'not connected yet');
    }
  }
  if (d.kind === 'node') {
    if (!state.control) return;  // nothing moves without control
    mapCanvas.classList.add('dragging');
    const w = toWorld(p.x + d.offX, p.y + d.offY);
    const target = { x: w.x, y: w.y, z: d.z, until: Infinity };
    state.overrides.set(d.id, target);
    sendMove(d.id, target);
    requestDraw('map');
  } else {
    mapCanvas.classList.add('panning');
    state.autoFit = false;
    state.view = { ...d.view, cx: d.view.cx - (p.x - d.start.x) / d.view.scale,
      cy: d.view.cy + (p.y - d.start.y) / d.view.scale };
    requestDraw('map');
  }
});

function endDrag(e, cancelled) {
  const d = state.drag;
  if (!d) return;
  state.drag = null;
  mapCanvas.classList.remove('dragging', 'panning');
  if (mapCanvas.hasPointerCapture(e.pointerId)) mapCanvas.releasePointerCapture(e.pointerId);
  if (d.kind === 'pan' && !d.moved && !cancelled) {
    const hit = linkAt(d.start.x, d.start.y);
    if (hit) toggleLink(state.ids[hit.i], state.ids[hit.j]);
  }
  if (d.kind === 'node') {
    if (!d.moved && !cancelled) {
      select(d.id);
    } else if (state.control && state.overrides.has(d.id)) {
      const o = state.overrides.get(d.id);
      sendMove(d.id, o, true);
      o.until = performance.now() + 2500;  // hold it there until the snapshot agrees
    }
  }
  requestDraw('map');
}
mapCanvas.addEventListener('pointerup', (e) => endDrag(e, false));
mapCanvas.addEventListener('pointercancel', (e) => endDrag(e, true));
mapCanvas.addEventListener('pointerleave', () => {
  if (!state.drag) {
    hideMapTooltip();
    if (state.hover != null) { state.hover = null; requestDraw('map'); }
  }
});
mapCanvas.addEventListener('wheel', (e) => {
  e.preventDefault();
  // Zoom about the pointer: the metre under it stays under it.
  const p = localPoint(e);
  const before = toWorld(p.x, p.y);
  const f = Math.exp(-clamp(e.deltaY, -300, 300) * 0.0015);
  state.view.scale = clamp(state.view.scale * f, 1e-6, 1e4);
  const after = toWorld(p.x, p.y);
  state.view.cx += before.x - after.x;
  state.view.cy += before.y - after.y;
  state.autoFit = false;
  requestDraw('map');
}, { passive: false });
mapCanvas.addEventListener('dblclick', () => { state.autoFit = true; requestDraw('map'); });
$('#map-fit').addEventListener('click', () => { state.autoFit = true; requestDraw('map'); });
$('#link-filter').addEventListener('change', () => requestDraw('map'));

/// Drops the viewer's placements once the snapshot agrees (or after a while).
export function settleOverrides(s) {
  const now = performance.now();
  for (const [id, o] of state.overrides) {
    if (state.drag && state.drag.id === id) continue;
    const p = s.nodes[state.indexOf.get(id)]?.position;
    const agrees = posOk(p) && Math.abs(p.x - o.x) < 0.05 && Math.abs(p.y - o.y) < 0.05;
    if (agrees || now > o.until) state.overrides.delete(id);
  }
}
