// Whether this viewer may move nodes (the emulator's --dashboard-control): the
// pill in the top bar, the map's help text and its "movable" cursor.
import { $ } from './dom.js';
import { state } from './state.js';

export const CONTROL_OFF_TEXT = 'moving nodes is off; start with --dashboard-control';

const pill = $('#control-state');
const help = $('#map-help');
const mapCanvas = $('#map canvas');

export function setControl(on) {
  if (state.control === on) return;
  state.control = on;
  pill.dataset.control = on ? 'on' : 'off';
  pill.textContent = on ? 'moving nodes allowed (drag a node on the map)' : CONTROL_OFF_TEXT;
  help.textContent = on
    ? 'Click a node to watch it. Drag a node to move it. Wheel zooms, dragging the background pans.'
    : `Click a node to watch it. ${CONTROL_OFF_TEXT[0].toUpperCase()}${CONTROL_OFF_TEXT.slice(1)}. `
      + 'Wheel zooms, dragging the background pans.';
  mapCanvas.classList.toggle('movable', on);
}
