"""Drives the real `rfsitl run` process over loopback TCP for integration tests.

Standard library only (Debian's /usr/bin/python3). Every emulator started here
binds 127.0.0.1, gets its own free port range, and is stopped (SIGINT, then
SIGKILL after a timeout) when its `with` block ends.
"""

import json
import os
import random
import select
import signal
import socket
import subprocess
import tempfile
import threading
import time

BIN = os.environ.get("RFSITL_BIN", "rfsitl")
TERMINATOR = b"\r\r\n\n"
LOSS_REASONS = ("below_sensitivity", "collision", "half_duplex", "decode_failure",
                "unknown_destination")


def _ports_free(ports):
    held = []
    try:
        for p in ports:
            s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            held.append(s)
            s.bind(("127.0.0.1", p))
        return True
    except OSError:
        return False
    finally:
        for s in held:
            s.close()


def pick_port_bases(node_ids):
    """A (net_base, loc_base) pair whose ports are all free now."""
    for _ in range(200):
        net_base = random.randrange(20000, 50000)
        loc_base = net_base + 3
        ports = [net_base + 10 * n for n in node_ids] + [loc_base + 10 * n for n in node_ids]
        if _ports_free(ports):
            return net_base, loc_base
    raise RuntimeError("no free port range found on 127.0.0.1")


def scenario_yaml(nodes, extra="", node_phy=None):
    """nodes: {id: (x, y, z) or None}, positions in local metres; node_phy:
    {id: {key: value}} per-node PHY settings."""
    lines = ["name: integration-test", "seed: 7", "nodes:"]
    for node_id, pos in nodes.items():
        lines.append(f"  - id: {node_id}")
        if pos is not None:
            lines.append(f"    position: {{x: {pos[0]}, y: {pos[1]}, z: {pos[2]}}}")
        if node_phy and node_id in node_phy:
            fields = ", ".join(f"{k}: {v}" for k, v in node_phy[node_id].items())
            lines.append(f"    phy: {{{fields}}}")
    return "\n".join(lines) + "\n" + extra


class Emulator:
    """`with Emulator({1: (0, 0, 10), 2: (5, 0, 10)}) as emu:` runs rfsitl."""

    def __init__(self, nodes, extra_yaml="", args=(), ready_timeout=60.0, node_phy=None):
        self.nodes = nodes
        self.net_base, self.loc_base = pick_port_bases(list(nodes))
        self.dir = tempfile.TemporaryDirectory(prefix="rfsitl-it-")
        self.scenario = os.path.join(self.dir.name, "scenario.yaml")
        with open(self.scenario, "w") as f:
            f.write(scenario_yaml(nodes, extra_yaml, node_phy))
        self.summary_path = os.path.join(self.dir.name, "summary.json")
        self.args = [BIN, "run", self.scenario, "--net-base", str(self.net_base),
                     "--loc-base", str(self.loc_base), "--stats-interval", "0",
                     "--summary-json", self.summary_path, *args]
        self.ready_timeout = ready_timeout
        self.output = []
        self.proc = None
        self.summary = None
        self._clients = []

    def net_port(self, node_id):
        return self.net_base + 10 * node_id

    def loc_port(self, node_id):
        return self.loc_base + 10 * node_id

    def __enter__(self):
        self.proc = subprocess.Popen(self.args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     text=True)
        ready = threading.Event()

        def pump():
            for line in self.proc.stdout:
                self.output.append(line)
                if "rfsitl: ready" in line:
                    ready.set()
            ready.set()

        self._reader = threading.Thread(target=pump, daemon=True)
        self._reader.start()
        if not ready.wait(self.ready_timeout) or self.proc.poll() is not None:
            self._kill()
            raise RuntimeError("emulator did not become ready:\n" + "".join(self.output))
        return self

    def __exit__(self, *exc):
        for c in self._clients:
            c.close()
        self.stop()
        self.dir.cleanup()
        return False

    def _kill(self):
        if self.proc and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(10)

    def stop(self):
        """SIGINT, wait for the clean shutdown, and load the summary JSON."""
        if self.proc is None or self.summary is not None:
            return self.summary
        self.proc.send_signal(signal.SIGINT)
        try:
            rc = self.proc.wait(60)
        except subprocess.TimeoutExpired:
            self._kill()
            raise AssertionError("emulator did not stop within 60 s of SIGINT")
        self._reader.join(10)
        if rc != 0:
            raise AssertionError(f"emulator exited with {rc}:\n" + "".join(self.output))
        with open(self.summary_path) as f:
            self.summary = json.load(f)
        return self.summary

    def agent(self, node_id):
        c = NetClient(self.net_port(node_id))
        self._clients.append(c)
        return c

    def feed(self, node_id):
        c = LocationFeed(self.loc_port(node_id))
        self._clients.append(c)
        return c

    def node(self, node_id):
        """Counters of one node from the summary (after stop())."""
        for n in self.summary["nodes"]:
            if n["id"] == node_id:
                return n
        raise KeyError(node_id)


def connect(port, timeout=10.0):
    deadline = time.monotonic() + timeout
    while True:
        try:
            s = socket.create_connection(("127.0.0.1", port), timeout=5)
            s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            return s
        except OSError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.05)


class NetClient:
    """An agent on a net port speaking UB-ANC framing."""

    def __init__(self, port):
        self.sock = connect(port)
        self.buf = b""

    def close(self):
        self.sock.close()

    def send(self, src, dst, payload):
        self.sock.sendall(bytes([src, dst]) + payload + TERMINATOR)

    def send_raw(self, data):
        self.sock.sendall(data)

    def receive(self, count=1, timeout=2.0):
        """Up to `count` frames as (src, dst, payload), waiting at most `timeout` s."""
        frames = []
        deadline = time.monotonic() + timeout
        while len(frames) < count:
            while TERMINATOR in self.buf and len(frames) < count:
                raw, self.buf = self.buf.split(TERMINATOR, 1)
                frames.append((raw[0], raw[1], raw[2:]))
            if len(frames) >= count:
                break
            left = deadline - time.monotonic()
            if left <= 0:
                break
            readable, _, _ = select.select([self.sock], [], [], left)
            if readable:
                chunk = self.sock.recv(65536)
                if not chunk:
                    break
                self.buf += chunk
        return frames


class LocationFeed:
    """A location feed: one position per line."""

    def __init__(self, port):
        self.sock = connect(port)

    def close(self):
        self.sock.close()

    def send_line(self, line):
        self.sock.sendall(line.encode() + b"\n")

    def move_local(self, x, y, z):
        self.send_line(json.dumps({"x": x, "y": y, "z": z}))


def lost_total(node):
    return sum(node["lost"][r] for r in LOSS_REASONS)


def assert_accounted(test, summary):
    """Every frame handed in ended in exactly one place, nothing pending."""
    for n in summary["nodes"]:
        outcomes = n["delivered"] + lost_total(n) + n["queue_dropped"]
        test.assertEqual(n["pending"], 0, f"node {n['id']} still has pending frames: {n}")
        test.assertEqual(n["handed_in"], outcomes, f"node {n['id']} books do not balance: {n}")
