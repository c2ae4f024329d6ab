"""Shared by the benchmark report scripts (bench_plots.py, bench_summary.py): reading
the CSV files bench/run_benchmarks.sh writes, and the published numbers we compare with.
"""

import csv
import glob
import math
import os

# RF-SITL paper (GNU Radio 3.7, 12-vCPU VM, 80-byte GMSK packets, 1 Msps), in ms.
PAPER_N6_ONE_FLOWGRAPH_MS = 2670.0
PAPER_N6_SPLIT_MS = 150.0
PAPER_N15_SPLIT_MS = 300.0  # "under 300 ms" (Fig. 5, split architecture)

# Targets of the performance issue (2 cores, real time, 1 Msps).
TARGET_N6_MEAN_MS = 6.0
TARGET_N15_MEAN_MS = 8.0
TARGET_N15_P90_MS = 12.0
TARGET_CAPACITY_N = 32
TARGET_CAPACITY_FADING_N = 64  # issue 13: 64 nodes, 4-tap Rician fading, real time
TARGET_MIX_FRACTION = 0.60
TARGET_VIRTUAL_SPEED = 20.0


def num(v):
    """A CSV cell as float (NaN when empty or not a number)."""
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def read_rows(path):
    """Rows of a CSV file as dicts; [] when the file is missing."""
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def read_rtts(path):
    """Sorted RTTs (ms) of the acknowledged packets of a `rfsitl ping --csv` file, and losses."""
    rows = read_rows(path)
    ok = sorted(num(r["rtt_ms"]) for r in rows if r["status"] == "ok")
    return ok, len(rows) - len(ok)


def fig4_curves(out):
    """{architecture: csv path} of the Fig. 4 runs."""
    paths = sorted(glob.glob(os.path.join(out, "fig4", "rtt_*.csv")))
    return {os.path.basename(p)[len("rtt_"):-len(".csv")]: p for p in paths}


def floor_ms(out):
    rows = read_rows(os.path.join(out, "airtime.csv"))
    return num(rows[-1]["floor_ms"]) if rows else math.nan


def percentile(sorted_values, q):
    """Linear-interpolated percentile, as `rfsitl ping` computes it."""
    if not sorted_values:
        return math.nan
    pos = q * (len(sorted_values) - 1)
    lo = math.floor(pos)
    hi = min(lo + 1, len(sorted_values) - 1)
    return sorted_values[lo] + (pos - lo) * (sorted_values[hi] - sorted_values[lo])


def mean(values):
    return sum(values) / len(values) if values else math.nan
