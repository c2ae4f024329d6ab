// Bookkeeping of the server's snapshots: the node set, which directed links
// carried or lost frames recently (from the deltas of the cumulative per-link
// counters), and the totals over time for the traffic plot. Views read the
// results from `state`; this module touches no DOM.
import { state } from './state.js';

const HISTORY_POINTS = 480;  // 2 minutes at 4 snapshots/s

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
  }
  // The server re-sends the SNR matrix only when something moved.
  if (s.links && !s.links.snr_db && prev && prev.links && prev.links.n === s.links.n) {
    s.links.snr_db = prev.links.snr_db;
  }
  state.snap = s;

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
