// Whether this viewer may move nodes (the emulator's --dashboard-control): the
// pill in the top bar, the map's help text and its "movable" cursor. Control
// may be on for the run but refused to this viewer, when the dashboard needs a
// control token (reachable beyond loopback) and the page's URL has none or a
// wrong one.
import { controlToken } from './connection.js';
import { $ } from './dom.js';
import { state } from './state.js';

export const CONTROL_OFF_TEXT = 'moving nodes is off; start with --dashboard-control';
export const TOKEN_MISSING_TEXT =
  'moving nodes needs the control token: open the URL with ?token= that the emulator printed';
export const TOKEN_WRONG_TEXT = 'wrong control token in this URL: moving nodes refused';

/** Why this viewer cannot move nodes, for the pill and hints. */
export function controlOffText() {
  if (!state.controlRefused) return CONTROL_OFF_TEXT;
  return controlToken ? TOKEN_WRONG_TEXT : TOKEN_MISSING_TEXT;
}

/** From the server's hello: why control is refused to this viewer (null: it is not). */
export function setControlRefused(reason) {
  state.controlRefused = reason || null;
}

const pill = $('#control-state');
const help = $('#map-help');
const mapCanvas = $('#map canvas');

export function setControl(runControl) {
  const on = !!runControl && !state.controlRefused;
  const off = controlOffText();
  const text = on ? 'moving nodes allowed (drag a node on the map)' : off;
  if (state.control === on && pill.textContent === text) return;
  state.control = on;
  pill.dataset.control = on ? 'on' : 'off';
  pill.textContent = text;
  const clicks = 'Click a node to watch it, a link to plot its gain (the end nearer the click sends).';
  help.textContent = on
    ? `${clicks} Drag a node to move it. Wheel zooms, dragging the background pans.`
    : `${clicks} ${off[0].toUpperCase()}${off.slice(1)}. `
      + 'Wheel zooms, dragging the background pans.';
  mapCanvas.classList.toggle('movable', on);
}
