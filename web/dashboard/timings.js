// The page's own JavaScript cost: mean / p95 / max of the last few hundred
// samples of each timing (message parsing, handling, each drawing). The test
// hook's perf() and tests/browser/perf.mjs read it; nothing else depends on it.

export class Timings {
  constructor() { this.series = new Map(); }

  add(name, ms) {
    let s = this.series.get(name);
    if (!s) this.series.set(name, (s = []));
    s.push(ms);
    if (s.length > 400) s.shift();
  }

  summary() {
    const out = {};
    for (const [name, s] of this.series) {
      const sorted = [...s].sort((a, b) => a - b);
      const mean = s.reduce((a, b) => a + b, 0) / s.length;
      out[name] = {
        n: s.length, mean: +mean.toFixed(3),
        p95: +sorted[Math.min(sorted.length - 1, Math.floor(sorted.length * 0.95))].toFixed(3),
        max: +sorted[sorted.length - 1].toFixed(3),
      };
    }
    return out;
  }
}
