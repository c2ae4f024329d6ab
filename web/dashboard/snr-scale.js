// The SNR range the colour scale spans, shared by the map's links and the
// matrix: it starts at -10..60 dB, widens to show the least sensitive receiver
// and the strongest link, and never narrows again (colours stay comparable
// over a run). The legends' bars and their tick labels follow it.
import { cssGradient } from './colour.js';
import { clamp } from './math.js';
import { state } from './state.js';

function showLabels() {
  for (const e of document.querySelectorAll('.snr-lo')) e.textContent = String(state.snrLo);
  for (const e of document.querySelectorAll('.snr-hi')) e.textContent = String(state.snrHi);
  for (const e of document.querySelectorAll('.snr-mid')) e.textContent = String((state.snrLo + state.snrHi) / 2);
}

for (const bar of document.querySelectorAll('.snr-bar')) {
  bar.style.background = cssGradient(bar.classList.contains('dim'));
}
showLabels();

export function updateSnrRange(s) {
  let lo = -10, hi = state.snrHi;
  for (const n of s.nodes) {
    if (n.sensitivity_db != null) lo = Math.min(lo, Math.floor((n.sensitivity_db - 15) / 10) * 10);
  }
  const snr = s.links?.snr_db || [];
  let max = -Infinity;
  for (const v of snr) if (v != null && v > max) max = v;
  if (max > hi) hi = Math.min(100, Math.ceil(max / 10) * 10);
  if (lo !== state.snrLo || hi !== state.snrHi) {
    state.snrLo = lo;
    state.snrHi = hi;
    showLabels();
  }
}

/** The colour-table index (0..255) of an SNR in dB. */
export const snrIndex = (v) => clamp(Math.round((v - state.snrLo) / (state.snrHi - state.snrLo) * 255), 0, 255);
