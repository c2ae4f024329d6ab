#!/usr/bin/python3
"""End to end without the emulator: two examples/gnuradio/gmsk_node.py
processes (nodes 1 and 2) join a fake emulator (gnuradio.rfsitl.fake_emulator)
that runs a two-node channel in real time: each node hears the other at
20 dB SNR and itself at 40 dB, over unit-power complex noise. TCP clients on
the nodes' net ports then exchange UB-ANC frames:

  1 -> 2 (80-byte payload, written in two pieces), 2 -> 1, 1 -> 255
  (broadcast: node 2 gets it, node 1's agent not its own), and 1 -> 3
  (node 2 drops it; a marker frame behind it arrives alone), then five
  frames 1 -> 2 in one TCP write (back-to-back bursts, in order).

With --node2-grc FILE, node 2 runs the flowgraph grcc generated from
examples/gnuradio/gmsk_node.grc instead (ready = its net port accepts).

Loopback only; every wait is bounded; exits non-zero on failure.
    PYTHONPATH=<build>/python /usr/bin/python3 test_two_nodes_fake.py
"""

import argparse
import os
import queue
import random
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np
from gnuradio.rfsitl.fake_emulator import FakeEmulator

TERM = b"\r\r\n\n"
B = 250
FS = 1e6
HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_NODE = os.path.join(HERE, "..", "..", "examples", "gnuradio", "gmsk_node.py")


class Channel(threading.Thread):
    """Lock-step ticks for the joined peers: rx_m = sum_n g[n][m] tx_n + noise,
    delivered one tick later (kTick k carries tick k-1's samples), paced to
    real time at fs. Records per-tick wall time for a throughput figure."""

    def __init__(self, peers, gains, seed=1):
        super().__init__(daemon=True)
        self.peers = peers
        self.gains = gains
        self.rng = np.random.default_rng(seed)
        self.stop_flag = threading.Event()
        self.error = None
        self.ticks = 0
        self.late_ticks = 0
        self.t0 = None
        self.tx_samples = [0] * len(peers)

    def noise(self):
        n = self.rng.standard_normal((2, B)).astype(np.float32)
        return ((n[0] + 1j * n[1]) / np.sqrt(2)).astype(np.complex64)

    def run(self):
        try:
            n = len(self.peers)
            rx = [None] * n  # first tick: nothing received yet
            t0 = self.t0 = time.monotonic()
            while not self.stop_flag.is_set():
                ks = [p.send_tick(rx[i]) for i, p in enumerate(self.peers)]
                tx = []
                for i, p in enumerate(self.peers):
                    x = p.recv_tx(ks[i])
                    self.tx_samples[i] += len(x)
                    tx.append(np.pad(x, (0, B - len(x))))
                rx = [sum(self.gains[j][i] * tx[j] for j in range(n)) + self.noise()
                      for i in range(n)]
                rx = [r.astype(np.complex64) for r in rx]
                self.ticks += 1
                ahead = t0 + self.ticks * B / FS - time.monotonic()
                if ahead > 0:
                    time.sleep(ahead)
                else:
                    self.late_ticks += 1
        except Exception as e:  # reported by the main thread
            self.error = e


def free_net_base():
    """A base whose ports base+10 and base+20 are free on 127.0.0.1."""
    for _ in range(50):
        base = random.randrange(20000, 40000)
        socks = []
        try:
            for node in (1, 2):
                s = socket.socket()
                s.bind(("127.0.0.1", base + 10 * node))
                socks.append(s)
            return base
        except OSError:
            continue
        finally:
            for s in socks:
                s.close()
    raise RuntimeError("no free port pair found")


def read_lines(stream, q):
    for line in iter(stream.readline, ""):
        q.put(line.rstrip("\n"))


def wait_line(q, needle, timeout, log):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            line = q.get(timeout=max(0.01, deadline - time.monotonic()))
        except queue.Empty:
            break
        log.append(line)
        if needle in line:
            return line
    raise TimeoutError("no line containing %r within %.0f s" % (needle, timeout))


def wait_port(port, timeout):
    """Waits until 127.0.0.1:port accepts a connection (then closes it)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            return
        except OSError:
            time.sleep(0.1)
    raise TimeoutError("port %d not listening within %.0f s" % (port, timeout))


def recv_frames(sock, want, timeout):
    """Reads until `want` frames (terminator included) arrived; returns them."""
    sock.settimeout(0.1)
    buf, frames = b"", []
    deadline = time.monotonic() + timeout
    while len(frames) < want and time.monotonic() < deadline:
        try:
            data = sock.recv(65536)
            if not data:
                break
            buf += data
        except socket.timeout:
            continue
        while TERM in buf:
            frame, buf = buf.split(TERM, 1)
            frames.append(frame)
    return frames


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gmsk-node", default=DEFAULT_NODE)
    ap.add_argument("--python", default="/usr/bin/python3")
    ap.add_argument("--node2-grc", default=None,
                    help="run node 2 from this grcc-generated gmsk_node.grc script")
    args = ap.parse_args()

    tmp = tempfile.mkdtemp(prefix="rfsitl_two_nodes_")
    path = os.path.join(tmp, "emu.sock")
    base = free_net_base()
    emu = FakeEmulator(path, sample_rate_hz=FS, tick_samples=B, time_mode="realtime")
    procs, errfiles, logs, channel, clients = [], [], {}, None, []
    ok = False
    try:
        outq = {}
        for node in (1, 2):
            err = open(os.path.join(tmp, "node%d.log" % node), "w+")
            errfiles.append(err)
            if node == 2 and args.node2_grc:
                cmd = [args.python, args.node2_grc, "--socket-path", path, "--node-id", "2",
                       "--net-base", str(base)]
            else:
                cmd = [args.python, args.gmsk_node, "--socket", path, "--id", str(node),
                       "--net-base", str(base), "--reconnect-ms", "5000"]
            p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=err, text=True)
            procs.append(p)
            outq[node] = queue.Queue()
            logs[node] = []
            threading.Thread(target=read_lines, args=(p.stdout, outq[node]), daemon=True).start()

        peers = {}
        for _ in (1, 2):
            peer = emu.accept(timeout=30)
            peers[peer.node_id] = peer
        assert sorted(peers) == [1, 2], peers
        iq = (1 + 1j) / np.sqrt(2)
        gains = [[100 * iq, 10 * iq], [10 * iq, 100 * iq]]  # gains[tx][rx]
        channel = Channel([peers[1], peers[2]], gains)
        channel.start()
        for node in (1, 2):
            if node == 2 and args.node2_grc:
                wait_port(base + 20, 20)
                print("node 2 (GRC flowgraph) listening on %d" % (base + 20))
                continue
            line = wait_line(outq[node], "ready", 20, logs[node])
            assert "node %d ready, net port %d" % (node, base + 10 * node) in line, line
            print(line)

        c1 = socket.create_connection(("127.0.0.1", base + 10))
        c2 = socket.create_connection(("127.0.0.1", base + 20))
        clients = [c1, c2]
        for c in clients:
            c.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        time.sleep(0.2)  # let socket_pdu register the clients
        rng = random.Random(5)

        def payload(n):
            return bytes(rng.randrange(256) for _ in range(n))

        # 1 -> 2, 80 bytes, written in two pieces that split the header.
        f12 = bytes([1, 2]) + payload(80)
        c1.sendall(f12[:1])
        time.sleep(0.01)
        t_send = time.monotonic()  # from the write that completes the frame
        c1.sendall(f12[1:] + TERM)
        got = recv_frames(c2, 1, 10)
        latency = time.monotonic() - t_send
        assert got == [f12], "node 2 got %r" % got
        print("1 -> 2: 80-byte frame delivered in %.1f ms" % (latency * 1e3))

        f21 = bytes([2, 1]) + payload(40)
        c2.sendall(f21 + TERM)
        got = recv_frames(c1, 1, 10)
        assert got == [f21], "node 1 got %r" % got
        print("2 -> 1: delivered")

        fb = bytes([1, 255]) + payload(20)
        c1.sendall(fb + TERM)
        got = recv_frames(c2, 1, 10)
        assert got == [fb], "node 2 got %r" % got
        print("1 -> 255: delivered to node 2")

        f13 = bytes([1, 3]) + payload(30)
        marker = bytes([1, 2]) + b"marker"
        c1.sendall(f13 + TERM)
        c1.sendall(marker + TERM)
        got = recv_frames(c2, 1, 10)
        assert got == [marker], "node 2 got %r" % got
        print("1 -> 3: not delivered to node 2's agent; the frame behind it was")
        # Back-to-back frames in one TCP write: five bursts queued at once.
        train = [bytes([1, 2]) + bytes([i]) + payload(60) for i in range(5)]
        c1.sendall(b"".join(f + TERM for f in train))
        got = recv_frames(c2, 5, 10)
        assert got == train, "node 2 got %d of 5 back-to-back frames" % len(got)
        print("1 -> 2: 5 back-to-back frames delivered in order")

        # Node 1's agent heard nothing: not its own broadcast, nothing else.
        got = recv_frames(c1, 1, 0.5)
        assert got == [], "node 1 got %r" % got
        assert channel.error is None, channel.error

        virtual = channel.ticks * B / FS
        wall = time.monotonic() - channel.t0
        # The Python fake is the bottleneck; "late" ticks mean it ran slower
        # than real time, not that the nodes did.
        print("fake emulator: %d ticks = %.2f s virtual in %.2f s wall (%.0f ticks/s), %d late, "
              "tx samples %s" % (channel.ticks, virtual, wall, channel.ticks / wall,
                                 channel.late_ticks, channel.tx_samples))
        ok = True
    finally:
        if channel is not None:
            channel.stop_flag.set()
        for c in clients:
            c.close()
        for p in procs:
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
        for node, p in zip((1, 2), procs):
            try:
                rc = p.wait(timeout=15)
            except subprocess.TimeoutExpired:
                p.kill()
                rc = p.wait()
                ok = False
                print("node %d did not stop on SIGTERM" % node)
            if rc != 0:
                ok = False
                print("node %d exited with %d" % (node, rc))
        if channel is not None:
            # Its error, if any, now is the nodes leaving; earlier ones were checked.
            channel.join(5)
        emu.close()
        if not ok:
            for node, err in zip((1, 2), errfiles):
                err.seek(0)
                print("---- node %d stderr ----\n%s" % (node, err.read()[-4000:]))
                print("---- node %d stdout ----\n%s" % (node, "\n".join(logs.get(node, []))))
        for err in errfiles:
            err.close()
        shutil.rmtree(tmp, ignore_errors=True)
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
