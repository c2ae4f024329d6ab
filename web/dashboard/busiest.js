// The busiest links table: the directed links with the most frames decoded or
// lost over the last ACTIVE_MS, from a sliding window of the per-link counters.
// Its rows are created once and hidden when unused.
import { $, el } from './dom.js';
import { select } from './selection.js';
import { ACTIVE_MS, state } from './state.js';

const BUSIEST_ROWS = 8;
const busiest = [];
const noneNote = $('#busiest-none');
{
  const tbody = $('#busiest-links tbody');
  for (let r = 0; r < BUSIEST_ROWS; ++r) {
    const texts = ['link', 'decoded', 'lost', 'snr', 'margin'].map((cls) => {
      const t = document.createTextNode('');
      return { cls, t, td: el('td', { class: cls }, t) };
    });
    const tr = el('tr', {}, ...texts.map((x) => x.td));
    tr.hidden = true;
    const row = { tr, texts, rx: null };
    tr.addEventListener('click', () => { if (row.rx != null) select(row.rx); });
    busiest.push(row);
    tbody.append(tr);
  }
}

export function updateBusiest(s) {
  const L = s.links;
  if (!L || !L.received) return;
  const w = state.linkWindow;
  w.push({ t: s.wall_s, received: Uint32Array.from(L.received), lost: Uint32Array.from(L.lost) });
  while (w.length > 1 && w[1].t <= s.wall_s - ACTIVE_MS / 1000) w.shift();
  const base = w[0];
  const top = [];
  if (w.length > 1) {
    const cur = w[w.length - 1];
    for (let k = 0; k < cur.received.length; ++k) {
      const d = cur.received[k] - base.received[k], l = cur.lost[k] - base.lost[k];
      if (d > 0 || l > 0) top.push([d + l, k, d, l]);
    }
    top.sort((a, b) => b[0] - a[0]);
  }
  const N = L.n;
  for (let r = 0; r < BUSIEST_ROWS; ++r) {
    const row = busiest[r];
    const item = top[r];
    row.tr.hidden = !item;
    if (!item) { row.rx = null; continue; }
    const [, k, d, l] = item;
    const tx = (k / N) | 0, rx = k - tx * N;
    const v = L.snr_db[k];
    const sens = s.nodes[rx].sensitivity_db;
    const margin = v != null && sens != null ? v - sens : null;
    row.rx = state.ids[rx];
    const vals = [`${state.ids[tx]} → ${state.ids[rx]}`, String(d), String(l),
      v == null ? '–' : v.toFixed(1), margin == null ? '–' : margin.toFixed(1)];
    row.texts.forEach((x, j) => { if (x.t.data !== vals[j]) x.t.data = vals[j]; });
    row.texts[2].td.classList.toggle('nonzero', l > 0);
    row.texts[4].td.classList.toggle('neg', margin != null && margin < 0);
  }
  noneNote.hidden = top.length > 0;
}
