#!/usr/bin/env python3
"""Plots the packet error rate in Rayleigh block fading from `rfsitl_fading_per`
CSV: per PHY (one colour each) the measured fading PER against mean SNR, its
reference (the measured AWGN curve averaged over the exponential SNR
distribution), the reference over the bench's own fade sample, and the AWGN
curve itself against SNR; log PER. Prints the gaps at a few PER levels.

    build/release/bench/rfsitl_fading_per --csv out/fading_per/fading_per.csv
    /usr/bin/python3 bench/plot_fading_per.py out/fading_per/fading_per.csv \
        -o out/fading_per/fading_per.png
"""

import argparse
import csv
import math
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LEVELS = (0.1, 0.03)


def crossing(points, level):
    """Mean SNR where a decreasing curve first falls below `level`, log10(PER)
    interpolated linearly (the bench's own rule)."""
    for (s0, p0), (s1, p1) in zip(points, points[1:]):
        if p0 >= level > p1 > 0:
            l0, l1, lt = math.log10(p0), math.log10(p1), math.log10(level)
            return s0 + (s1 - s0) * (l0 - lt) / (l0 - l1)
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()

    # rows[phy][kind] = [(snr_db, per, frames)]
    rows = defaultdict(lambda: defaultdict(list))
    with open(args.csv) as f:
        for r in csv.DictReader(f):
            rows[r["phy"]][r["kind"]].append((float(r["snr_db"]), float(r["per"]),
                                              int(r["frames"])))
    for kinds in rows.values():
        for pts in kinds.values():
            pts.sort()

    measured_frames = [n for k in rows.values() for _, _, n in k["fading"] + k["awgn"]]
    floor = 0.5 / max(measured_frames) if measured_frames else 1e-4
    fig, ax = plt.subplots(figsize=(10, 8))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, phy in enumerate(sorted(rows)):
        c = colours[i % len(colours)]
        k = rows[phy]
        # Points without errors are left out: on a log axis they have no place.
        awgn = [(s, p) for s, p, _ in k["awgn"] if p > 0]
        ax.semilogy([s for s, _ in awgn], [p for _, p in awgn], "s-", color=c,
                    markersize=3, linewidth=0.8, alpha=0.6, label=f"{phy}: AWGN (x axis: SNR)")
        ref = [(s, p) for s, p, _ in k["reference"]]
        ax.semilogy([s for s, _ in ref], [p for _, p in ref], "-", color=c, linewidth=1.6,
                    label=f"{phy}: reference, AWGN curve averaged over Exp(1)")
        real = [(s, p) for s, p, _ in k["realized"] if p > 0]
        if real:
            ax.semilogy([s for s, _ in real], [p for _, p in real], ":", color=c,
                        linewidth=1.2, label=f"{phy}: AWGN curve averaged over the bench's fades")
        fad = k["fading"]
        # Binomial 1-sigma bars (a point without errors gets none).
        sig = [math.sqrt(p * (1 - p) / n) for _, p, n in fad]
        gaps = []
        meas = [(s, max(p, floor)) for s, p, _ in fad]
        for level in LEVELS:
            a, b = crossing(meas, level), crossing(ref, level)
            if a is None or b is None:
                gaps.append(f"n/a at {level:g}")
            else:
                gaps.append(f"{a - b:+.2f} dB at {level:g}")
                print(f"{phy}: PER {level:g}: measured {a:.2f} dB, reference {b:.2f} dB, "
                      f"gap {a - b:+.2f} dB")
        ax.errorbar([s for s, _, _ in fad], [max(p, floor) for _, p, _ in fad],
                    yerr=[[min(e, max(p, floor) - floor * 0.5) for e, (_, p, _) in zip(sig, fad)],
                          sig],
                    fmt="o", color=c, markersize=6, markerfacecolor="white", markeredgewidth=1.5,
                    capsize=2, linestyle="none",
                    label=f"{phy}: Rayleigh block fading, measured (gap {', '.join(gaps)})")
    n_fading = max((n for k in rows.values() for _, _, n in k["fading"]), default=0)
    ax.set_xlabel("mean SNR per sample [dB] (fading); SNR per sample [dB] (AWGN)")
    ax.set_ylabel(f"packet error rate (80-byte frames; {n_fading} per fading point)")
    lowest = min((p for k in rows.values() for kind in ("awgn", "fading")
                  for _, p, _ in k[kind] if p > 0), default=floor)
    ax.set_ylim(max(floor, lowest) * 0.5, 1.1)
    ax.grid(True, which="both", alpha=0.3)
    # Below the axes: inside, eight entries would cover a curve wherever they went.
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2)
    ax.set_title("rfsitl: PER in Rayleigh block fading (fading stage, receiver hops between frames)"
                 "\nagainst the measured AWGN PER averaged over the exponential SNR distribution",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(f"plot: {args.output}")


if __name__ == "__main__":
    main()
