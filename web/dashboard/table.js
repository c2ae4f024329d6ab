// The counters table: one row per node, built once per node set; a snapshot
// only rewrites the text nodes whose value changed (and flashes those cells).
import { phyColour } from './colour.js';
import { $, el } from './dom.js';
import { onSelect, select } from './selection.js';
import { posOk } from './snapshot.js';
import { LOSS_REASONS } from './state.js';

// Column key (the cell's class) and how to read it from a snapshot's node.
const COLUMNS = [
  ['handed_in', (n) => n.handed_in],
  ['transmitted', (n) => n.transmitted],
  ['delivered', (n) => n.delivered],
  ['lost', (n) => LOSS_REASONS.reduce((a, r) => a + (n.lost?.[r] ?? 0), 0)],
  ...LOSS_REASONS.map((r) => [`lost-${r}`, (n) => n.lost?.[r] ?? 0]),
  ['queue_dropped', (n) => n.queue_dropped],
  ['queue_depth', (n) => n.queue_depth],
  ['received', (n) => n.received],
  ['rx_crc_failures', (n) => n.rx_crc_failures],
];
const FLASH = [{ backgroundColor: 'rgba(255, 214, 90, 0.55)' }, { backgroundColor: 'rgba(255, 214, 90, 0)' }];

const tbody = $('#node-table tbody');
const rows = new Map();  // id -> {tr, phy, phyDot, position, cells: [{td, text, value}]}

/** Replaces the rows with one (still empty) row per node id. */
export function buildTable(ids) {
  rows.clear();
  const frag = document.createDocumentFragment();
  for (const id of ids) {
    const tr = el('tr', { dataset: { node: id } });
    const idTd = el('td', { class: 'id' }, String(id));
    const phyDot = el('span', { class: 'phy-dot' });
    const phyText = document.createTextNode('–');
    const phyTd = el('td', { class: 'phy' }, phyDot, phyText);
    const posText = document.createTextNode('–');
    const posTd = el('td', { class: 'position' }, posText);
    tr.append(idTd, phyTd, posTd);
    const cells = COLUMNS.map(([key]) => {
      const text = document.createTextNode('–');
      const td = el('td', { class: key.startsWith('lost-') ? `${key} lost-reason` : key }, text);
      tr.append(td);
      return { td, text, value: null };
    });
    tr.addEventListener('click', () => select(id));
    rows.set(id, { tr, phyText, phyDot, phy: null, posText, pos: '', cells });
    frag.append(tr);
  }
  tbody.replaceChildren(frag);
}

export function updateTable(nodes) {
  for (const n of nodes) {
    const row = rows.get(n.id);
    if (!row) continue;
    if (row.phy !== n.phy) {
      row.phy = n.phy;
      row.phyText.data = n.phy;
      row.phyDot.style.background = phyColour(n.phy);
    }
    const p = n.position;
    const pos = posOk(p) ? `${p.x.toFixed(1)}, ${p.y.toFixed(1)}, ${p.z.toFixed(1)}`
      : p ? 'invalid' : 'unknown';
    if (pos !== row.pos) {
      row.pos = pos;
      row.posText.data = pos;
    }
    for (let c = 0; c < COLUMNS.length; ++c) {
      const v = COLUMNS[c][1](n) ?? 0;
      const cell = row.cells[c];
      if (cell.value === v) continue;
      const first = cell.value === null;
      if (first || (cell.value === 0) !== (v === 0)) {
        cell.td.classList.toggle('zero', v === 0);
        cell.td.classList.toggle('nonzero', v !== 0);
      }
      cell.value = v;
      cell.text.data = String(v);
      if (!first) cell.td.animate(FLASH, { duration: 900, easing: 'ease-out' });
    }
  }
}

onSelect((id, previous) => {
  const old = previous != null && rows.get(previous);
  if (old) old.tr.classList.remove('selected');
  const row = id != null && rows.get(id);
  if (row) row.tr.classList.add('selected');
});
