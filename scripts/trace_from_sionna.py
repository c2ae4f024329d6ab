#!/usr/bin/env python3
"""Turn ray-traced paths (e.g. exported from Sionna RT) into a channel trace
for rfsitl's `trace` stage (docs/channel_traces.md). Standard library only.

Input: JSON,
    {
      "carrier_hz": 2.4e9,
      "baseband": false,
      "links": [
        {"tx": 1, "rx": 2, "samples": [
          {"t_s": 0.0, "a": [[0.001, -0.0002], [0.0003, 0.0001]], "tau_s": [1.7e-8, 2.9e-8]},
          ...]},
        ...]
    }
tx and rx are the scenario's node ids; each sample lists the paths at time
t_s: complex coefficients a_k as [re, im] and delays tau_k in seconds (what
Sionna RT's Paths holds per transmitter/receiver pair and time step: `a` and
`tau`, one antenna each).

Model (narrowband): the link's complex gain at the carrier is
    h = sum_k a_k exp(-j 2 pi fc tau_k)
("baseband": false, the default: a_k are passband path coefficients, without
the carrier's propagation phase), or h = sum_k a_k ("baseband": true: a_k are
already baseband-equivalent, a_k exp(-j 2 pi fc tau_k), as a channel impulse
response is). The delay spread is assumed well below the symbol time: the
trace carries one complex gain per link, no taps. gain_db = 20 log10 |h|
(-300 dB when no path reaches: h = 0), phase_deg = arg h in degrees.

Output: the CSV format (t_s,tx,rx,gain_db,phase_deg), or with --npy the NPY
format (float64 (T, L, 2)) plus its links file; NPY needs every link sampled at
the same times t_k = k * step_s.

Usage:
    trace_from_sionna.py paths.json -o trace.csv
    trace_from_sionna.py paths.json --npy trace.npy --links trace_links.csv
"""
import argparse
import cmath
import json
import math
import struct
import sys

GAIN_FLOOR_DB = -300.0  # the trace stage's lower limit
GAIN_CEILING_DB = 100.0


class InputError(Exception):
    pass


def link_gain(sample, carrier_hz, baseband, where):
    """The complex gain h of one sample's paths."""
    a = sample.get("a", [])
    tau = sample.get("tau_s", [])
    if len(a) != len(tau):
        raise InputError(f"{where}: {len(a)} coefficients but {len(tau)} delays")
    h = 0j
    for k, (coeff, delay) in enumerate(zip(a, tau)):
        if not (isinstance(coeff, list) and len(coeff) == 2):
            raise InputError(f"{where}: a[{k}] must be [re, im]")
        ak = complex(float(coeff[0]), float(coeff[1]))
        h += ak if baseband else ak * cmath.exp(-2j * math.pi * carrier_hz * float(delay))
    return h


def gain_phase(h, where):
    magnitude = abs(h)
    gain_db = 20.0 * math.log10(magnitude) if magnitude > 0 else GAIN_FLOOR_DB
    gain_db = max(gain_db, GAIN_FLOOR_DB)
    if not math.isfinite(gain_db) or gain_db > GAIN_CEILING_DB:
        raise InputError(f"{where}: gain {gain_db} dB is above {GAIN_CEILING_DB} dB")
    return gain_db, math.degrees(cmath.phase(h))


def convert(doc):
    """[(tx, rx, [(t_s, gain_db, phase_deg), ...]), ...], samples in time order."""
    carrier_hz = float(doc["carrier_hz"])
    baseband = bool(doc.get("baseband", False))
    if not carrier_hz > 0:
        raise InputError("carrier_hz must be > 0")
    links = []
    seen = set()
    for i, link in enumerate(doc["links"]):
        tx, rx = int(link["tx"]), int(link["rx"])
        if tx == rx or (tx, rx) in seen:
            raise InputError(f"links[{i}]: {tx}->{rx} repeats a link or joins a node to itself")
        seen.add((tx, rx))
        rows = []
        for j, sample in enumerate(link["samples"]):
            where = f"links[{i}].samples[{j}]"
            h = link_gain(sample, carrier_hz, baseband, where)
            rows.append((float(sample["t_s"]),) + gain_phase(h, where))
        rows.sort(key=lambda r: r[0])
        links.append((tx, rx, rows))
    return links


def write_csv(links, out):
    out.write("t_s,tx,rx,gain_db,phase_deg\n")
    for tx, rx, rows in links:
        for t_s, gain_db, phase_deg in rows:
            out.write(f"{t_s!r},{tx},{rx},{gain_db:.6f},{phase_deg:.6f}\n")


def write_npy(links, npy_path, links_path):
    """float64 (T, L, 2), C order, NPY format 1.0; the links file alongside."""
    times = [r[0] for r in links[0][2]]
    for tx, rx, rows in links:
        if [r[0] for r in rows] != times:
            raise InputError(f"--npy: link {tx}->{rx} is not sampled at the first link's times")
    if len(times) > 1:
        step = (times[-1] - times[0]) / (len(times) - 1)
        if times[0] != 0 or any(abs(t - k * step) > 1e-9 * max(1.0, t) for k, t in enumerate(times)):
            raise InputError("--npy: the times must be 0, step, 2 step, ...")
        print(f"step_s: {step!r}", file=sys.stderr)
    header = "{'descr': '<f8', 'fortran_order': False, 'shape': (%d, %d, 2), }" % (
        len(times), len(links))
    header += " " * ((-(10 + len(header) + 1)) % 64) + "\n"
    with open(npy_path, "wb") as f:
        f.write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode("ascii"))
        for k in range(len(times)):
            for _, _, rows in links:
                f.write(struct.pack("<2d", rows[k][1], rows[k][2]))
    with open(links_path, "w") as f:
        f.write("tx,rx\n")
        for tx, rx, _ in links:
            f.write(f"{tx},{rx}\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("input", help="paths as JSON (see this script's docstring)")
    parser.add_argument("-o", "--output", help="CSV trace (default: standard output)")
    parser.add_argument("--npy", help="write the NPY format here instead")
    parser.add_argument("--links", help="with --npy: the links file")
    args = parser.parse_args()
    try:
        with open(args.input) as f:
            links = convert(json.load(f))
        if not links:
            raise InputError("no links")
        if args.npy:
            if not args.links:
                raise InputError("--npy needs --links")
            write_npy(links, args.npy, args.links)
        elif args.output:
            with open(args.output, "w") as out:
                write_csv(links, out)
        else:
            write_csv(links, sys.stdout)
    except (InputError, KeyError, TypeError, ValueError, OSError) as e:
        sys.exit(f"trace_from_sionna: {args.input}: {e}")


if __name__ == "__main__":
    main()
