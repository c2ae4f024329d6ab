#!/usr/bin/python3
"""End to end with the real emulator: `rfsitl run --nodes 2 --phy external`
(real time, its default channel) and two examples/gnuradio/gmsk_node.py
processes as nodes 1 and 2. TCP clients on the nodes' net ports exchange
20 frames each way (80-byte payloads 1 -> 2, 8-byte answers 2 -> 1) and a
broadcast; then the emulator is stopped and both nodes must exit by
themselves (emulator gone for good).

Exits 77 (ctest: skipped) when the rfsitl binary is missing or predates
external transceivers. Loopback only; every wait is bounded.
    PYTHONPATH=<build>/python /usr/bin/python3 test_two_nodes_emulator.py --rfsitl build/release/apps/rfsitl
"""

import argparse
import os
import queue
import random
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time

TERM = b"\r\r\n\n"
SKIP = 77
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
from test_two_nodes_fake import read_lines, recv_frames, wait_line  # noqa: E402


def free_base():
    """A port base whose net (base + 10 n) and location (base + 3 + 10 n)
    ports for nodes 1 and 2 are free on 127.0.0.1."""
    for _ in range(50):
        base = random.randrange(20000, 40000, 10)
        socks = []
        try:
            for port in (base + 10, base + 20, base + 13, base + 23):
                s = socket.socket()
                s.bind(("127.0.0.1", port))
                socks.append(s)
            return base
        except OSError:
            continue
        finally:
            for s in socks:
                s.close()
    raise RuntimeError("no free ports found")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rfsitl", default=os.path.join(ROOT, "build", "release", "apps", "rfsitl"))
    ap.add_argument("--gmsk-node", default=os.path.join(ROOT, "examples", "gnuradio",
                                                        "gmsk_node.py"))
    ap.add_argument("--python", default="/usr/bin/python3")
    ap.add_argument("--frames", type=int, default=20)
    args = ap.parse_args()

    if not os.access(args.rfsitl, os.X_OK):
        print("SKIP: no rfsitl binary at %s (build it first)" % args.rfsitl)
        return SKIP
    usage = subprocess.run([args.rfsitl, "run", "--help"], capture_output=True, text=True,
                           timeout=30).stdout
    if "external" not in usage:
        print("SKIP: %s has no external transceivers (rebuild it)" % args.rfsitl)
        return SKIP

    tmp = tempfile.mkdtemp(prefix="rfsitl_gr_e2e_")
    path = os.path.join(tmp, "emu.sock")
    base = free_base()
    emu_cmd = [args.rfsitl, "run", "--nodes", "2", "--phy", "external", "--net-base", str(base),
               "--loc-base", str(base + 3), "--external-socket", path]
    if "--no-dashboard" in usage:
        emu_cmd.append("--no-dashboard")
    emu_log = open(os.path.join(tmp, "emulator.log"), "w+")
    emu = subprocess.Popen(emu_cmd, stdout=emu_log, stderr=subprocess.STDOUT)
    procs, errfiles, outq, logs, clients = [], [], {}, {}, []
    ok = False
    try:
        deadline = time.monotonic() + 20
        while not os.path.exists(path) and time.monotonic() < deadline and emu.poll() is None:
            time.sleep(0.05)
        assert os.path.exists(path), "the emulator did not create %s" % path
        for node in (1, 2):
            err = open(os.path.join(tmp, "node%d.log" % node), "w+")
            errfiles.append(err)
            p = subprocess.Popen(
                [args.python, args.gmsk_node, "--socket", path, "--id", str(node),
                 "--net-base", str(base), "--reconnect-ms", "3000"],
                stdout=subprocess.PIPE, stderr=err, text=True)
            procs.append(p)
            outq[node], logs[node] = queue.Queue(), []
            threading.Thread(target=read_lines, args=(p.stdout, outq[node]), daemon=True).start()
        for node in (1, 2):
            print(wait_line(outq[node], "ready", 30, logs[node]))

        c1 = socket.create_connection(("127.0.0.1", base + 10))
        c2 = socket.create_connection(("127.0.0.1", base + 20))
        clients = [c1, c2]
        for c in clients:
            c.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        time.sleep(0.2)
        rng = random.Random(7)
        lat = []
        for i in range(args.frames):
            f = bytes([1, 2]) + bytes(rng.randrange(256) for _ in range(80))
            t = time.monotonic()
            c1.sendall(f + TERM)
            got = recv_frames(c2, 1, 5)
            lat.append(time.monotonic() - t)
            assert got == [f], "frame %d 1 -> 2: node 2 got %r" % (i, got)
            a = bytes([2, 1]) + bytes([i]) * 8
            c2.sendall(a + TERM)
            got = recv_frames(c1, 1, 5)
            assert got == [a], "answer %d 2 -> 1: node 1 got %r" % (i, got)
        b = bytes([2, 255]) + b"broadcast"
        c2.sendall(b + TERM)
        assert recv_frames(c1, 1, 5) == [b], "broadcast not delivered"
        print("%d frames each way + a broadcast delivered; 1 -> 2 (80 bytes, 1.66 ms on the "
              "air) one-way ms: mean %.2f median %.2f max %.2f"
              % (args.frames, 1e3 * statistics.mean(lat), 1e3 * statistics.median(lat),
                 1e3 * max(lat)))

        emu.send_signal(signal.SIGINT)
        emu.wait(timeout=15)
        for node, p in zip((1, 2), procs):
            rc = p.wait(timeout=20)  # 3 s of reconnect attempts, then exit
            wait_line(outq[node], "gmsk_node: node %d stopped" % node, 5, logs[node])
            assert rc == 0, "node %d exited with %d" % (node, rc)
            assert any("emulator gone" in line for line in logs[node]), logs[node]
        print("emulator stopped; both nodes exited by themselves")
        ok = True
    finally:
        for c in clients:
            c.close()
        for p in procs + [emu]:
            if p.poll() is None:
                p.kill()
                p.wait()
        emu_log.seek(0)
        summary = emu_log.read()
        if not ok:
            print("---- emulator ----\n%s" % summary[-4000:])
            for node, err in zip((1, 2), errfiles):
                err.seek(0)
                print("---- node %d stderr ----\n%s" % (node, err.read()[-3000:]))
                print("---- node %d stdout ----\n%s" % (node, "\n".join(logs.get(node, []))))
        else:
            tail = [line for line in summary.splitlines() if "summary" in line]
            print("\n".join(tail))
        for f in errfiles + [emu_log]:
            f.close()
        shutil.rmtree(tmp, ignore_errors=True)
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
