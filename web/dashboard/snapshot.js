// Bookkeeping of the server's snapshots: the node set, which directed links
// carried or lost frames recently (from the deltas of the cumulative per-link
// counters), the totals over time for the traffic plot, and every link's SNR
// over time for the link plot. Views read the results from `state`; this
// module touches no DOM.
import { state } from './state.js';

const HISTORY_POINTS = 480;  // 2 minutes at 4 snapshots/s

// The SNR history keeps one row of N^2 values per snapshot, as dB x 10 in an
// Int16Array (the server rounds to 0.1 dB), in a ring: 3 minutes at 4
// snapshots/s, fewer rows when N^2 x 720 would pass 4 Mi values (8 MB), so a
// 64-node swarm keeps its 3 minutes in 6 MB and a bigger one less time in at
// most 8 MB. Every link is kept, so a link clicked now shows its past at once.
const SNR_ROWS = 720;
const SNR_VALUES = 1 << 22;
const NO_LINK = -32768;

function newSnrHistory(n) {
  const n2 = Math.max(1, n * n);
  const cap = Math.max(2, Math.min(SNR_ROWS, Math.floor(SNR_VALUES / n2)));
  return { n, cap, len: 0, next: 0, t: new Float64Array(cap), v: new Int16Array(cap * n2) };
}

/// Appends the snapshot's SNR matrix (carried over when the server left it out) at its virtual time.
function recordSnr(s) {
  const h = state.snrHistory;
  const snr = s.links?.snr_db;
  if (!h || !snr || s.links.n !== h.n || !Number.isFinite(s.virtual_s)) return;
  if (h.len && !(s.virtual_s > h.t[(h.next + h.cap - 1) % h.cap])) return;  // no time passed
  const n2 = h.n * h.n, row = h.next * n2;
  for (let k = 0; k < n2; ++k) {
    const x = snr[k];
    h.v[row + k] = x == null ? NO_LINK : Math.max(-32767, Math.min(32767, Math.round(x * 10)));
  }
  h.t[h.next] = s.virtual_s;
  h.next = (h.next + 1) % h.cap;
  h.len = Math.min(h.len + 1, h.cap);
}

/** Link k's (tx * N + rx) recorded SNR, oldest first: {t: virtual s, db: dB or null (no link)}. */
export function snrSeries(k) {
  const h = state.snrHistory;
  const out = { t: [], db: [] };
  if (!h || k < 0 || k >= h.n * h.n) return out;
  const n2 = h.n * h.n;
  for (let r = 0; r < h.len; ++r) {
    const row = (h.next - h.len + r + h.cap) % h.cap;
    const v = h.v[row * n2 + k];
    out.t.push(h.t[row]);
    out.db.push(v === NO_LINK ? null : v / 10);
  }
  return out;
}

/// A usable position (the server sends null coordinates for non-finite ones).
export const posOk = (p) => !!p && Number.isFinite(p.x) && Number.isFinite(p.y) && Number.isFinite(p.z);

/** Adopts a node list; true when it differs from the current one (per-link data restarts). */
export function setNodeIds(ids) {
  const same = ids.length === state.ids.length && ids.every((id, i) => id === state.ids[i]);
  if (same) return false;
  state.ids = ids.slice();
  state.indexOf = new Map(ids.map((id, i) => [id, i]));
  const n2 = ids.length * ids.length;
  state.activeRx = new Float64Array(n2);
  state.activeLost = new Float64Array(n2);
  state.history = [];
  state.linkWindow = [];
  state.snrHistory = newSnrHistory(ids.length);
  return true;
}

/** Makes `s` the current snapshot; call after setNodeIds. */
export function recordSnapshot(s) {
  const prev = state.snap;
  if (prev && s.wall_s < prev.wall_s) {  // a new emulator run behind the same address
    state.history = [];
    state.linkWindow = [];
    state.activeRx.fill(0);
    state.activeLost.fill(0);
    state.snrHistory = newSnrHistory(state.ids.length);
  }
  // The server re-sends the SNR matrix only when something moved.
  if (s.links && !s.links.snr_db && prev && prev.links && prev.links.n === s.links.n) {
    s.links.snr_db = prev.links.snr_db;
  }
  state.snap = s;
  recordSnr(s);

  // A counter that grew since the previous snapshot marks its link active now.
  const now = performance.now();
  const L = s.links;
  const P = prev && prev.links;
  if (L && P && P.n === L.n && prev.wall_s <= s.wall_s) {
    const rec = L.received, lost = L.lost, prec = P.received, plost = P.lost;
    for (let k = 0; k < rec.length; ++k) {
      if (rec[k] > prec[k]) state.activeRx[k] = now;
      if (lost[k] > plost[k]) state.activeLost[k] = now;
    }
  }

  let delivered = 0, lost = 0, received = 0;
  for (const n of s.nodes) {
    delivered += n.delivered;
    received += n.received;
    for (const v of Object.values(n.lost ?? {})) lost += v;
  }
  state.history.push({ t: s.wall_s, delivered, lost, received });
  if (state.history.length > HISTORY_POINTS) state.history.shift();
}

/// Does rx decode tx now? true / false / null (receiver's sensitivity unknown).
export function decodes(tx, rx) {
  const s = state.snap;
  const v = s.links.snr_db[tx * s.links.n + rx];
  if (v == null) return false;
  const sens = s.nodes[rx].sensitivity_db;
  if (sens == null) return null;
  return v >= sens;
}
