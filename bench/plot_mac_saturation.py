#!/usr/bin/env python3
"""Plots `rfsitl_mac_saturation` CSV: goodput of mac none, tdma and csma
against the number of senders, with Bianchi's analytic DCF saturation
throughput beside csma (left), and csma's collision probability beside the
model's (right).

    build/release/bench/rfsitl_mac_saturation --csv out/mac/mac_saturation.csv
    /usr/bin/python3 bench/plot_mac_saturation.py out/mac/mac_saturation.csv \\
        -o out/mac/mac_saturation.png
"""

import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()
    with open(args.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{args.csv}: no rows")
    n = [int(r["n"]) for r in rows]

    def col(key):
        return [float(r[key]) for r in rows]

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    left.plot(n, col("csma_kbps"), "o-", label="csma (measured)")
    left.plot(n, col("bianchi_kbps"), "k--", label="Bianchi's model")
    left.plot(n, col("tdma_kbps"), "s-", label="tdma")
    left.plot(n, col("none_kbps"), "x-", label="none")
    left.set_xlabel("saturated senders N")
    left.set_ylabel("goodput to the sink (kbit/s)")
    left.set_xscale("log", base=2)
    left.set_xticks(n, [str(v) for v in n])
    left.set_ylim(bottom=0)
    left.grid(alpha=0.3)
    left.legend()
    right.plot(n, col("csma_p"), "o-", label="csma (ACK timeouts / transmissions)")
    right.plot(n, col("bianchi_p"), "k--", label="Bianchi's p")
    right.set_xlabel("saturated senders N")
    right.set_ylabel("collision probability")
    right.set_xscale("log", base=2)
    right.set_xticks(n, [str(v) for v in n])
    right.set_ylim(bottom=0)
    right.grid(alpha=0.3)
    right.legend()
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)


if __name__ == "__main__":
    main()
