#!/usr/bin/env python3
"""Draws the benchmark figures from the CSV files in OUT (bench/run_benchmarks.sh).

    /usr/bin/python3 bench/bench_plots.py out/bench

Writes fig4_rtt_cdf.png, fig5_rtt_vs_n.png, capacity.png and mix_kernel.png for the
stages whose data exist. The dashed line in the RTT plots is the air-time floor.
"""

import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import bench_common as bc  # noqa: E402


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"plot: {path}")


def plot_fig4(out, floor):
    curves = bc.fig4_curves(out)
    if not curves:
        return
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for arch, path in curves.items():
        rtts, lost = bc.read_rtts(path)
        if not rtts:
            continue
        ys = [(i + 1) / len(rtts) for i in range(len(rtts))]
        ax.step(rtts, ys, where="post",
                label=f"rfsitl {arch} (mean {bc.mean(rtts):.2f} ms, {lost} lost)")
    if floor == floor:
        ax.axvline(floor, color="k", linestyle="--", linewidth=1,
                   label=f"air-time floor {floor:.3f} ms")
    ax.set_xlabel("round-trip time [ms]")
    ax.set_xlim(left=0)
    ax.set_ylim(0, 1.02)
    ax.set_ylabel("empirical CDF")
    ax.set_title("Fig. 4 analogue: 80-byte GMSK ping RTT, N = 6, real time, 1 Msps\n"
                 f"(paper: mean {bc.PAPER_N6_ONE_FLOWGRAPH_MS:.0f} ms one flowgraph, "
                 f"{bc.PAPER_N6_SPLIT_MS:.0f} ms split)", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower right")
    save(fig, os.path.join(out, "fig4_rtt_cdf.png"))


def plot_fig5(out, floor):
    rows = [r for r in bc.read_rows(os.path.join(out, "fig5_rtt_vs_n.csv"))]
    if not rows:
        return
    ns = [int(r["n"]) for r in rows]
    mean = [bc.num(r["mean_ms"]) for r in rows]
    p10 = [bc.num(r["p10_ms"]) for r in rows]
    p90 = [bc.num(r["p90_ms"]) for r in rows]
    lag = [bc.num(r["max_lag_ms"]) for r in rows]
    fig, (ax, lx) = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True,
                                 gridspec_kw={"height_ratios": [3, 1.3]})
    ax.fill_between(ns, p10, p90, alpha=0.25, label="rfsitl p10 ... p90")
    ax.plot(ns, mean, "o-", label="rfsitl mean")
    if floor == floor:
        ax.axhline(floor, color="k", linestyle="--", linewidth=1,
                   label=f"air-time floor {floor:.3f} ms")
    ax.plot([6, 15], [bc.PAPER_N6_SPLIT_MS, bc.PAPER_N15_SPLIT_MS], "s", color="tab:red",
            label="paper, split (mean)")
    ax.set_yscale("log")
    ax.set_ylabel("round-trip time [ms]")
    ax.set_title("Fig. 5 analogue: 80-byte GMSK ping RTT (node 1 <-> node N), real time",
                 fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    lx.plot(ns, lag, "o-", color="tab:purple")
    lx.set_ylabel("worst lag [ms]")
    lx.set_xlabel("nodes N")
    lx.set_xscale("log", base=2)
    lx.set_xticks(ns if len(ns) <= 12 else [n for n in ns if n in (2, 3, 4, 6, 8, 10, 15, 32, 64)])
    lx.set_xticklabels([str(n) for n in lx.get_xticks()])
    lx.grid(True, alpha=0.3)
    save(fig, os.path.join(out, "fig5_rtt_vs_n.png"))


def plot_capacity(out, name="capacity", title="1 ping/node/s"):
    rows = bc.read_rows(os.path.join(out, f"{name}.csv"))
    if not rows:
        return
    fig, (lx, dx) = plt.subplots(1, 2, figsize=(11, 4.5))
    for r in rows:
        lag = bc.read_rows(os.path.join(out, name, f"lag_{r['n']}.csv"))
        if not lag:
            continue
        t0 = bc.num(lag[0]["wall_s"])
        mark = "" if r["keeps_real_time"] == "1" else " (falls behind)"
        lx.plot([bc.num(x["wall_s"]) - t0 for x in lag], [bc.num(x["lag_ms"]) for x in lag],
                ".-", label=f"N = {r['n']}{mark}")
    lx.axhline(50, color="k", linestyle="--", linewidth=1, label="50 ms bound at the end")
    lx.set_yscale("symlog", linthresh=1)
    lx.set_ylim(bottom=0)
    lx.set_xlabel("seconds into the load")
    lx.set_ylabel("lag of the latest tick [ms] (stats lines)")
    lx.set_title(f"Real-time lag under load ({title})", fontsize=10)
    lx.grid(True, alpha=0.3)
    lx.legend(fontsize=8)
    ns = [int(r["n"]) for r in rows]
    dx.plot(ns, [bc.num(r["delivery_ratio"]) for r in rows], "o-", label="delivery ratio (frames)")
    dx.plot(ns, [bc.num(r["round_trip_ratio"]) for r in rows], "s-",
            label="round trips completed")
    dx.set_ylim(0, 1.05)
    dx.set_xlabel("nodes N")
    dx.set_ylabel("ratio")
    ax2 = dx.twinx()
    ax2.plot(ns, [bc.num(r["rtt_p90_ms"]) for r in rows], "^--", color="tab:red",
             label="RTT p90 [ms]")
    ax2.set_yscale("log")
    ax2.set_ylabel("RTT p90 [ms]")
    for n, r in zip(ns, rows):
        if r["keeps_real_time"] != "1":
            dx.axvspan(n - 1, n + 1, color="tab:red", alpha=0.15)
    dx.set_title("Delivery under load (shaded: not real time)", fontsize=10)
    dx.grid(True, alpha=0.3)
    h1, l1 = dx.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    dx.legend(h1 + h2, l1 + l2, fontsize=8, loc="lower left")
    save(fig, os.path.join(out, f"{name}.png"))


def plot_mix(out):
    rows = bc.read_rows(os.path.join(out, "mix_kernel.csv"))
    mixes = [r for r in rows if r["kind"] == "mix"]
    peaks = [r for r in rows if r["kind"] == "peak"]
    if not mixes:
        return
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name in sorted({r["name"] for r in mixes}):
        for block in sorted({int(r["block"]) for r in mixes}):
            sel = [r for r in mixes if int(r["block"]) == block and r["name"] == name]
            if sel:
                ax.plot([int(r["n_inputs"]) for r in sel],
                        [bc.num(r["cmac_per_s"]) / 1e9 for r in sel],
                        "o-" if name == "channel::mix" else "s--", label=f"{name}, B = {block}")
    styles = iter(["--", "-.", ":", (0, (5, 1))])
    for p in peaks:
        ax.axhline(bc.num(p["cmac_per_s"]) / 1e9, color="k", linestyle=next(styles, "--"),
                   linewidth=1, label=f"peak {p['name']}")
    ax.set_xscale("log", base=2)
    ns = sorted({int(r["n_inputs"]) for r in mixes})
    ax.set_xticks(ns)
    ax.set_xticklabels([str(n) for n in ns])
    ax.set_xlabel("active inputs N")
    ax.set_ylabel("G complex MAC/s (one thread)")
    ax.set_ylim(bottom=0)
    ax.set_title("Mixing kernel against the CPU's measured peak (1 cMAC = 8 flops)", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    save(fig, os.path.join(out, "mix_kernel.png"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="directory the benchmark wrote (out/bench)")
    a = ap.parse_args()
    floor = bc.floor_ms(a.out)
    plot_fig4(a.out, floor)
    plot_fig5(a.out, floor)
    plot_capacity(a.out)
    plot_capacity(a.out, "ofdm_native", "802.11a/g 24 Mbit/s at 20 Msps, 1 ping/node/s")
    plot_mix(a.out)


if __name__ == "__main__":
    main()
