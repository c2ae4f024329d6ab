#!/usr/bin/env python3
"""Plots the empirical CDF of round-trip times from `rfsitl ping --csv` files
(the analogue of the RF-SITL paper's Fig. 4).

    /usr/bin/python3 scripts/plot_rtt.py out/demo/rtt_*.csv -o out/demo/rtt_cdf.png
"""

import argparse
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_rtts(path):
    with open(path) as f:
        return sorted(float(r["rtt_ms"]) for r in csv.DictReader(f) if r["status"] == "ok")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv", nargs="+")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--floor-ms", type=float, default=0.0,
                    help="draw the air-time floor (frame + acknowledgement) at this RTT")
    ap.add_argument("--title", default="rfsitl: round-trip time of 80-byte GMSK packets")
    args = ap.parse_args()

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for path in args.csv:
        rtts = read_rtts(path)
        if not rtts:
            continue
        label = os.path.splitext(os.path.basename(path))[0].replace("rtt_", "").replace("_", " -> ")
        ys = [(i + 1) / len(rtts) for i in range(len(rtts))]
        ax.step(rtts, ys, where="post", label=f"{label} (mean {sum(rtts) / len(rtts):.2f} ms)")
    if args.floor_ms > 0:
        ax.axvline(args.floor_ms, color="k", linestyle="--", linewidth=1,
                   label=f"air-time floor {args.floor_ms:.2f} ms")
    ax.set_xlabel("round-trip time [ms]")
    ax.set_xlim(left=0)
    ax.set_ylabel("empirical CDF")
    ax.set_title(args.title)
    ax.grid(True, alpha=0.3)
    ax.set_ylim(0, 1.02)
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(f"plot: {args.output}")


if __name__ == "__main__":
    main()
