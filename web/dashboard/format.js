// Numbers as the dashboard shows them: times, distances and frequencies with
// units chosen so the text stays short. A missing value is shown as '–'.

export const fmtClock = (s) => {
  if (s == null || !Number.isFinite(s)) return '–';
  if (s < 60) return `${s.toFixed(2)} s`;
  const h = Math.floor(s / 3600);
  const m = Math.floor((s % 3600) / 60);
  const sec = (s % 60).toFixed(1).padStart(4, '0');
  return h > 0 ? `${h}:${String(m).padStart(2, '0')}:${sec}` : `${m}:${sec}`;
};

export const fmtSeconds = (s) => {
  if (s == null || !Number.isFinite(s)) return '–';
  const a = Math.abs(s);
  if (a < 1e-3) return `${(s * 1e6).toFixed(0)} µs`;
  if (a < 1) return `${(s * 1e3).toFixed(1)} ms`;
  return `${s.toFixed(2)} s`;
};

export const fmtMetres = (m) => (Math.abs(m) >= 1000 ? `${(m / 1000).toPrecision(3)} km`
  : `${Number(m.toPrecision(3))} m`);

export const fmtHz = (hz) => {
  const a = Math.abs(hz);
  if (a >= 1e6) return `${Number((hz / 1e6).toPrecision(3))} MHz`;
  if (a >= 1e3) return `${Number((hz / 1e3).toPrecision(3))} kHz`;
  return `${Number(hz.toPrecision(3))} Hz`;
};
