#!/usr/bin/python3
"""IP throughput over the emulated radio: iperf3 (Debian) TCP and UDP between
two IP nodes 10 m apart, per PHY and MAC, beside the air-time bound of
1500-byte IP packets and csma's saturation throughput for one sender.

    sudo /usr/bin/python3 bench/ip_throughput.py [--bin build/release/apps/rfsitl]
        [--bench-dir build/release/bench] [--seconds 10] [--csv out/ip/ip_throughput.csv]

Each case runs `rfsitl run --ip` (real time) with the case's PHY and MAC,
starts `iperf3 -s` in node 2's namespace and, from node 1's:
  * TCP: `iperf3 -c 10.77.0.2 -M 1460 -t T` (1500-byte IP packets);
  * UDP: `iperf3 -c 10.77.0.2 -u -l 1472 -b RATE -t T`, RATE 1.2 times the
    air-time bound (the excess is dropped by the full TX queue, and counted).
Goodput is what iperf3's receiver got (payload bits per second). The bounds
(`rfsitl_mac_saturation --bounds`) are for 1514-byte radio payloads (a
1500-byte IP packet in its Ethernet frame): frames back to back (air), and
one csma sender's saturation throughput (DIFS, mean backoff, SIFS, ACK), both
in bits of IP packet per second. iperf3 counts its payload only, 1448 of the
1500 bytes for TCP (with timestamps) and 1472 for UDP.

Needs root, iproute2 and iperf3; every namespace is the emulator's own and is
removed when it stops.
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "integration"))

CASES = (  # (label, phy YAML, sample rate, MAC)
    ("gmsk", "{type: gmsk}", 1e6, "none"),
    ("gmsk", "{type: gmsk}", 1e6, "csma"),
    ("gmsk", "{type: gmsk}", 1e6, "tdma"),
    ("ofdm 6", "{type: ofdm, rate_mbps: 6}", 2e6, "csma"),
    ("ofdm 24", "{type: ofdm, rate_mbps: 24}", 2e6, "csma"),
)
IP_PACKET = 1500
RADIO_PAYLOAD = IP_PACKET + 14  # in its Ethernet frame


def bounds(bench_dir, phy_yaml, fs):
    args = [os.path.join(bench_dir, "rfsitl_mac_saturation"), "--bounds", "--payload",
            str(RADIO_PAYLOAD), "--sample-rate", str(fs)]
    if "ofdm" in phy_yaml:
        rate = phy_yaml.split("rate_mbps:")[1].strip(" }")
        args += ["--phy", "ofdm", "--rate-mbps", rate]
    out = subprocess.run(args, capture_output=True, text=True, check=True, timeout=60).stdout
    row = dict(zip(*[line.split(",") for line in out.strip().splitlines()]))
    scale = IP_PACKET / RADIO_PAYLOAD  # Ethernet header bits are not IP bits
    return float(row["air_kbps"]) * scale, float(row["csma_kbps"]) * scale


def in_netns(name, *cmd, timeout=60):
    return subprocess.run(["ip", "netns", "exec", name, *cmd], capture_output=True, text=True,
                          timeout=timeout)


def wait_reachable(netns, address, timeout=30.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if in_netns(netns, "ping", "-c", "1", "-W", "1", address).returncode == 0:
            return True
    return False


def iperf(prefix, seconds, udp_kbps=None):
    """Goodput (kbit/s) iperf3's receiver reported, or None."""
    server = subprocess.Popen(["ip", "netns", "exec", f"{prefix}-2", "iperf3", "-s", "-1"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(0.5)  # the server's listen(): iperf3 -c would fail before it
        cmd = ["iperf3", "-c", "10.77.0.2", "-t", str(seconds), "-J"]
        cmd += ["-u", "-l", "1472", "-b", f"{udp_kbps:.0f}k"] if udp_kbps else ["-M", "1460"]
        run = in_netns(f"{prefix}-1", *cmd, timeout=seconds + 60)
        try:
            end = json.loads(run.stdout)["end"]
        except (ValueError, KeyError):
            return None
        if not udp_kbps:
            return end["sum_received"]["bits_per_second"] / 1e3
        # UDP: iperf3 3.12 reports the receiver's side as sum_received; older
        # ones only the sender's rate and the receiver's loss in `sum`.
        if "sum_received" in end:
            return end["sum_received"]["bits_per_second"] / 1e3
        return end["sum"]["bits_per_second"] * (1 - end["sum"]["lost_percent"] / 100) / 1e3
    finally:
        server.kill()
        server.wait()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default="build/release/apps/rfsitl")
    ap.add_argument("--bench-dir", default="build/release/bench")
    ap.add_argument("--seconds", type=int, default=10)
    ap.add_argument("--csv")
    args = ap.parse_args()
    os.environ["RFSITL_BIN"] = os.path.abspath(args.bin)
    from harness import Emulator  # noqa: E402 (reads RFSITL_BIN)

    rows = []
    print("| PHY | fs | MAC | TCP kbit/s | UDP kbit/s | air bound | csma bound | TCP / csma |")
    print("|---|---|---|---|---|---|---|---|")
    for label, phy, fs, mac in CASES:
        air, csma = bounds(args.bench_dir, phy, fs)
        extra = f"phy: {phy}\nmac: {{type: {mac}}}\ntime: {{sample_rate_hz: {fs:.0f}}}\n"
        with Emulator({1: (0, 0, 10), 2: (10, 0, 10)}, extra_yaml=extra,
                      args=["--ip", "--no-dashboard"]) as emu:
            prefix = f"rfsitl-{emu.net_base}"
            if not wait_reachable(f"{prefix}-1", "10.77.0.2"):
                print(f"| {label} | {fs / 1e6:g} Msps | {mac} | node 2 unreachable |")
                continue
            tcp = iperf(prefix, args.seconds)
            udp = iperf(prefix, args.seconds, udp_kbps=1.2 * air)
        ratio = f"{tcp / csma:.2f}" if tcp and mac == "csma" else "-"
        fmt = lambda v: f"{v:.1f}" if v is not None else "failed"  # noqa: E731
        print(f"| {label} | {fs / 1e6:g} Msps | {mac} | {fmt(tcp)} | {fmt(udp)} | {air:.1f} | "
              f"{csma:.1f} | {ratio} |", flush=True)
        rows.append({"phy": label, "sample_rate_hz": fs, "mac": mac, "tcp_kbps": tcp,
                     "udp_kbps": udp, "air_kbps": air, "csma_kbps": csma})
    if args.csv:
        os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ["phy"])
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
