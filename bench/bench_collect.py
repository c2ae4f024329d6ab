#!/usr/bin/env python3
"""Turns the raw output of one benchmark run into one CSV row (bench/run_benchmarks.sh).

    bench_collect.py rtt-row --n N --ping-csv F --summary-json F --floor-ms X --out CSV
    bench_collect.py capacity-row --n N --load-json F --emu-log F --from-line A --to-line B
                                  --load-seconds D --summary-json F --floor-ms X --out CSV
                                  [--lag-csv F]

"Keeps real time" (capacity) is judged from the emulator's own measurements: the
`[stats] ... lag X ms (max Y ms)` lines it prints once per second (lag: how late the
latest tick started). Only lines printed while the load generator was sending count:
log lines A..B, cut at D seconds after the load began (the load began at most one
stats interval before the first of them), so the drain after the last ping is out.
The run keeps real time when
  (a) the median lag of the last END_SAMPLES (5) of those lines is below MAX_END_LAG_MS
      (50 ms): at the end of the load the latest tick started less than 50 ms late, and
  (b) the lag does not grow: the Theil-Sen slope (median of the slopes between all pairs
      of samples, robust against the spikes a single sample catches when it lands inside
      a busy frame) of lag against wall time is below MAX_SLOPE_MS_PER_S (0.5 ms per
      second: under 30 ms of drift in 60 s),
  and the load generator itself completed. An emulator that is slower than real time
  on average falls further behind every second: it fails (b), and over 60 s (a).
"""

import argparse
import csv
import json
import math
import os
import re
import statistics

from bench_common import percentile

END_SAMPLES = 5
MAX_END_LAG_MS = 50.0
MAX_SLOPE_MS_PER_S = 0.5
STATS_RE = re.compile(
    r"^\[stats\] virtual ([\d.]+) s, wall ([\d.]+) s, lag ([\d.]+) ms \(max ([\d.]+) ms\)")


def read_summary(path, tick_samples=250, fs=1e6):
    """Worst lag, late ticks and their fraction from `rfsitl run --summary-json`."""
    try:
        with open(path) as f:
            s = json.load(f)
    except (OSError, ValueError):
        return {"max_lag_ms": math.nan, "late_ticks": math.nan, "late_tick_fraction": math.nan,
                "virtual_s": math.nan, "wall_s": math.nan, "emu_frames": 0, "emu_delivered": 0,
                "emu_lost": {}}
    # Runs since the summary named its tick say it; older summaries were all 250 at 1 Msps.
    ticks = s["virtual_s"] * s.get("sample_rate_hz", fs) / s.get("tick_samples", tick_samples)
    lost = {}
    for n in s.get("nodes", []):
        for reason, v in n["lost"].items():
            lost[reason] = lost.get(reason, 0) + v
    return {
        "max_lag_ms": 1e3 * s["max_lag_s"],
        "late_ticks": s["late_ticks"],
        "late_tick_fraction": s["late_ticks"] / ticks if ticks > 0 else math.nan,
        "virtual_s": s["virtual_s"],
        "wall_s": s["wall_s"],
        "emu_frames": sum(n["handed_in"] for n in s.get("nodes", [])),
        "emu_delivered": sum(n["delivered"] for n in s.get("nodes", [])),
        "emu_lost": lost,
    }


def append_row(path, row):
    new = not os.path.exists(path) or os.path.getsize(path) == 0
    with open(path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(row))
        if new:
            w.writeheader()
        w.writerow({k: (f"{v:.4f}" if isinstance(v, float) else v) for k, v in row.items()})


def rtt_row(a):
    rtts, lost = [], 0
    if os.path.exists(a.ping_csv):
        with open(a.ping_csv) as f:
            for r in csv.DictReader(f):
                if r["status"] == "ok":
                    rtts.append(float(r["rtt_ms"]))
                else:
                    lost += 1
    rtts.sort()
    mean = statistics.fmean(rtts) if rtts else math.nan
    s = read_summary(a.summary_json)
    row = {"n": a.n, "packets": len(rtts) + lost, "lost": lost, "mean_ms": mean,
           "p10_ms": percentile(rtts, 0.1), "p50_ms": percentile(rtts, 0.5),
           "p90_ms": percentile(rtts, 0.9), "floor_ms": a.floor_ms}
    for k in ("mean", "p10", "p50", "p90"):
        row[f"{k}_x_floor"] = row[f"{k}_ms"] / a.floor_ms
    row.update({k: s[k] for k in ("max_lag_ms", "late_ticks", "late_tick_fraction", "virtual_s",
                                  "wall_s")})
    append_row(a.out, row)
    print(f"N={a.n:3d}: rtt mean {mean:.3f} ms ({row['mean_x_floor']:.2f} x floor) "
          f"p10 {row['p10_ms']:.3f} p90 {row['p90_ms']:.3f} lost {lost}; "
          f"worst lag {s['max_lag_ms']:.2f} ms, late ticks {s['late_ticks']}")


def lag_samples(log, first, last):
    """(wall_s, lag_ms, max_lag_ms) of the stats lines in log lines first..last (1-based)."""
    out = []
    with open(log, errors="replace") as f:
        for i, line in enumerate(f, start=1):
            if first <= i <= last:
                m = STATS_RE.match(line)
                if m:
                    out.append((float(m.group(2)), float(m.group(3)), float(m.group(4))))
    return out


def theil_sen_slope(points):
    """Median of the pairwise slopes of (x, y, ...) points; NaN with fewer than 3."""
    if len(points) < 3:
        return math.nan
    slopes = [(q[1] - p[1]) / (q[0] - p[0])
              for i, p in enumerate(points) for q in points[i + 1:] if q[0] > p[0]]
    return statistics.median(slopes) if slopes else math.nan


def capacity_row(a):
    try:
        with open(a.load_json) as f:
            load = json.load(f)
    except (OSError, ValueError):
        load = None
    samples = lag_samples(a.emu_log, a.from_line, a.to_line)
    if samples:
        # The load began in (first - 1 s, first]; keep what is surely inside it.
        cut = samples[0][0] - 1.0 + a.load_seconds + 0.05
        samples = [s for s in samples if s[0] <= cut]
    if a.lag_csv:
        with open(a.lag_csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["wall_s", "lag_ms", "max_lag_ms"])
            w.writerows(samples)
    end_lag = statistics.median([s[1] for s in samples[-END_SAMPLES:]]) if samples else math.nan
    growth = theil_sen_slope(samples)
    keeps = (load is not None and len(samples) >= 3 and end_lag < MAX_END_LAG_MS
             and growth < MAX_SLOPE_MS_PER_S)
    s = read_summary(a.summary_json)
    nan = math.nan

    def num(v):
        return nan if v is None else float(v)

    rtt = (load or {}).get("rtt_ms", {})
    row = {"n": a.n, "keeps_real_time": int(keeps), "end_lag_ms": end_lag,
           "lag_slope_ms_per_s": growth,
           "max_lag_ms": s["max_lag_ms"], "late_tick_fraction": s["late_tick_fraction"],
           "pings_sent": (load or {}).get("pings_sent", 0),
           "pings_delivered": (load or {}).get("pings_delivered", 0),
           "acked": (load or {}).get("acked", 0),
           "delivery_ratio": num((load or {}).get("delivery_ratio")),
           "round_trip_ratio": num((load or {}).get("round_trip_ratio")),
           "rtt_mean_ms": num(rtt.get("mean")), "rtt_p10_ms": num(rtt.get("p10")),
           "rtt_p50_ms": num(rtt.get("p50")), "rtt_p90_ms": num(rtt.get("p90")),
           "rtt_p99_ms": num(rtt.get("p99")), "floor_ms": a.floor_ms}
    row["rtt_mean_x_floor"] = row["rtt_mean_ms"] / a.floor_ms
    row["rtt_p90_x_floor"] = row["rtt_p90_ms"] / a.floor_ms
    for reason in ("collision", "half_duplex", "below_sensitivity", "decode_failure"):
        row[f"lost_{reason}"] = s["emu_lost"].get(reason, 0)
    row["emu_frames"] = s["emu_frames"]
    row["emu_delivered"] = s["emu_delivered"]
    # The emulator's CPU (all its threads) over the load, as a share of one core.
    cpu = 100.0 * a.cpu_s / a.cpu_wall_s if a.cpu_s is not None and a.cpu_wall_s else nan
    row["cpu_percent"] = cpu
    row["cpu_per_node_percent"] = cpu / a.n
    iperf = ""
    if a.iperf_json:
        row.update(iperf_figures(a.iperf_json))
        iperf = (f"; iperf3 UDP {row['iperf_goodput_kbps']:.0f} of {row['iperf_offered_kbps']:.0f}"
                 f" kbit/s, lost {row['iperf_lost_percent']:.2f} %, jitter "
                 f"{row['iperf_jitter_ms']:.2f} ms")
    append_row(a.out, row)
    print(f"N={a.n:3d}: {'keeps' if keeps else 'does NOT keep'} real time "
          f"(end lag {end_lag:.2f} ms, slope {growth:.3f} ms/s, worst {s['max_lag_ms']:.1f} ms); "
          f"delivery {row['delivery_ratio']:.3f}, round trips {row['round_trip_ratio']:.3f}, "
          f"rtt mean {row['rtt_mean_ms']:.2f} p90 {row['rtt_p90_ms']:.2f} ms; "
          f"cpu {cpu:.1f} % of a core ({row['cpu_per_node_percent']:.2f} % per node){iperf}")


def iperf_figures(path):
    """Offered and received rate (kbit/s of UDP payload), loss and jitter of an
    `iperf3 -u -J` client's report; NaN for each when the report is missing or
    is an error (iperf3 writes {"error": ...})."""
    nan = math.nan
    out = {"iperf_offered_kbps": nan, "iperf_goodput_kbps": nan, "iperf_lost_percent": nan,
           "iperf_jitter_ms": nan}
    try:
        with open(path) as f:
            end = json.load(f)["end"]
    except (OSError, ValueError, KeyError, TypeError):
        return out
    sent = end.get("sum_sent") or end.get("sum") or {}
    got = end.get("sum_received") or end.get("sum") or {}
    out["iperf_offered_kbps"] = float(sent.get("bits_per_second", nan)) / 1e3
    # iperf3 3.12 reports the receiver's side as sum_received; older ones only
    # the sender's rate and the receiver's loss in `sum`.
    if "sum_received" in end:
        out["iperf_goodput_kbps"] = float(got.get("bits_per_second", nan)) / 1e3
    else:
        out["iperf_goodput_kbps"] = (float(got.get("bits_per_second", nan))
                                     * (1 - float(got.get("lost_percent", nan)) / 100) / 1e3)
    out["iperf_lost_percent"] = float((end.get("sum") or {}).get("lost_percent", nan))
    out["iperf_jitter_ms"] = float((end.get("sum") or {}).get("jitter_ms", nan))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("rtt-row")
    r.add_argument("--ping-csv", required=True)
    c = sub.add_parser("capacity-row")
    c.add_argument("--load-json", required=True)
    c.add_argument("--emu-log", required=True)
    c.add_argument("--from-line", type=int, required=True)
    c.add_argument("--to-line", type=int, required=True)
    c.add_argument("--load-seconds", type=float, required=True)
    c.add_argument("--lag-csv")
    c.add_argument("--cpu-s", type=float, help="emulator CPU seconds (user + system) over the load")
    c.add_argument("--cpu-wall-s", type=float, help="wall seconds those CPU seconds were spent in")
    c.add_argument("--iperf-json", help="an iperf3 -u -J client report run beside the load")
    for p in (r, c):
        p.add_argument("--n", type=int, required=True)
        p.add_argument("--summary-json", required=True)
        p.add_argument("--floor-ms", type=float, required=True)
        p.add_argument("--out", required=True)
    a = ap.parse_args()
    rtt_row(a) if a.cmd == "rtt-row" else capacity_row(a)


if __name__ == "__main__":
    main()
