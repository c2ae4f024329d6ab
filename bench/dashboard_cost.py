#!/usr/bin/python3
"""What the dashboard costs the emulator: CPU time, memory and real-time lag of
`rfsitl run --nodes N` (64 by default) with the dashboard off, on without
viewers, and on with V WebSocket viewers that each watch a node (spectrum,
constellation and a snapshot every 0.25 s), under the same ping traffic.

    /usr/bin/python3 bench/dashboard_cost.py [--bin build/release/apps/rfsitl]
        [--nodes 64] [--seconds 20] [--viewers 1 4] [--csv out/bench/dashboard_cost.csv]

Each configuration is one run of its own on fresh ports; CPU is the emulator
process's user + system time over the measured window (after a warm-up),
memory its peak resident set (VmHWM). The viewers here are minimal Python
WebSocket clients that read every message (what a browser would receive);
rendering in the browser costs the viewer's machine, not the emulator.
Standard library only, loopback only, bounded in time.
"""

import argparse
import csv
import json
import os
import random
import re
import signal
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests",
                                "integration"))
from ws_client import WsClient  # noqa: E402 (after the path)

TICKS = os.sysconf("SC_CLK_TCK")


def proc_cpu_s(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS  # utime + stime


def proc_mem_kb(pid, key):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1])
    return 0


class Viewer(threading.Thread):
    """A WebSocket client of /ws that watches one node and reads everything."""

    def __init__(self, port, node):
        super().__init__(daemon=True)
        self.ws = WsClient("127.0.0.1", port, timeout=5)
        self.ws.send({"type": "watch", "node": node})
        self.bytes = 0
        self.messages = 0
        self.stop = False

    def run(self):
        self.ws.sock.settimeout(2)
        try:
            while not self.stop:
                _, fin, payload = self.ws.read_frame()
                self.bytes += len(payload)
                self.messages += 1 if fin else 0  # FIN: a message's last frame
        except (OSError, ConnectionError):
            pass


def measure(args, mode, viewers, index):
    base = args.port_base + 1000 * (index % 30) + random.randrange(0, 900, 10)
    net_base = base + 3
    cmd = [args.bin, "run", "--nodes", str(args.nodes), "--net-base", str(net_base),
           "--loc-base", str(base + 6), "--stats-interval", "0", "--dashboard-port", "0"]
    if mode == "off":
        cmd.append("--no-dashboard")
    emu = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines = []
    port = None
    deadline = time.monotonic() + 60
    for line in emu.stdout:
        lines.append(line)
        m = re.search(r"rfsitl: dashboard http://127\.0\.0\.1:(\d+)/", line)
        if m:
            port = int(m.group(1))
        if "rfsitl: ready" in line or time.monotonic() > deadline:
            break
    threading.Thread(target=lambda: [lines.append(x) for x in emu.stdout], daemon=True).start()
    pings = subprocess.Popen([args.bin, "ping", "--src", "1", "--dst", str(args.nodes),
                              "--count", "100000", "--interval", "0.02", "--timeout", "1",
                              "--net-base", str(net_base), "-q"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    clients = []
    try:
        for v in range(viewers):
            c = Viewer(port, 1 + (v * 17) % args.nodes)
            c.start()
            clients.append(c)
        time.sleep(args.warmup)
        cpu0, t0 = proc_cpu_s(emu.pid), time.monotonic()
        time.sleep(args.seconds)
        cpu1, t1 = proc_cpu_s(emu.pid), time.monotonic()
        hwm = proc_mem_kb(emu.pid, "VmHWM")
        received = sum(c.bytes for c in clients)
        messages = sum(c.messages for c in clients)
    finally:
        for c in clients:
            c.stop = True
        pings.send_signal(signal.SIGINT)
        try:
            pings.wait(10)
        except subprocess.TimeoutExpired:
            pings.kill()
        emu.send_signal(signal.SIGINT)
        try:
            emu.wait(30)
        except subprocess.TimeoutExpired:
            emu.kill()
    text = "".join(lines)
    lag = re.search(r"worst real-time lag ([\d.]+) ms, late ticks (\d+)", text)
    return {"mode": mode if mode == "off" else f"on, {viewers} viewer(s)", "nodes": args.nodes,
            "viewers": viewers, "cpu_percent": round(100 * (cpu1 - cpu0) / (t1 - t0), 1),
            "peak_rss_mb": round(hwm / 1024, 1),
            "ws_kbytes_per_s_per_viewer": round(received / 1024 / (t1 - t0) / max(viewers, 1), 1),
            "ws_messages_per_s_per_viewer": round(messages / (t1 - t0) / max(viewers, 1), 1),
            "worst_lag_ms": float(lag.group(1)) if lag else float("nan"),
            "late_ticks": int(lag.group(2)) if lag else -1}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default="build/release/apps/rfsitl")
    ap.add_argument("--port-base", type=int, default=int(os.environ.get("PORT_BASE", "20000")),
                    help="first of the port ranges used (base + 1000 k); default $PORT_BASE "
                         "or 20000")
    ap.add_argument("--nodes", type=int, default=64)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--warmup", type=float, default=3.0)
    ap.add_argument("--viewers", type=int, nargs="*", default=[1, 4])
    ap.add_argument("--csv", default="")
    args = ap.parse_args()
    runs = [("off", 0), ("on", 0)] + [("on", v) for v in args.viewers]
    rows = []
    for i, (mode, viewers) in enumerate(runs):
        row = measure(args, mode, viewers, i)
        rows.append(row)
        print(f"{row['mode']:>18}: CPU {row['cpu_percent']:6.1f} %  peak RSS "
              f"{row['peak_rss_mb']:7.1f} MB  per viewer {row['ws_kbytes_per_s_per_viewer']:7.1f} "
              f"KB/s ({row['ws_messages_per_s_per_viewer']} msg/s)  worst lag "
              f"{row['worst_lag_ms']} ms", flush=True)
    base = rows[0]
    for r in rows[1:]:
        print(f"{r['mode']:>18}: +{r['cpu_percent'] - base['cpu_percent']:.1f} points of CPU, "
              f"+{r['peak_rss_mb'] - base['peak_rss_mb']:.1f} MB over the dashboard off")
    if args.csv:
        os.makedirs(os.path.dirname(args.csv) or ".", exist_ok=True)
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
