#!/usr/bin/python3
"""Delivery ratio against swarm spacing: GMSK and 802.11a/g OFDM, Rayleigh
and Rician fading, ten seeds each, as campaigns of virtual-time runs.

Six UAVs on a 3 x 2 grid, 30 m up, each sending 80-byte frames to its
neighbour 20 times a second; free-space path loss at 2.4 GHz from 0 dBm
transmitters, then block fading (the nodes hover: each seed draws each link's
fade once). For every PHY, fading model and spacing the script writes the
scenario, runs it as a campaign over the seeds (`rfsitl sweep`, one process
per run, resumable), and gathers the tables into one.

    PYTHONPATH=build/release/python RFSITL_BIN=build/release/apps/rfsitl \\
        /usr/bin/python3 examples/python/spacing_sweep.py --out spacing.results
    ... spacing_sweep.py --out spacing.results --plot spacing.png
    ... spacing_sweep.py --quick        # 3 spacings, 2 seeds, 1 s runs: a minute

It prints the mean delivery ratio per PHY, fading model and spacing with its
95 % confidence interval over the seeds. Running it again reuses every row
already in the tables.
"""

import argparse
import os

import pandas
import yaml

from rfsitl.campaign import Campaign
from rfsitl.plotting import mean_ci95, plot_metric

SPACINGS_M = [100, 200, 400, 800, 1600]
PHYS = {
    # GMSK at the emulator's default 1 Msps; OFDM at 20 Msps, 100 us ticks.
    "gmsk": ({"type": "gmsk"}, {}),
    "ofdm": ({"type": "ofdm", "rate_mbps": 6}, {"sample_rate_hz": 20e6, "tick_us": 100}),
}
FADING = {
    "rayleigh": {"type": "fading", "model": "rayleigh"},
    "rician": {"type": "fading", "model": "rician", "k_db": 6},
}


def scenario(phy, fading, spacing_m, duration_s):
    settings, timing = PHYS[phy]
    nodes = [{"id": i + 1, "position": {"x": spacing_m * (i % 3), "y": spacing_m * (i // 3),
                                        "z": 30}} for i in range(6)]
    traffic = [{"at_s": 0.01 + 0.007 * i, "src": i + 1, "dst": (i + 1) % 6 + 1,
                "size_bytes": 80, "repeat": int(20 * duration_s) - 1, "interval_s": 0.05}
               for i in range(6)]
    return {
        "name": f"spacing-{phy}-{fading}-{spacing_m}m",
        "time": {"mode": "virtual", "duration_s": duration_s, **timing},
        "phy": settings,
        "radio": {"carrier_hz": 2.4e9, "tx_power_dbm": 0, "noise_figure_db": 7},
        "channel": {"stages": [{"type": "path_loss", "model": "free_space"}, FADING[fading]]},
        "nodes": nodes,
        "traffic": traffic,
    }


def run(out, spacings, seeds, duration_s, jobs):
    tables = []
    for phy in PHYS:
        for fading in FADING:
            for spacing in spacings:
                folder = os.path.join(out, f"{phy}-{fading}-{spacing}m")
                os.makedirs(folder, exist_ok=True)
                with open(os.path.join(folder, "scenario.yaml"), "w") as f:
                    yaml.safe_dump(scenario(phy, fading, spacing, duration_s), f, sort_keys=False)
                table = Campaign.from_dict({"scenario": "scenario.yaml", "seeds": seeds,
                                            "output": "results"}, folder=folder).run(
                                                jobs=jobs, quiet=True)
                tables.append(table.assign(phy=phy, fading=fading, spacing_m=spacing))
    return pandas.concat(tables, ignore_index=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="spacing.results", help="folder of the campaigns")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--duration", type=float, default=2.0, help="virtual seconds per run")
    ap.add_argument("--jobs", type=int, default=None, help="runs at once (default: cores)")
    ap.add_argument("--quick", action="store_true", help="3 spacings, 2 seeds, 1 s runs")
    ap.add_argument("--plot", help="write a PNG of the delivery ratio against the spacing")
    args = ap.parse_args()
    spacings, seeds, duration = SPACINGS_M, args.seeds, args.duration
    if args.quick:
        spacings, seeds, duration = [100, 400, 1600], 2, 1.0
    df = run(args.out, spacings, seeds, duration, args.jobs)
    failed = df[df["status"] != "ok"]
    if len(failed):
        print(f"{len(failed)} runs failed:\n{failed[['phy', 'fading', 'spacing_m', 'seed', 'error']]}")
    df = df[df["status"] == "ok"]
    df.to_csv(os.path.join(args.out, "all.csv"), index=False)
    print(f"{'phy':5s} {'fading':9s} {'spacing':>8s}  delivery ratio (95 % CI over seeds)")
    for (phy, fading, spacing), g in df.groupby(["phy", "fading", "spacing_m"]):
        mean, half, _ = mean_ci95(g["delivery_ratio"].to_numpy())
        print(f"{phy:5s} {fading:9s} {spacing:6d} m  {mean:.3f} +- {half:.3f}  (n={len(g)})")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        df = df.assign(config=df["phy"] + " / " + df["fading"])
        fig, ax = plt.subplots(figsize=(7, 4))
        plot_metric(df, "delivery_ratio", by="spacing_m", hue="config", ax=ax)
        ax.set_xscale("log")
        ax.set_xlabel("spacing (m)")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=100)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
