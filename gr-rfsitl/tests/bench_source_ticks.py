#!/usr/bin/python3
"""How many ticks per second an emulator_source (with its sink) sustains: a
fake emulator in this process ticks one node as fast as the node answers
(virtual time), each tick carrying B received samples, and the node transmits
continuously (so every kTx is full). Real time at 1 Msps with B = 250 needs
4000 ticks/s. The fake is plain Python, so the figure is a lower bound on what
the block itself can do. With --realtime the fake paces the ticks at 1 Msps
instead and the CPU time of the process (node and fake) is reported.

    PYTHONPATH=<build>/python /usr/bin/python3 bench_source_ticks.py [--chain gmsk]
"""

import argparse
import os
import shutil
import sys
import tempfile
import time

import numpy as np
from gnuradio import analog, blocks, gr
from gnuradio import rfsitl
from gnuradio.rfsitl.fake_emulator import TICK, FakeEmulator, HEADER, MAGIC

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--tick-samples", type=int, default=250)
    ap.add_argument("--realtime", action="store_true",
                    help="pace the ticks at 1 Msps and report CPU use instead of the peak rate")
    ap.add_argument("--chain", choices=["null", "gmsk"], default="null",
                    help="what consumes the received samples: a null sink or the example "
                         "GMSK receiver (examples/gnuradio/gmsk_node.py)")
    args = ap.parse_args()
    B = args.tick_samples
    gr.logging().set_default_level(gr.log_levels.warn)

    tmp = tempfile.mkdtemp(prefix="rfsitl_bench_")
    path = os.path.join(tmp, "emu.sock")
    emu = FakeEmulator(path, tick_samples=B)
    tb = gr.top_block()
    src = rfsitl.emulator_source(path, 1, 2000, 5000)
    snk = rfsitl.emulator_sink(path, 1)
    if args.chain == "gmsk":
        sys.path.insert(0, os.path.join(HERE, "..", "..", "examples", "gnuradio"))
        from gmsk_node import GmskRx
        tb.connect(src, GmskRx())
    else:
        tb.connect(src, blocks.null_sink(gr.sizeof_gr_complex))
    tb.connect(analog.sig_source_c(1e6, analog.GR_COS_WAVE, 1e3, 1.0), snk)
    tb.start()
    node = emu.accept(timeout=10)
    # One pre-built tick message; only tick/time change (no numpy per tick).
    rng = np.random.default_rng(0)
    rx = ((rng.standard_normal(B) + 1j * rng.standard_normal(B)) / np.sqrt(2)).astype(np.complex64)
    msg = bytearray(HEADER.pack(MAGIC, TICK, 0, 0, 0, B, 0) + rx.tobytes())
    sock = node.sock
    k, tx_total = 0, 0
    t0 = time.monotonic()
    cpu0 = time.process_time()  # every thread of this process: the node and the fake
    end = t0 + args.seconds
    while time.monotonic() < end:
        if args.realtime:
            ahead = t0 + k * B / 1e6 - time.monotonic()
            if ahead > 0:
                time.sleep(ahead)
        for _ in range(1 if args.realtime else 100):
            HEADER.pack_into(msg, 0, MAGIC, TICK, 0, k, k * B, B if k else 0, 0)
            sock.send(msg if k else msg[:HEADER.size])
            reply = sock.recv(65536)
            tx_total += (len(reply) - HEADER.size) // 8
            k += 1
    wall = time.monotonic() - t0
    cpu = time.process_time() - cpu0
    tb.stop()
    tb.wait()
    node.close()
    emu.close()
    shutil.rmtree(tmp, ignore_errors=True)
    rate = k / wall
    print("chain=%s B=%d: %d ticks in %.2f s = %.0f ticks/s = %.2f Msps (%.1fx real time at "
          "1 Msps); tx samples per tick %.1f; source ticks %d discontinuities %d"
          % (args.chain, B, k, wall, rate, rate * B / 1e6, rate * B / 1e6, tx_total / k,
             src.ticks(), src.discontinuities()))
    print("CPU: %.2f s in %.2f s wall = %.0f%% of one core (node + Python fake)"
          % (cpu, wall, 100 * cpu / wall))


if __name__ == "__main__":
    main()
