// The top bar's status fields: scenario, clocks, real-time lag and late work.
import { $, setText } from './dom.js';
import { fmtClock, fmtSeconds } from './format.js';

const scenario = $('#scenario');
const virtual = $('#virtual-time');
const wall = $('#wall-time');
const lag = $('#lag');
const lateTicks = $('#late-ticks');
const lateDecodes = $('#late-decodes');

export function showHello(m) {
  setText(scenario, m.scenario || '–');
  document.title = `rfsitl · ${m.scenario}`;
}

export function showStatus(s) {
  setText(scenario, s.scenario ?? '–');
  setText(virtual, fmtClock(s.virtual_s));
  setText(wall, fmtClock(s.wall_s));
  setText(lag, `${fmtSeconds(s.lag_s)} / ${fmtSeconds(s.max_lag_s)}`);
  lag.classList.toggle('warn', s.lag_s > 0.02 && s.lag_s <= 0.2);
  lag.classList.toggle('bad', s.lag_s > 0.2);
  setText(lateTicks, String(s.late_ticks ?? '–'));
  setText(lateDecodes, String(s.late_decodes ?? '–'));
}
