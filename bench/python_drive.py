#!/usr/bin/python3
"""The cost of driving the engine from Python: virtual-time speed of one
scenario run by rfsitl_virtual_speed (C++, in one go) and by the Python
module in one step, in steps of 100 ms, and in steps of 100 ms reading the
counters and the link table after each (as a controller would), alternated
run by run; medians and their ratios to the C++ figure.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_drive.py \
        --bench-bin build/release/bench/rfsitl_virtual_speed [--nodes 15] [--duration 60] [--runs 3]

The scenario: N nodes on a grid 20 m apart, each sending an 80-byte frame a
second to a random other node at a random time (the load rfsitl_virtual_speed
puts on its default formation), written to a temporary file both read.
"""

import argparse
import os
import random
import re
import statistics
import subprocess
import sys
import tempfile
import time


def scenario_yaml(nodes, duration, seed):
    rng = random.Random(seed)
    lines = ["name: python-drive", f"seed: {seed}",
             "time: {mode: virtual, duration_s: %g}" % (duration + 0.05),
             "engine: {stats_interval_s: 0}", "nodes:"]
    side = max(1, int(nodes ** 0.5 + 0.999))
    for i in range(nodes):
        lines.append(f"  - {{id: {i + 1}, position: {{x: {20 * (i % side)}, "
                     f"y: {20 * (i // side)}, z: 10}}}}")
    lines.append("traffic:")
    for i in range(nodes):
        for k in range(int(duration)):
            j = rng.randrange(nodes - 1)
            j = j + 1 if j >= i else j
            lines.append(f"  - {{at_s: {k + rng.random():.6f}, src: {i + 1}, dst: {j + 1}, "
                         f"size_bytes: 80}}")
    return "\n".join(lines) + "\n"


def cxx_speed(bench_bin, path):
    out = subprocess.run([bench_bin, "--scenario", path], capture_output=True, text=True,
                         check=True).stdout
    return float(re.search(r"speed=([0-9.]+) x", out).group(1))


def python_speed(path, step_s, read):
    """Speed through the module, stepping `step_s` (reading the counters and
    the link table after each step if `read`)."""
    import rfsitl
    emu = rfsitl.Emulator(path, keep_frames=False, record_events=False, iq=False)
    t0 = time.perf_counter()
    while not emu.done:
        emu.run_for(step_s)
        if read:
            emu.counters()
            emu.links()
    wall = time.perf_counter() - t0
    return emu.now / wall


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bench-bin", required=True, help="rfsitl_virtual_speed of the same build")
    ap.add_argument("--nodes", type=int, default=15)
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--step", type=float, default=0.1, help="Python's step, virtual seconds")
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "scenario.yaml")
        with open(path, "w") as f:
            f.write(scenario_yaml(args.nodes, args.duration, 1))
        kinds = {
            "rfsitl_virtual_speed (C++, one go)": lambda: cxx_speed(args.bench_bin, path),
            "module, one step": lambda: python_speed(path, args.duration + 1.0, False),
            f"module, {args.step} s steps": lambda: python_speed(path, args.step, False),
            f"module, {args.step} s steps + counters + links": lambda: python_speed(
                path, args.step, True),
        }
        speeds = {k: [] for k in kinds}
        for _ in range(args.runs):  # alternated, so that a busy moment hits all alike
            for name, run in kinds.items():
                speeds[name].append(run())
    print(f"python_drive: nodes={args.nodes} duration={args.duration} s runs={args.runs}")
    base = statistics.median(speeds[next(iter(kinds))])
    for name, values in speeds.items():
        m = statistics.median(values)
        print(f"  {name:44s} median {m:8.2f} x real time  ratio {m / base:.3f}  "
              f"({', '.join(f'{v:.1f}' for v in values)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
