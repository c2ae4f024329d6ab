// The watched node: the server streams its spectrum and constellation to us.
// Views that show something per watched node subscribe with onSelect() rather
// than being called from here, so they can import select() for their own click
// handlers without an import cycle.
import { send } from './connection.js';
import { $, setText } from './dom.js';
import { requestDraw } from './scheduler.js';
import { posOk } from './snapshot.js';
import { state } from './state.js';

const nodeText = $('#selected-node');
const infoText = $('#selected-info');
const unwatch = $('#unwatch');
const listeners = [];

/** Calls `fn(id, previousId)` whenever the watched node changes. */
export const onSelect = (fn) => { listeners.push(fn); };

/** Watches node `id` (null: none). */
export function select(id) {
  if (id === state.selected) return;
  const previous = state.selected;
  state.selected = id;
  state.spectrum = null;
  state.constellation = null;
  state.specHi = 40;
  for (const fn of listeners) fn(id, previous);
  send({ type: 'watch', node: id });
  setText(nodeText, id == null ? '–' : String(id));
  unwatch.disabled = id == null;
  updateSelectedInfo();
  requestDraw('map', 'matrix', 'spectrum', 'waterfall', 'constellation');
}
unwatch.addEventListener('click', () => select(null));
// Escape during a drag belongs to the drag, not to the selection.
document.addEventListener('keydown', (e) => { if (e.key === 'Escape' && !state.drag) select(null); });

/** The line under the panel's title: PHY, sensitivity, position, frames received. */
export function updateSelectedInfo() {
  const id = state.selected;
  if (id == null) {
    setText(infoText, 'click a node on the map or in the table');
    return;
  }
  const i = state.indexOf.get(id);
  const n = state.snap?.nodes[i];
  if (!n) {
    setText(infoText, 'watching');
    return;
  }
  const sens = n.sensitivity_db != null ? `needs ${n.sensitivity_db.toFixed(1)} dB SNR` : 'sensitivity unknown';
  const p = n.position;
  const where = posOk(p) ? `x ${p.x.toFixed(1)} y ${p.y.toFixed(1)} z ${p.z.toFixed(1)} m` : 'position unknown';
  setText(infoText, `${n.phy} · ${sens} · ${where} · received ${n.received}`);
}
