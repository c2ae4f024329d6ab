// Drawing happens in one requestAnimationFrame per burst of messages: handlers
// only mark what changed, and each canvas is redrawn at most once per frame
// however many snapshots, spectra or pointer moves arrived since the last one.
import { state } from './state.js';

const drawers = {};  // name -> function drawing that canvas
const dirty = new Set();
let frameRequested = false;

/** Makes `draw` the drawing of `name` (each canvas's module registers its own). */
export function registerDrawer(name, draw) {
  drawers[name] = draw;
}

/** Marks canvases for redrawing in the next animation frame. */
export const requestDraw = (...what) => {
  for (const w of what) dirty.add(w);
  if (!frameRequested) {
    frameRequested = true;
    requestAnimationFrame(drawFrame);
  }
};

function drawFrame() {
  frameRequested = false;
  const todo = [...dirty];
  dirty.clear();
  const t0 = performance.now();
  for (const what of todo) {
    const s = performance.now();
    drawers[what]();
    state.timings.add(`draw_${what}`, performance.now() - s);
  }
  state.timings.add('frame', performance.now() - t0);
}
