#!/usr/bin/env python3
"""Plots packet error rate versus SNR from `rfsitl_per_sweep` CSV, one curve per
PHY/rate, with the theoretical curve of each uncoded PHY from its BER formula,
and prints the SNR at which each curve crosses 10% and 1% PER.

    /usr/bin/python3 bench/plot_per.py out/per/per_vs_snr.csv -o out/per/per_vs_snr.png
"""

import argparse
import csv
import math
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# GMSK: BER = Q(sqrt(2 alpha Eb/N0)) (Murota and Hirade's form). With coherent
# detection MSK reaches alpha = 1, the BPSK bound; GMSK at BT = 0.5 stays close
# to MSK (BT = 0.25 costs about 1.7 dB: alpha = 0.68), so the reference drawn is
# alpha = 1. Per-sample SNR at k = 2 samples per bit: Eb/N0 = 2 SNR. A packet is
# lost when any of its bits is: PER = 1 - (1 - BER)^n, with n the bits under the
# CRCs (about 736 for both GMSK frame formats with an 80-byte payload).
GMSK_ALPHA = 1.0
GMSK_BITS = 8 * (8 + 80 + 4)


def q(x):
    return 0.5 * math.erfc(x / math.sqrt(2.0))


def gmsk_theory(snr_db):
    ebn0 = 2.0 * 10 ** (snr_db / 10.0)
    ber = q(math.sqrt(2.0 * GMSK_ALPHA * ebn0))
    return 1.0 - (1.0 - ber) ** GMSK_BITS


# DSSS with DBPSK at 1 sample per chip: differential detection of BPSK,
# BER = exp(-Eb/N0) / 2, with Eb/N0 = L SNR for L chips per bit (the processing
# gain). The CRCs cover the 13-byte header and the payload with its CRC-32
# (8 * (13 + 80 + 4) = 776 bits).
DSSS_BITS = 8 * (13 + 80 + 4)


def dsss_dbpsk_theory(chips):
    def per(snr_db):
        ber = 0.5 * math.exp(-chips * 10 ** (snr_db / 10.0))
        return 1.0 - (1.0 - ber) ** DSSS_BITS
    return per


# GFSK at k = 8 samples per bit: non-coherent orthogonal binary FSK,
# BER = exp(-Eb / 2N0) / 2, Eb/N0 = 8 SNR. The CRCs cover the 10-byte header
# (with its CRC-16) and the payload with its CRC-16: 8 * (10 + 80 + 2) = 736 bits.
# Only the energy detector at h = 1 (orthogonal tones) is that theory's receiver;
# the SiK-like discriminator is drawn against the same curve to show its gap.
GFSK_BITS = 8 * (10 + 80 + 2)


def gfsk_noncoherent_theory(snr_db):
    ber = 0.5 * math.exp(-8 * 10 ** (snr_db / 10.0) / 2.0)
    return 1.0 - (1.0 - ber) ** GFSK_BITS


THEORY = {
    "gmsk": ("coherent MSK bound (uncoded GMSK)", gmsk_theory),
    "dsss-barker11-dbpsk": ("DSSS DBPSK L=11 theory", dsss_dbpsk_theory(11)),
    "dsss-mseq31-dbpsk": ("DSSS DBPSK L=31 theory", dsss_dbpsk_theory(31)),
    "dsss-mseq127-dbpsk": ("DSSS DBPSK L=127 theory", dsss_dbpsk_theory(127)),
    "gfsk-energy-h1": ("non-coherent BFSK theory (k = 8)", gfsk_noncoherent_theory),
}


def crossing(points, target, floor=1e-9):
    """SNR where PER first falls to `target`, interpolating log10(PER) linearly
    (a measured 0 counts as `floor`, half a frame's worth)."""
    points = sorted(points)
    for (s0, p0), (s1, p1) in zip(points, points[1:]):
        if p0 > target >= p1:
            l0, l1 = math.log10(max(p0, floor)), math.log10(max(p1, floor))
            lt = math.log10(target)
            return s0 + (s1 - s0) * (l0 - lt) / (l0 - l1)
    return None


def sort_key(name):
    digits = "".join(ch for ch in name if ch.isdigit())
    return (name.rstrip("0123456789"), int(digits) if digits else 0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()

    curves = defaultdict(list)
    frames = 0
    with open(args.csv) as f:
        for row in csv.DictReader(f):
            curves[row["phy"]].append((float(row["snr_db"]), float(row["per"])))
            frames = max(frames, int(row["frames"]))
    floor = 0.5 / frames if frames else 1e-4

    fig, ax = plt.subplots(figsize=(10, 6))
    # Up to 20 curves: tab20 keeps every one its own colour.
    ax.set_prop_cycle(color=[plt.cm.tab20(i) for i in range(20)])
    print("| PHY | SNR at 10% PER | SNR at 1% PER | theory at 10% / 1% |")
    print("|---|---|---|---|")
    for name in sorted(curves, key=sort_key):
        pts = sorted(curves[name])
        line, = ax.semilogy([s for s, _ in pts], [max(p, floor) for _, p in pts], "o-",
                            markersize=3, label=name)
        s10, s1 = crossing(pts, 0.1, floor), crossing(pts, 0.01, floor)
        theory = ""
        # Both GMSK implementations are compared with the one GMSK formula, and
        # both GFSK receivers with the non-coherent BFSK one.
        key = name
        if name.startswith("gmsk"):
            key = "gmsk"
        elif name.startswith("gfsk"):
            key = "gfsk-energy-h1"
        if key in THEORY:
            label, fn = THEORY[key]
            xs = [x / 10 for x in range(int(pts[0][0] * 10) - 20, int(pts[-1][0] * 10) + 1)]
            tp = [(x, fn(x)) for x in xs]
            if key == name:
                ax.semilogy(xs, [max(p, floor) for _, p in tp], "--", color=line.get_color(),
                            label=label)
            t10, t1 = crossing(tp, 0.1), crossing(tp, 0.01)
            theory = f"{t10:.1f} dB / {t1:.1f} dB" if t10 and t1 else ""
        fmt = lambda v: f"{v:.1f} dB" if v is not None else "n/a"  # noqa: E731
        print(f"| {name} | {fmt(s10)} | {fmt(s1)} | {theory} |")
    ax.set_xlabel("SNR per sample [dB] (signal power / noise power in fs)")
    ax.set_ylabel(f"packet error rate ({frames} frames of 80 bytes per point)")
    ax.set_ylim(floor * 0.8, 1.05)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(ncol=2, fontsize=8)
    ax.set_title("rfsitl: PER versus SNR through the emulator's channel")
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(f"plot: {args.output}")


if __name__ == "__main__":
    main()
