// Number helpers shared by the plots and the map.

export const clamp = (v, lo, hi) => Math.max(lo, Math.min(hi, v));

/** A round 1 / 2 / 5 x 10^k step near `raw`, for grid lines, axes and the scale bar. */
export const niceStep = (raw) => {
  const p = 10 ** Math.floor(Math.log10(raw));
  const f = raw / p;
  return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * p;
};
