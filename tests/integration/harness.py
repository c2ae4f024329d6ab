"""Drives the real `rfsitl run` process over loopback TCP for integration tests.

Standard library only (Debian's /usr/bin/python3). Every emulator started here
binds 127.0.0.1, gets its own free port range, and is stopped (SIGINT, then
SIGKILL after a timeout) when its `with` block ends.
"""

import json
import os
import random
import re
import select
import signal
import socket
import subprocess
import tempfile
import threading
import time

import yaml

BIN = os.environ.get("RFSITL_BIN", "rfsitl")
TERMINATOR = b"\r\r\n\n"
LOSS_REASONS = ("below_sensitivity", "collision", "half_duplex", "decode_failure",
                "unknown_destination", "retry_limit")


def ports_free(ports):
    """True when every one of `ports` can be bound on 127.0.0.1 now."""
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
        if ports_free(ports):
            return net_base, loc_base
    raise RuntimeError("no free port range found on 127.0.0.1")


def run_batch(folder, name, text, args=(), timeout=240):
    """Writes scenario `text` to folder/name.yaml, runs it to its end (a
    virtual-time batch run) on free ports without a dashboard, and returns its
    summary JSON as a dict; a failing run raises with its output's tail."""
    path = os.path.join(folder, f"{name}.yaml")
    with open(path, "w") as f:
        f.write(text)
    ids = [n["id"] for n in yaml.safe_load(text)["nodes"]]
    net_base, loc_base = pick_port_bases(ids)
    summary = os.path.join(folder, f"{name}.json")
    r = subprocess.run([BIN, "run", path, "--net-base", str(net_base), "--loc-base",
                        str(loc_base), "--no-dashboard", "--summary-json", summary, *args],
                       capture_output=True, text=True, timeout=timeout)
    if r.returncode != 0:
        raise AssertionError(f"{name}: exit {r.returncode}\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
    with open(summary) as f:
        return json.load(f)


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


# For real-time tests with programs in other processes (children, flowgraphs):
# every tick is a round trip to each of them, and on a loaded machine each one
# waits for the scheduler. 4000-sample ticks at a tenth of real time are 25
# round trips per wall second, 160 times fewer than the defaults (250 samples
# at full speed). With 1000-sample ticks at half speed (500 a second) these
# runs fell further and further behind under `stress-ng --cpu 6` on 2 cores,
# beyond any deadline.
LOAD_TOLERANT_TICK = 4000
LOAD_TOLERANT = ["--tick", str(LOAD_TOLERANT_TICK), "--speed", "0.1"]

# How long a test waits for something it expects to happen (a frame, a count,
# a log line). A loaded machine runs the emulator behind the wall clock, so
# only a generous deadline is safe; a wait ends as soon as its condition
# holds, so it costs nothing on an idle machine. (Waits for something that
# must NOT happen stay short: lag can only make them pass, never fail.)
ARRIVAL_S = 30.0


class Emulator:
    """`with Emulator({1: (0, 0, 10), 2: (5, 0, 10)}) as emu:` runs rfsitl."""

    def __init__(self, nodes, extra_yaml="", args=(), ready_timeout=60.0, node_phy=None,
                 ready_marker="rfsitl: ready"):
        self.ready_marker = ready_marker
        self.nodes = nodes
        self.net_base, self.loc_base = pick_port_bases(list(nodes))
        self.dir = tempfile.TemporaryDirectory(prefix="rfsitl-it-")
        self.scenario = os.path.join(self.dir.name, "scenario.yaml")
        with open(self.scenario, "w") as f:
            f.write(scenario_yaml(nodes, extra_yaml, node_phy))
        self.summary_path = os.path.join(self.dir.name, "summary.json")
        # Any free dashboard port: on the default 15700 a poller of an earlier
        # run (another test, or a run beside this suite) could reach this one.
        dashboard = [] if "--dashboard-port" in args or "--no-dashboard" in args else [
            "--dashboard-port", "0"]
        self.args = [BIN, "run", self.scenario, "--net-base", str(self.net_base),
                     "--loc-base", str(self.loc_base), "--stats-interval", "0",
                     "--summary-json", self.summary_path, *dashboard, *args]
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
                if self.ready_marker in line:
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
        self.proc.stdout.close()
        if rc != 0:
            raise AssertionError(f"emulator exited with {rc}:\n" + "".join(self.output))
        with open(self.summary_path) as f:
            self.summary = json.load(f)
        return self.summary

    def agent(self, node_id):
        c = NetClient(self.net_port(node_id))
        self._clients.append(c)
        return c

    def agent_connected(self, node_id):
        """Asks node_id's net port (on a connection of its own) whether an agent holds it."""
        c = NetClient(self.net_port(node_id))
        try:
            reply = c.control("rfsitl status")
        finally:
            c.close()
        m = re.search(r"agent=(\d)", reply)
        assert m, reply
        return m.group(1) == "1"

    def wait_for_agent(self, node_id, timeout=ARRIVAL_S):
        """Waits until node_id's net port has admitted an agent."""
        deadline = time.monotonic() + timeout
        while not self.agent_connected(node_id):
            if time.monotonic() > deadline:
                raise AssertionError(f"no agent on node {node_id}'s net port")
            time.sleep(0.02)

    def feed(self, node_id):
        c = LocationFeed(self.loc_port(node_id))
        self._clients.append(c)
        return c

    def dashboard_port(self):
        """The port the running emulator's dashboard serves."""
        m = re.search(r"rfsitl: dashboard http://[^/]*:(\d+)/", "".join(self.output))
        if not m:
            raise AssertionError("the emulator printed no dashboard URL")
        return int(m.group(1))

    def stats(self):
        """The running emulator's /api/stats (its dashboard must be on)."""
        import re
        import urllib.request
        m = re.search(r"rfsitl: dashboard (http://\S+/)", "".join(self.output))
        if not m:
            raise AssertionError("the emulator printed no dashboard URL")
        with urllib.request.urlopen(m.group(1) + "api/stats", timeout=5) as r:
            return json.load(r)

    def wait_until(self, predicate, timeout=ARRIVAL_S, what="condition"):
        """Polls stats() until predicate(stats) holds."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            st = self.stats()
            if predicate(st):
                return st
            time.sleep(0.02)
        raise AssertionError(f"timed out waiting for {what}: {self.stats()}")

    def wait_settled(self, timeout=ARRIVAL_S):
        """Waits until no node has a frame in flight (every node's pending is 0).
        Before stop() when the books are checked afterwards: a run behind the
        wall clock may not yet have given the last frames their outcome, and
        stop() ends the run where it is."""
        return self.wait_until(lambda st: all(n["pending"] == 0 for n in st["nodes"]),
                               timeout, "every frame's outcome")

    def node(self, node_id):
        """Counters of one node from the summary (after stop())."""
        for n in self.summary["nodes"]:
            if n["id"] == node_id:
                return n
        raise KeyError(node_id)


def without_ubsan_vptr_checks(emu):
    """For runs that exhaust file descriptors: UBSan checks a dynamic type it has
    not yet cached (or has evicted from its small cache) by reading the object's
    memory through a pipe(), which fails when every descriptor is taken, and it
    then reports a false "invalid vptr" at an arbitrary call. This turns off that
    one check for `emu` (call before starting it); every other check stays on."""
    suppressions = os.path.join(emu.dir.name, "ubsan.supp")
    with open(suppressions, "w") as f:
        f.write("vptr:*\nvptr_check:*\n")  # by report location, and by dynamic type
    ubsan = ":".join(filter(None, [os.environ.get("UBSAN_OPTIONS"),
                                   f"suppressions={suppressions}"]))
    emu.args = ["env", f"UBSAN_OPTIONS={ubsan}", *emu.args]
    return emu


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

    def control(self, request, timeout=10.0):
        """Sends a control frame (src = dst = 0) and returns the reply's text."""
        self.send(0, 0, request.encode())
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for src, dst, payload in self.receive(1, timeout=deadline - time.monotonic()):
                if src == 0 and dst == 0:
                    return payload.decode()
        raise AssertionError(f"no reply to control request {request!r}")

    def closed_by_peer(self, timeout=ARRIVAL_S):
        """True when the emulator closes this connection within `timeout` s."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            readable, _, _ = select.select([self.sock], [], [], deadline - time.monotonic())
            if readable:
                try:
                    chunk = self.sock.recv(65536)
                except ConnectionResetError:
                    return True
                if not chunk:
                    return True
                self.buf += chunk
        return False

    def receive(self, count=1, timeout=ARRIVAL_S):
        """Up to `count` frames as (src, dst, payload), waiting at most `timeout` s
        (give a short one where nothing should arrive)."""
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


# --- external transceivers (include/rfsitl/external/client/wire_protocol.hpp) -------------

MSG_HEADER = "<IHHQQII"  # magic, type, flags, tick, time, count, extra_bytes
MAGIC = 0x58534652
MSG_HELLO, MSG_WELCOME, MSG_REJECT, MSG_TICK, MSG_TX = 1, 2, 3, 4, 5


class ExternalSamplesNode:
    """A program in the "samples" role written from the protocol description:
    joins as node `node_id`, then answers each tick with what `tx_for(tick)`
    returns (packed cf32 bytes, see pack_samples; at most B samples). Records the received power
    of every tick. `answer=False` stops answering (a hung process)."""

    def __init__(self, socket_path, node_id, tx_for=None):
        import struct
        self.struct = struct
        self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        deadline = time.monotonic() + 10
        while True:
            try:
                self.sock.connect(socket_path)
                break
            except OSError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.05)
        hello = json.dumps({"node_id": node_id, "role": "samples",
                            "program": "harness.py"}).encode()
        self._send(MSG_HELLO, 0, 0, b"", hello)
        mtype, _, _, _, _, extra = self._recv(5.0)
        if mtype != MSG_WELCOME:
            raise RuntimeError("not welcomed: " + extra.decode(errors="replace"))
        self.welcome = json.loads(extra)
        self.tx_for = tx_for or (lambda tick: b"")
        self.answer = True
        self.ticks = 0
        self.rx_power = []  # (tick, mean |y|^2) of every tick with samples
        self.discontinuities = 0
        self.closed = False
        self._stop = False
        self._thread = threading.Thread(target=self._loop, daemon=True)
        self._thread.start()

    def _send(self, mtype, tick, t, samples, extra):
        h = self.struct.pack(MSG_HEADER, MAGIC, mtype, 0, tick, t, len(samples) // 8, len(extra))
        self.sock.send(h + samples + extra)

    def _recv(self, timeout):
        self.sock.settimeout(timeout)
        data = self.sock.recv(256 * 1024)
        if not data:
            raise ConnectionError("emulator closed the connection")
        magic, mtype, flags, tick, t, count, extra_len = self.struct.unpack_from(MSG_HEADER, data)
        assert magic == MAGIC
        samples = data[32:32 + 8 * count]
        return mtype, flags, tick, t, samples, data[32 + 8 * count:]

    def _loop(self):
        last = None
        try:
            while not self._stop:
                try:
                    mtype, _, tick, t, samples, _ = self._recv(0.2)
                except socket.timeout:
                    continue
                if mtype != MSG_TICK:
                    raise RuntimeError(f"unexpected message type {mtype}")
                if last is not None and tick != last + 1:
                    self.discontinuities += 1
                last = tick
                if samples:
                    vals = self.struct.unpack(f"<{len(samples) // 4}f", samples)
                    power = sum(v * v for v in vals) / (len(vals) / 2)
                    self.rx_power.append((tick, power))
                if not self.answer:
                    continue
                self._send(MSG_TX, tick, t, self.tx_for(tick), b"")
                self.ticks += 1
        except (ConnectionError, OSError):
            pass
        self.closed = True

    def close(self):
        self._stop = True
        self._thread.join(5)
        self.sock.close()


def pack_samples(samples):
    """Complex samples as the protocol's cf32 little-endian bytes."""
    import struct
    flat = []
    for z in samples:
        flat += [z.real, z.imag]
    return struct.pack(f"<{len(flat)}f", *flat)


def child_pid(socket_path, node_id):
    """Process id of the `rfsitl node` child serving node_id, or None."""
    want = ["node", "--socket", socket_path, "--id", str(node_id)]
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                args = f.read().decode(errors="replace").split("\0")
        except OSError:
            continue
        if args[1:6] == want:
            return int(pid)
    return None


SOURCE_DIR = os.environ.get("RFSITL_SOURCE_DIR",
                            os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
GMSK_NODE = os.path.join(SOURCE_DIR, "examples", "gnuradio", "gmsk_node.py")


class GnuRadioNode:
    """examples/gnuradio/gmsk_node.py as a node of a running emulator (the
    GNU Radio flowgraph with our source and sink, serving its own net port)."""

    def __init__(self, emu, node_id):
        self.emu = emu
        self.node_id = node_id
        self.proc = None
        self.output = []

    def start(self):
        sock = f"/tmp/rfsitl-{self.emu.net_base}.sock"
        self.proc = subprocess.Popen(
            ["/usr/bin/python3", "-u", GMSK_NODE, "--socket", sock, "--id", str(self.node_id),
             "--net-base", str(self.emu.net_base), "--reconnect-ms", "5000"],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        ready = threading.Event()

        def pump():
            for line in self.proc.stdout:
                self.output.append(line)
                if "ready, net port" in line:
                    ready.set()
            ready.set()

        threading.Thread(target=pump, daemon=True).start()
        if not ready.wait(60) or self.proc.poll() is not None:
            self.kill()
            raise RuntimeError(f"GNU Radio node {self.node_id} did not start:\n"
                               + "".join(self.output))
        return self

    def kill(self):
        if self.proc and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(10)

    def stop(self):
        if self.proc and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(15)
            except subprocess.TimeoutExpired:
                self.kill()
        if self.proc and self.proc.stdout:
            self.proc.stdout.close()


def wait_for_output(emu, text, timeout=60.0):
    """Waits until the emulator has printed a line containing `text`."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if any(text in line for line in emu.output):
            return True
        time.sleep(0.05)
    return False
