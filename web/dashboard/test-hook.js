// window.rfsitlDashboard: a read-only view of the page for tests and automation
// (tests/browser/*). Getters hand out copies, so a caller cannot change what the
// page shows; the object is frozen and the property cannot be redefined.
import { linkPlotDrawn } from './link-plot.js';
import { mapCanvas, nodeCanvasPosition, toWorld } from './map-view.js';
import { matrixCellCentre } from './matrix.js';
import { ACTIVE_MS, state } from './state.js';

const api = {
  /** A copy of the last snapshot as the page holds it (null before the first): the
   *  message, with the SNR matrix carried over when the server left it out. */
  get snapshot() { return state.snap ? structuredClone(state.snap) : null; },
  /** A copy of the hello message. */
  get hello() { return state.helloText ? JSON.parse(state.helloText) : null; },
  get connection() { return state.conn; },
  get control() { return state.control; },
  get selected() { return state.selected; },
  /** The link whose gain is plotted: [tx id, rx id], or null. */
  get link() { return state.link ? state.link.slice() : null; },
  /** What the link plot drew last: {link, points, distinct, lo, hi, last} (null: no link drawn). */
  linkPlot: linkPlotDrawn,
  get nodeIds() { return state.ids.slice(); },
  get spectrum() { return state.spectrum ? JSON.parse(JSON.stringify(state.spectrum)) : null; },
  get constellation() { return state.constellation ? JSON.parse(JSON.stringify(state.constellation)) : null; },
  get messages() { return state.messages.map((m) => ({ ...m })); },
  get snrRange() { return [state.snrLo, state.snrHi]; },
  /** A node's centre in the map canvas, CSS pixels from the canvas's top left (null if unknown). */
  nodeCanvasPosition,
  /** The same in viewport (client) coordinates, as mouse events use. */
  nodeClientPosition(id) {
    const p = nodeCanvasPosition(id);
    if (!p) return null;
    const r = mapCanvas.getBoundingClientRect();
    return { x: r.left + p.x, y: r.top + p.y };
  },
  /** Local metres under a viewport point of the map. */
  worldAtClient(clientX, clientY) {
    const r = mapCanvas.getBoundingClientRect();
    return toWorld(clientX - r.left, clientY - r.top);
  },
  /** Centre of the heat-map cell tx -> rx: canvas CSS pixels and viewport coordinates. */
  matrixCell(txId, rxId) {
    const tx = state.indexOf.get(txId), rx = state.indexOf.get(rxId);
    if (tx === undefined || rx === undefined) return null;
    return matrixCellCentre(tx, rx);
  },
  /** Directed links (tx id, rx id) that decoded frames in the last 2 s. */
  activeLinks() {
    const now = performance.now(), N = state.ids.length, out = [];
    for (let k = 0; k < state.activeRx.length; ++k) {
      if (state.activeRx[k] && now - state.activeRx[k] < ACTIVE_MS) {
        out.push([state.ids[(k / N) | 0], state.ids[k % N]]);
      }
    }
    return out;
  },
  /** JS time per message and per drawing, in ms (mean, p95, max over the last 400). */
  perf() { return state.timings.summary(); },
};

Object.defineProperty(window, 'rfsitlDashboard', {
  value: Object.freeze(api), writable: false, configurable: false, enumerable: true,
});
