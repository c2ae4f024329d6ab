// The lists beside the map: nodes without a position (they cannot be drawn,
// so they get a button to watch them) and the node count per PHY. Both are
// rebuilt only when their content changes, not on every snapshot.
import { phyColour } from './colour.js';
import { $, el } from './dom.js';
import { onSelect, select } from './selection.js';
import { posOk } from './snapshot.js';
import { state } from './state.js';

const unknownList = $('#unknown-nodes');
const phyLegend = $('#phy-legend');
let unknownKey = '';
let phyKey = '';

export function updateUnknown(nodes) {
  const ids = nodes.filter((n) => !posOk(n.position)).map((n) => n.id);
  const key = `${ids.join(',')}|${state.selected}`;
  if (key === unknownKey) return;
  unknownKey = key;
  if (!ids.length) {
    unknownList.replaceChildren(el('li', { class: 'none' }, 'none'));
    return;
  }
  unknownList.replaceChildren(...ids.map((id) => {
    const b = el('button', { type: 'button', title: `node ${id}: waiting for its location feed`,
      class: id === state.selected ? 'selected' : '' }, String(id));
    b.addEventListener('click', () => select(id));
    return el('li', { dataset: { node: id } }, b);
  }));
}

export function updatePhyLegend(nodes) {
  const counts = new Map();
  for (const n of nodes) counts.set(n.phy, (counts.get(n.phy) || 0) + 1);
  const key = [...counts].map(([p, c]) => `${p}:${c}`).join(',');
  if (key === phyKey) return;
  phyKey = key;
  phyLegend.replaceChildren(...[...counts].map(([phy, c]) => el('li', { dataset: { phy } },
    el('span', { class: 'phy-dot', style: `background:${phyColour(phy)}` }), `${phy} (${c})`)));
}

// The watched node's button is highlighted.
onSelect(() => {
  unknownKey = '';
  if (state.snap) updateUnknown(state.snap.nodes);
});
