// The counters table: one row per node, built once per node set; a snapshot
// only rewrites the text nodes whose value changed (and flashes those cells).
// The counter columns are the server's: the hello lists every per-node counter
// (key, label, help; by-reason counters with their reasons) in display order.
import { phyColour } from './colour.js';
import { $, el } from './dom.js';
import { onSelect, select } from './selection.js';
import { posOk } from './snapshot.js';
import { state } from './state.js';

const FLASH = [{ backgroundColor: 'rgba(255, 214, 90, 0.55)' }, { backgroundColor: 'rgba(255, 214, 90, 0)' }];

const thead = $('#node-table thead');
const tbody = $('#node-table tbody');
const rows = new Map();  // id -> {tr, phy, phyDot, position, cells: [{td, text, value}]}
let columns = [];        // {cls: the cells' classes, read: node of a snapshot -> value}
let fieldsText = null;   // the field list `columns` was built from

const sumOf = (o) => Object.values(o ?? {}).reduce((a, v) => a + v, 0);

/** A by-reason counter: a group header over its total and one column per reason. */
function reasonColumns(f, top, bottom) {
  top.append(el('th', { class: 'group', colSpan: 1 + f.reasons.length, title: f.help }, f.label));
  bottom.append(el('th', { title: 'All reasons' }, 'total'));
  const cols = [{ cls: f.key, read: (n) => sumOf(n[f.key]) }];
  for (const r of f.reasons) {
    bottom.append(el('th', { title: r.help }, r.label));
    cols.push({ cls: `${f.key}-${r.key} reason`, read: (n) => n[f.key]?.[r.key] ?? 0 });
  }
  return cols;
}

/** Adopts the hello's counter list: rebuilds the header and, if it changed, the rows. */
export function setCounterFields(fields) {
  const text = JSON.stringify(fields);
  if (text === fieldsText) return;
  fieldsText = text;
  const grouped = fields.some((f) => f.reasons);
  const top = el('tr'), bottom = el('tr');
  const head = (title, label) => el('th', { rowSpan: grouped ? 2 : 1, title }, label);
  top.append(head('Node id', 'id'), head('Transceiver type', 'phy'),
    head('Local x, y, z in metres', 'position'));
  columns = [];
  for (const f of fields) {
    if (f.reasons) {
      columns.push(...reasonColumns(f, top, bottom));
    } else {
      top.append(head(f.help, f.label));
      columns.push({ cls: f.key, read: (n) => n[f.key] });
    }
  }
  thead.replaceChildren(...(grouped ? [top, bottom] : [top]));
  buildTable(state.ids);
}

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
    const cells = columns.map(({ cls }) => {
      const text = document.createTextNode('–');
      const td = el('td', { class: cls }, text);
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
    for (let c = 0; c < columns.length; ++c) {
      const v = columns[c].read(n) ?? 0;
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
