// The tooltip of the node under the pointer on the map.
import { $, el } from './dom.js';
import { mapSurface, nodeWorld } from './map-view.js';
import { decodes } from './snapshot.js';
import { state } from './state.js';

const tip = $('#map-tooltip');

export function hideMapTooltip() {
  tip.hidden = true;
}

/** Shows node `id`'s tooltip beside canvas point `p` (hides it for null). */
export function showMapTooltip(id, p) {
  if (id == null || !state.snap) {
    tip.hidden = true;
    return;
  }
  const i = state.indexOf.get(id);
  const n = state.snap.nodes[i];
  const w = nodeWorld(i);
  const N = state.snap.links.n;
  let dec = 0, total = 0;
  for (let j = 0; j < N; ++j) {
    if (j === i || state.snap.links.snr_db[j * N + i] == null) continue;
    ++total;
    if (decodes(j, i) !== false) ++dec;
  }
  const sens = n.sensitivity_db != null ? `${n.sensitivity_db.toFixed(1)} dB` : 'unknown';
  tip.innerHTML = '';
  tip.append(
    el('b', {}, `node ${id}`), ` · ${n.phy}`, el('br'),
    w ? `x ${w.x.toFixed(1)}  y ${w.y.toFixed(1)}  z ${w.z.toFixed(1)} m` : 'position unknown', el('br'),
    el('span', { class: 'muted' }, `sensitivity ${sens} · hears ${dec} of ${total} senders`), el('br'),
    el('span', { class: 'muted' }, state.control ? 'click: watch · drag: move' : 'click: watch'));
  tip.hidden = false;
  const bw = mapSurface.w;
  tip.style.left = `${Math.min(p.x + 14, bw - tip.offsetWidth - 4)}px`;
  tip.style.top = `${p.y + 14}px`;
}

/** Re-renders the tooltip under a still pointer, so it follows new data. */
export function refreshMapTooltip() {
  if (state.hover != null && state.hoverAt && !state.drag) showMapTooltip(state.hover, state.hoverAt);
}
