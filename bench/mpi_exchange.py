#!/usr/bin/python3
"""What a distributed run costs (issue: runs across machines on MPI), printed,
not asserted: for N nodes and K ranks (mpirun, oversubscribed on this
machine), a virtual-time run of the default formation where every node sends
an 80-byte GMSK frame to a random other node every `--interval` seconds; per
run: wall time per tick, the bytes each rank sends per tick (from the
summary's `distributed.per_rank`), the share of wall time in the exchanges,
and the same run in one process (K = 0: no mpirun) for the baseline. Then the
model of bytes and time per tick, extrapolated (see the README section
"Distributed runs" for its assumptions).

With --realtime the same runs go at speed 1 for `--seconds` of wall time, and
each row says whether every rank kept real time: the worst lag of any rank
behind the wall clock, its late ticks, and the lag at the end.

    RFSITL_BIN=build/release/apps/rfsitl /usr/bin/python3 bench/mpi_exchange.py \\
        [--nodes 16,32,64] [--ranks 0,1,2,4] [--seconds 2] [--realtime]
"""

import argparse
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
BIN = os.environ.get("RFSITL_BIN", os.path.join(HERE, "..", "build", "release", "apps", "rfsitl"))
MPI_FLAGS = ["--oversubscribe", "--allow-run-as-root", "--mca", "btl", "self,vader,tcp",
             "--bind-to", "none"]


def scenario(n, seconds, interval, mode, seed=5):
    rng = random.Random(seed)
    lines = [f"name: mpi-bench-{n}", "seed: 3", f"time: {{mode: {mode}, duration_s: {seconds}}}",
             f"nodes: {n}", "traffic:"]
    for src in range(1, n + 1):
        dst = rng.choice([d for d in range(1, n + 1) if d != src])
        lines.append(f"  - {{at_s: {rng.uniform(0.01, interval):.4f}, src: {src}, dst: {dst}, "
                     f"size_bytes: 80, repeat: {int(seconds / interval)}, interval_s: {interval}}}")
    return "\n".join(lines) + "\n"


def run(d, n, k, seconds, interval, mode, base):
    path = os.path.join(d, f"s{n}.yaml")
    with open(path, "w") as f:
        f.write(scenario(n, seconds, interval, mode))
    summary = os.path.join(d, f"n{n}k{k}.json")
    cmd = [BIN, "run", path, "--no-dashboard", "--summary-json", summary,
           "--net-base", str(base), "--loc-base", str(base + 3), "--stats-interval", "0"]
    if k > 0:
        cmd = ["mpirun", "-n", str(k), *MPI_FLAGS, *cmd]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=1800)
    if r.returncode != 0:
        sys.exit(f"N={n} K={k}: exit {r.returncode}\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
    with open(summary) as f:
        j = json.load(f)
    return j


def runs(a, mode):
    """Every (N, K) of the arguments in turn: yields (n, k, summary, per_rank)."""
    with tempfile.TemporaryDirectory() as d:
        base = 21000  # below Linux's ephemeral ports (32768-60999), which mpirun uses
        for n in [int(x) for x in a.nodes.split(",")]:
            for k in [int(x) for x in a.ranks.split(",")]:
                j = run(d, n, k, a.seconds, a.interval, mode, base)
                base += 10 * n + 100
                yield n, k, j, j.get("distributed", {}).get("per_rank", [])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--nodes", default="16,32,64")
    ap.add_argument("--ranks", default="0,1,2,4")
    ap.add_argument("--seconds", type=float, default=2.0)
    ap.add_argument("--interval", type=float, default=0.05,
                    help="seconds between a node's frames (0.05: 20 frames/s per node)")
    ap.add_argument("--realtime", action="store_true",
                    help="run at speed 1 and report each run's lag behind the wall clock")
    a = ap.parse_args()
    if a.realtime:
        realtime(a)
        return
    if shutil.which("mpirun") is None:
        sys.exit("mpirun not found: apt-get install openmpi-bin libopenmpi-dev (scripts/setup.sh)")
    fs, tick = 1e6, 250  # the defaults
    ticks = a.seconds * fs / tick
    print(f"virtual {a.seconds} s, {ticks:.0f} ticks of {tick} samples at 1 Msps, GMSK, every node "
          f"one 80-byte frame per {a.interval} s to a random node; {os.cpu_count()} cores")
    print("| N | K | engine wall s | ms per tick | B sent per tick per rank (mean) | in exchanges | "
          "delivered |")
    print("|---|---|---|---|---|---|---|")
    for n, k, j, per_rank in runs(a, "virtual"):
        sent = (sum(p["exchanged_bytes"] for p in per_rank) / len(per_rank) / ticks
                if per_rank else 0.0)
        share = (sum(p["exchange_wall_s"] / p["wall_s"] for p in per_rank) / len(per_rank)
                 if per_rank else 0.0)
        delivered = sum(x["delivered"] for x in j["nodes"])
        wall_s = j["wall_s"]  # the engine's run, without mpirun's start and end
        print(f"| {n} | {k or '1 (no mpirun)'} | {wall_s:.2f} | {1e3 * wall_s / ticks:.3f} | "
              f"{sent:.0f} | {100 * share:.0f} % | {delivered} |", flush=True)
    # The model: an all-gather moves each transmitter's samples to the K - 1
    # other ranks; 8 bytes per complex sample.
    print()
    print("model: bytes received per rank per tick = active transmitters x B x 8 B x (K - 1) / K "
          "... each rank sends its own transmitters' samples to K - 1 ranks")
    for name, bw, lat in (("10 GbE (TCP)", 1.25e9, 30e-6), ("InfiniBand HDR", 25e9, 2e-6)):
        n, k, b = 1000, 16, 250
        active = 0.1 * n  # a tenth of the nodes on the air in a tick
        bytes_tick = active * b * 8 * (k - 1) / k  # arriving at each rank
        t = bytes_tick / bw + 4 * 2 * lat  # log2(16) = 4 stages, 2 exchanges per tick
        print(f"  1000 nodes on 16 hosts over {name}: {bytes_tick / 1e3:.0f} kB per rank per tick, "
              f"{1e6 * t:.0f} us per tick in exchanges, against a tick of {1e6 * b / fs:.0f} us at "
              f"1 Msps")


def realtime(a):
    """Real-time runs: does every rank keep up with the wall clock?"""
    print(f"real time, {a.seconds} s per run, 250-sample ticks at 1 Msps, GMSK, every node one "
          f"80-byte frame per {a.interval} s to a random node; {os.cpu_count()} cores")
    print("| N | K | worst lag ms (rank) | late ticks (all ranks) | lag at end ms | delivered | "
          "real time |")
    print("|---|---|---|---|---|---|---|")
    for n, k, j, per_rank in runs(a, "realtime"):
        if per_rank:
            worst, rank = max((p["max_lag_s"], r) for r, p in enumerate(per_rank))
            late = sum(p["late_ticks"] for p in per_rank)
        else:
            worst, rank, late = j["max_lag_s"], 0, j.get("late_ticks", 0)
        end = j["lag_s"]
        delivered = sum(x["delivered"] for x in j["nodes"])
        # Real time held: the run ended on the clock (a lag that grew
        # to the end would show there) and no rank fell a second behind.
        held = end < 0.05 and worst < 1.0
        print(f"| {n} | {k or '1 (no mpirun)'} | {1e3 * worst:.1f} ({rank}) | {late} | "
              f"{1e3 * end:.1f} | {delivered} | {'yes' if held else 'no'} |", flush=True)


if __name__ == "__main__":
    main()
