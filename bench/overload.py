#!/usr/bin/python3
"""Bounded under overload: the emulator's memory under a flood, against a ceiling
computed from its configured queue bounds.

    /usr/bin/python3 bench/overload.py [--bin build/release/apps/rfsitl] [--duration 60]
        [--nodes 64] [--idle 500] [--viewers 4] [--rate 200] [--csv out/bench/overload.csv]

`rfsitl run --nodes N` (real time, loopback) gets:
  * one agent per node that floods frames of the largest payload to the next
    node (--rate frames per second each, several times what the air carries),
    and reads what it is delivered;
  * --idle connections that never send anything, a third each on net ports
    (waiting behind the agents), location ports and the dashboard;
  * --viewers dashboard WebSocket viewers watching a node: half read 2 KiB
    every 0.5 s, half never read.
It samples the emulator's VmRSS and VmHWM (/proc/PID/status) every 0.5 s and
prints the peak, the RSS 10 s into the flood and at its end, the frames offered,
delivered and dropped by reason, and the ceiling:

    peak RSS <= baseline RSS + sum of the terms (each printed with its formula)

The baseline is the emulator's RSS once every agent is connected and has sent
a few frames of the largest payload (so that per-node frame buffers exist)
and the engine is idle again, before any other connection. The terms are the
bounds that limit what a flood, idle connections and slow viewers can make it
hold: TX queues, the to-agent write backlog, per-connection read buffers and
parsers, HTTP request limits and viewer queues (values as in the source tree,
checked against it when it is there). After the flood it stops sending, waits
until the emulator has taken every frame offered (handed_in = frames the agents
wrote) and resolved them all (pending 0), stops it with SIGINT and checks the
books of its --summary-json: handed_in = delivered + lost + queue_dropped per
node. Exit status 0 when the ceiling holds and the books balance, 1 otherwise.
Standard library only; binds and connects 127.0.0.1; the emulator is always
stopped.
"""

import argparse
import csv
import json
import os
import re
import resource
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests",
                                "integration"))
from ws_client import WsClient  # noqa: E402 (after the path)

TERMINATOR = b"\r\r\n\n"
LOSS_REASONS = ("below_sensitivity", "collision", "half_duplex", "decode_failure",
                "unknown_destination", "retry_limit")
KIB = 1024
MIB = 1024 * 1024
SOURCE_DIR = os.environ.get("RFSITL_SOURCE_DIR",
                            os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


# ---- the configured bounds -----------------------------------------------------------

class Bound:
    """A bound the ceiling uses: its value as assumed here and where it is set;
    `patterns` find it in the source tree (first group: the value's C++ text)."""

    def __init__(self, name, value, where, patterns):
        self.name, self.value, self.where, self.patterns = name, value, where, patterns
        self.checked = "not checked (no source tree)"


BOUNDS = {
    "tx_queue_frames": Bound(
        "TX queue per node (phy.tx_queue_frames default), frames", 64,
        "include/rfsitl/scenario/scenario.hpp",
        [r"tx_queue_frames\s*=\s*(\d+)"]),
    "write_backlog": Bound(
        "to-agent write backlog per net connection (kMaxWriteBacklogBytes), bytes", 4 * MIB,
        "src/agent_port/net_ports.cpp",
        [r"kMaxWriteBacklogBytes\s*=\s*([\d\s*]+);"]),
    "read_chunk": Bound(
        "read buffer per net or location connection, bytes", 64 * KIB,
        "include/rfsitl/io/port_session.hpp",
        [r"buf_\s*=\s*std::vector<std::uint8_t>\(([\d\s*]+)\)", r"kReadChunk\s*=\s*([\d\s*]+);"]),
    "location_line": Bound(
        "location line buffer per location connection (kMaxLocationLine), bytes", 4096,
        "include/rfsitl/position/location_port/location_port_source.hpp",
        [r"kMaxLocationLine\s*=\s*([\d\s*]+);"]),
    "viewer_queue": Bound(
        "messages queued per viewer (ViewerQueue::kCapacity)", 16,
        "include/rfsitl/monitor/viewer_queue.hpp",
        [r"kCapacity\s*=\s*([\d\s*]+);"]),
    "request_bytes": Bound(
        "dashboard request body / viewer message limit (kMaxRequestBytes), bytes", 64 * KIB,
        "src/monitor/dashboard_server.cpp",
        [r"kMaxRequestBytes\s*=\s*([\d\s*]+);"]),
    "http_header": Bound(
        "dashboard request header limit (Boost.Beast's default header_limit), bytes", 8 * KIB,
        "Boost.Beast http::basic_parser", []),
    "candidates": Bound(
        "connections waiting per port beyond the agent (PortSlot::kMaxCandidates)", 8,
        "include/rfsitl/io/port_slot.hpp",
        [r"kMaxCandidates\s*=\s*(\d+);"]),
}
# Not configured bounds but allowances, stated as such: what one accepted
# connection costs besides its buffers (socket, session object, shared_ptr
# control block, Asio's per-socket state, allocator headers), and the
# bookkeeping of one queued frame besides its payload (QueuedFrame, vector
# header, allocator header).
CONNECTION_ALLOWANCE = 4 * KIB
FRAME_ALLOWANCE = 64
NET_FRAME_STRUCT = 32  # sizeof(NetFrame) on x86-64: src, dst, std::vector
MIN_FRAME_BYTES = 6    # 2 header bytes + 4 terminator bytes: the most frames per read chunk


def check_bounds():
    """Compares every bound with the source tree; a changed value wins, and is said."""
    src = [os.path.join(SOURCE_DIR, d) for d in ("src", "include")]
    if not all(os.path.isdir(d) for d in src):
        return
    texts = {}
    for d in src:
        for root, _, files in os.walk(d):
            for f in files:
                if f.endswith((".cpp", ".hpp")):
                    p = os.path.join(root, f)
                    with open(p, errors="replace") as fh:
                        texts[os.path.relpath(p, SOURCE_DIR)] = fh.read()
    for b in BOUNDS.values():
        if not b.patterns:
            b.checked = "library default"
            continue
        found = None
        # The file named first, then anywhere (code moves).
        for path in [b.where] + sorted(texts):
            text = texts.get(path, "")
            for pat in b.patterns:
                m = re.search(pat, text)
                if m and re.fullmatch(r"[\d\s*]+", m.group(1)):
                    value = 1
                    for factor in m.group(1).split("*"):
                        value *= int(factor)
                    found = (path, value)
                    break
            if found:
                break
        if not found:
            b.checked = "NOT FOUND in the source tree: value assumed"
        elif found[1] != b.value:
            b.checked = f"source says {found[1]} ({found[0]}): using it"
            b.value, b.where = found[1], found[0]
        else:
            b.checked = f"checked in {found[0]}"
            b.where = found[0]


# ---- the emulator ----------------------------------------------------------------------

def read_status(pid):
    out = {}
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                k, _, v = line.partition(":")
                if k in ("VmRSS", "VmHWM"):
                    out[k] = int(v.split()[0]) * KIB
    except OSError:
        pass
    return out


def is_asan(binary):
    with open(binary, "rb") as f:
        tail = b""
        while True:
            chunk = f.read(8 * MIB)
            if not chunk:
                return False
            if b"__asan_init" in tail + chunk:
                return True
            tail = chunk[-16:]


def max_payload(binary):
    out = subprocess.run([binary, "describe", "phy", "gmsk"], capture_output=True, text=True,
                         timeout=60).stdout
    m = re.search(r"`max_payload_bytes` \| integer \| bytes \| `(\d+)`", out)
    if not m:
        raise RuntimeError("cannot read gmsk's max_payload_bytes from `rfsitl describe phy gmsk`")
    return int(m.group(1))


class Emulator:
    def __init__(self, args, summary_path, env):
        self.cmd = [args.bin, "run", "--nodes", str(args.nodes), "--net-base", str(args.net_base),
                    "--loc-base", str(args.loc_base), "--dashboard-port", str(args.dashboard_port),
                    "--bind", "127.0.0.1", "--stats-interval", "5", "--summary-json",
                    summary_path]
        self.proc = subprocess.Popen(self.cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     text=True, env=env)
        self.lines = []
        self.ready = threading.Event()
        self.reader = threading.Thread(target=self._pump, daemon=True)
        self.reader.start()

    def _pump(self):
        for line in self.proc.stdout:
            self.lines.append(line)
            if "rfsitl: ready" in line:
                self.ready.set()
        self.ready.set()

    def stop(self, timeout=60):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(timeout)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(10)
                raise RuntimeError(f"the emulator ignored SIGINT for {timeout} s; killed")
        self.reader.join(10)
        return self.proc.returncode

    def kill(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(10)


def api_stats(port):
    req = urllib.request.Request(f"http://127.0.0.1:{port}/api/stats")
    with urllib.request.urlopen(req, timeout=10) as r:
        return json.load(r)


def wait_stats(port, predicate, timeout, what):
    deadline = time.monotonic() + timeout
    last = None
    while time.monotonic() < deadline:
        try:
            last = api_stats(port)
            if predicate(last):
                return last
        except OSError:
            pass
        time.sleep(0.2)
    raise RuntimeError(f"timed out after {timeout} s waiting for {what}; last stats: "
                       + json.dumps(totals(last) if last else None))


def totals(stats):
    t = {k: 0 for k in ("handed_in", "delivered", "queue_dropped", "pending", "received",
                        "to_agent_dropped", "framing_errors", "transmitted")}
    t["lost"] = {r: 0 for r in LOSS_REASONS}
    for n in stats["nodes"]:
        for k in t:
            if k != "lost":
                t[k] += n.get(k, 0)
        for r in LOSS_REASONS:
            t["lost"][r] += n["lost"][r]
    return t


# ---- the load ----------------------------------------------------------------------

class Flooder:
    """Node `src`'s agent: sends frames to `dst` at `rate` per second and reads
    (and counts) every frame delivered to it."""

    def __init__(self, port, src, dst, payload):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=10)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.sock.setblocking(False)
        self.frame = bytes([src, dst]) + payload + TERMINATOR
        self.out = bytearray()
        self.offered = 0       # frames put in `out` (all written by the end)
        self.received = 0      # frames delivered to this agent
        self.credit = 0.0
        self._tail = b""

    def queue(self, frames):
        self.out += self.frame * frames
        self.offered += frames

    def pump(self):
        if self.out:
            try:
                n = self.sock.send(self.out)
                del self.out[:n]
            except BlockingIOError:
                pass
        while True:
            try:
                chunk = self.sock.recv(256 * KIB)
            except BlockingIOError:
                return
            if not chunk:
                raise ConnectionError("the emulator closed an agent's connection")
            # A terminator split across reads is counted once, by the read that
            # completes it (the last 3 bytes of a complete one never start another).
            data = self._tail + chunk
            self.received += data.count(TERMINATOR)
            self._tail = data[-3:]


class Viewer:
    """A dashboard WebSocket viewer that watches `node`; reads `read_bytes` per
    `pump()` (0: never reads). Its receive buffer is small so that the server's
    queue, not the kernel, holds what it does not read."""

    def __init__(self, port, node, read_bytes):
        ws = WsClient("127.0.0.1", port, rcvbuf=4096)
        ws.send({"type": "watch", "node": node})
        self.sock = ws.sock
        self.sock.setblocking(False)
        self.read_bytes = read_bytes
        self.bytes = 0

    def pump(self):
        if self.read_bytes <= 0:
            return
        try:
            chunk = self.sock.recv(self.read_bytes)
            if not chunk:
                raise ConnectionError("the dashboard closed a viewer")
            self.bytes += len(chunk)
        except BlockingIOError:
            pass


def write_out(flooders, failure):
    """Pumps until every flooder has written what it queued; RuntimeError
    `failure` after 60 s."""
    deadline = time.monotonic() + 60
    while any(f.out for f in flooders):
        for f in flooders:
            f.pump()
        if time.monotonic() > deadline:
            raise RuntimeError(failure)
        time.sleep(0.005)


def closed_by_peer(sock):
    """True when the emulator closed this idle connection."""
    sock.setblocking(False)
    try:
        return sock.recv(1) == b""
    except BlockingIOError:
        return False
    except OSError:
        return True


class Sampler(threading.Thread):
    """VmRSS and VmHWM of `pid` every `period` s: (monotonic time, rss, hwm)."""

    def __init__(self, pid, period=0.5):
        super().__init__(daemon=True)
        self.pid, self.period = pid, period
        self.samples = []
        self.halt = threading.Event()

    def run(self):
        while not self.halt.is_set():
            s = read_status(self.pid)
            if s:
                self.samples.append((time.monotonic(), s["VmRSS"], s["VmHWM"]))
            self.halt.wait(self.period)

    def rss_at(self, t):
        near = min(self.samples, key=lambda s: abs(s[0] - t))
        return near[1]


# ---- the ceiling -------------------------------------------------------------------

def ceiling_terms(n, payload_max, c_net, c_loc, c_dash, viewers, message_max, asan):
    b = {k: v.value for k, v in BOUNDS.items()}
    frame = payload_max + 2 + len(TERMINATOR)
    conns = c_net + c_loc + c_dash + viewers
    terms = [
        ("TX queues", "N x tx_queue_frames x (max_payload + frame allowance)",
         f"{n} x {b['tx_queue_frames']} x ({payload_max} + {FRAME_ALLOWANCE})",
         n * b["tx_queue_frames"] * (payload_max + FRAME_ALLOWANCE)),
        ("to-agent backlogs", "N x (write backlog + one frame)",
         f"{n} x ({b['write_backlog']} + {frame})", n * (b["write_backlog"] + frame)),
        ("net connections", "C_net x (read buffer + parser (max frame) + parsed frames "
         "(read buffer / 6 x sizeof NetFrame))",
         f"{c_net} x ({b['read_chunk']} + {frame} + {b['read_chunk']} / {MIN_FRAME_BYTES} x "
         f"{NET_FRAME_STRUCT})",
         c_net * (b["read_chunk"] + frame
                  + b["read_chunk"] // MIN_FRAME_BYTES * NET_FRAME_STRUCT)),
        ("location connections", "C_loc x (read buffer + location line)",
         f"{c_loc} x ({b['read_chunk']} + {b['location_line']})",
         c_loc * (b["read_chunk"] + b["location_line"])),
        ("dashboard HTTP connections", "C_dash x (header limit + body limit)",
         f"{c_dash} x ({b['http_header']} + {b['request_bytes']})",
         c_dash * (b["http_header"] + b["request_bytes"])),
        ("dashboard viewers", "V x ((queue capacity + hello + snapshot) x largest message "
         "+ incoming message limit)",
         f"{viewers} x (({b['viewer_queue']} + 2) x {message_max} + {b['request_bytes']})",
         viewers * ((b["viewer_queue"] + 2) * message_max + b["request_bytes"])),
        ("per-connection allowance", "all connections x allowance (not a configured bound)",
         f"{conns} x {CONNECTION_ALLOWANCE}", conns * CONNECTION_ALLOWANCE),
    ]
    if asan:
        heap = sum(t[3] for t in terms)
        terms.append(("ASan redzones and shadow", "the terms above once more (x2 in all)",
                      f"{heap}", heap))
        terms.append(("ASan quarantine", "quarantine_size_mb (set by this benchmark)",
                      f"{ASAN_QUARANTINE_MB} MiB", ASAN_QUARANTINE_MB * MIB))
    return terms


ASAN_QUARANTINE_MB = 32


def mb(v):
    return f"{v / MIB:.1f} MB"


# ---- the run -----------------------------------------------------------------------

def ports_free(ports):
    for p in ports:
        s = socket.socket()
        # As the emulator binds: a port in TIME_WAIT from an earlier run is free.
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind(("127.0.0.1", p))
        except OSError:
            return p
        finally:
            s.close()
    return None


def run(args):
    check_bounds()
    asan = is_asan(args.bin)
    payload_max = max_payload(args.bin)
    payload_len = args.payload or payload_max
    payload = bytes(ord("A") + i % 26 for i in range(payload_len))
    n = args.nodes
    net_ports = [args.net_base + 10 * i for i in range(1, n + 1)]
    loc_ports = [args.loc_base + 10 * i for i in range(1, n + 1)]
    taken = ports_free(net_ports + loc_ports + [args.dashboard_port])
    if taken:
        raise RuntimeError(f"port {taken} on 127.0.0.1 is in use: choose other --net-base, "
                           "--loc-base or --dashboard-port")
    # Every connection is a descriptor here and in the emulator.
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    need = 4 * (n + args.idle + args.viewers) + 256
    if soft < need:
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(need, hard), hard))

    env = dict(os.environ)
    if asan:
        env["ASAN_OPTIONS"] = (env.get("ASAN_OPTIONS", "") +
                               f":quarantine_size_mb={ASAN_QUARANTINE_MB}").lstrip(":")
    tmp = tempfile.TemporaryDirectory(prefix="rfsitl-overload-")
    summary_path = os.path.join(tmp.name, "summary.json")
    emu = Emulator(args, summary_path, env)
    flooders, viewers, idle = [], [], {"net": [], "location": [], "dashboard": []}
    sampler = Sampler(emu.proc.pid)
    ok = True
    try:
        if not emu.ready.wait(120) or emu.proc.poll() is not None:
            raise RuntimeError("the emulator did not get ready:\n" + "".join(emu.lines[-20:]))
        sampler.start()
        print(f"overload: {args.bin} ({'ASan' if asan else 'no sanitizer'}), {n} nodes, "
              f"net base {args.net_base}, location base {args.loc_base}, dashboard port "
              f"{args.dashboard_port}", flush=True)

        # Warm-up: every agent connects and sends a few frames of the largest
        # payload, so that per-node frame buffers exist before the baseline.
        for i in range(1, n + 1):
            flooders.append(Flooder(args.net_base + 10 * i, i, i % n + 1, payload))
        for f in flooders:
            f.queue(args.warmup_frames)
        write_out(flooders, "the warm-up frames were not taken within 60 s")
        warm_offered = sum(f.offered for f in flooders)
        stop_pump = threading.Event()

        def pump_quietly():
            while not stop_pump.is_set():
                for f in flooders:
                    f.pump()
                time.sleep(0.02)

        drainer = threading.Thread(target=pump_quietly, daemon=True)
        drainer.start()
        wait_stats(args.dashboard_port,
                   lambda s: totals(s)["handed_in"] == warm_offered and totals(s)["pending"] == 0,
                   120, "the warm-up frames to be resolved")
        time.sleep(1.0)  # settle; then the baseline over one second
        t_b = time.monotonic()
        time.sleep(1.0)
        base_samples = sorted(s[1] for s in sampler.samples if s[0] >= t_b)
        baseline = base_samples[len(base_samples) // 2]
        stop_pump.set()
        drainer.join()

        # Idle connections: a third each on net ports (behind the agents),
        # location ports and the dashboard; then the viewers.
        k_net = args.idle // 3
        k_loc = args.idle // 3
        k_dash = args.idle - k_net - k_loc
        for j in range(k_net):
            idle["net"].append(socket.create_connection(("127.0.0.1", net_ports[j % n]), 10))
        for j in range(k_loc):
            idle["location"].append(socket.create_connection(("127.0.0.1", loc_ports[j % n]), 10))
        for _ in range(k_dash):
            idle["dashboard"].append(
                socket.create_connection(("127.0.0.1", args.dashboard_port), 10))
        for v in range(args.viewers):
            viewers.append(Viewer(args.dashboard_port, 1 + (v * 17) % n,
                                  2048 if v % 2 == 0 else 0))
        slow = sum(1 for v in viewers if v.read_bytes > 0)
        print(f"overload: {len(flooders)} flooding agents ({payload_len}-byte payloads, "
              f"{args.rate:g} frames/s each), idle connections: {k_net} net, {k_loc} location, "
              f"{k_dash} dashboard; {len(viewers)} viewers ({slow} read 2 KiB per 0.5 s, "
              f"{len(viewers) - slow} never read); baseline RSS {mb(baseline)}", flush=True)

        # The flood.
        t0 = time.monotonic()
        t_end = t0 + args.duration
        last, next_view, next_print = t0, t0, t0 + 10
        offered_before = sum(f.offered for f in flooders)
        cap = 256 * KIB  # what an agent keeps unsent at most (the emulator reads it all)
        while True:
            now = time.monotonic()
            if now >= t_end:
                break
            dt, last = now - last, now
            for f in flooders:
                f.credit += args.rate * dt
                k = int(f.credit)
                if k and len(f.out) < cap:
                    f.queue(k)
                f.credit -= k
                f.pump()
            if now >= next_view:
                for v in viewers:
                    v.pump()
                next_view = now + 0.5
            if now >= next_print:
                s = sampler.samples[-1] if sampler.samples else (0, 0, 0)
                print(f"overload: t={now - t0:4.0f} s  RSS {mb(s[1])}  offered "
                      f"{sum(f.offered for f in flooders) - offered_before}", flush=True)
                next_print += 10
            time.sleep(0.01)
        rss_end = sampler.samples[-1][1]
        rss_10 = sampler.rss_at(t0 + 10)
        flood_samples = [s for s in sampler.samples if s[0] >= t0]
        peak_sampled = max(s[1] for s in flood_samples)

        # Drain: write what is left, let the emulator take and resolve it.
        write_out(flooders, "the emulator stopped reading the agents' frames")
        offered = sum(f.offered for f in flooders)
        stop_pump.clear()
        drainer = threading.Thread(target=pump_quietly, daemon=True)
        drainer.start()
        stats = wait_stats(args.dashboard_port,
                           lambda s: totals(s)["handed_in"] + totals(s)["framing_errors"]
                           >= offered and totals(s)["pending"] == 0,
                           180, "every offered frame to be taken and resolved")
        message_max = 0
        with urllib.request.urlopen(f"http://127.0.0.1:{args.dashboard_port}/api/snapshot",
                                    timeout=10) as r:
            message_max = len(r.read())
        hwm = read_status(emu.proc.pid).get("VmHWM", 0)
        time.sleep(0.5)
        stop_pump.set()
        drainer.join()
        agents_read = sum(f.received for f in flooders)
        closed = {k: sum(closed_by_peer(s) for s in v) for k, v in idle.items()}
        sampler.halt.set()
        rc = emu.stop()
        if rc != 0:
            raise RuntimeError(f"the emulator exited with {rc}")
        with open(summary_path) as f:
            summary = json.load(f)
    finally:
        sampler.halt.set()
        for s in [f.sock for f in flooders] + [v.sock for v in viewers] + \
                [s for v in idle.values() for s in v]:
            s.close()
        emu.kill()
        log = "".join(emu.lines)
        if args.log:
            os.makedirs(os.path.dirname(args.log) or ".", exist_ok=True)
            with open(args.log, "w") as f:
                f.write(log)
        tmp.cleanup()

    # ---- report -----------------------------------------------------------------
    tot = totals(summary)
    lost = sum(tot["lost"].values())
    lag = re.search(r"worst real-time lag ([\d.]+) ms, late ticks (\d+)", log)
    virt = re.search(r"rfsitl summary: virtual ([\d.]+) s in ([\d.]+) s wall", log)
    print()
    print(f"memory: baseline RSS {mb(baseline)}; RSS 10 s into the flood {mb(rss_10)}, "
          f"at its end ({args.duration:g} s) {mb(rss_end)} (growth from 10 s to the end "
          f"{(rss_end - rss_10) / MIB:+.1f} MB); peak RSS sampled during the flood "
          f"{mb(peak_sampled)}, VmHWM (peak of the whole run) {mb(hwm)}")
    print(f"frames: offered {offered} (warm-up {warm_offered}), handed in {tot['handed_in']}, "
          f"transmitted {tot['transmitted']}, delivered {tot['delivered']}, lost {lost} ("
          + ", ".join(f"{r} {tot['lost'][r]}" for r in LOSS_REASONS)
          + f"), queue-dropped {tot['queue_dropped']}, framing errors {tot['framing_errors']}, "
          f"pending {tot['pending']}")
    print(f"        received by agents {tot['received']} (the agents read {agents_read}), "
          f"to-agent dropped {tot['to_agent_dropped']}")
    if virt and lag:
        print(f"real time: virtual {virt.group(1)} s in {virt.group(2)} s wall, worst lag "
              f"{lag.group(1)} ms, late ticks {lag.group(2)}")
    print(f"connections: the emulator closed {closed['dashboard']} of {k_dash} idle dashboard "
          f"connections (its 30 s request timeout), {closed['net']} of {k_net} idle net and "
          f"{closed['location']} of {k_loc} idle location connections; viewers read "
          f"{sum(v.bytes for v in viewers)} bytes; largest dashboard message (a snapshot with "
          f"the link matrix) {message_max} bytes")

    print("\nbounds (value, where, check):")
    for b in BOUNDS.values():
        print(f"  {b.name}: {b.value}  [{b.where}; {b.checked}]")
    print(f"  allowances (not configured bounds): {CONNECTION_ALLOWANCE} bytes per connection, "
          f"{FRAME_ALLOWANCE} bytes per queued frame; sizeof(NetFrame) {NET_FRAME_STRUCT}")
    terms = ceiling_terms(n, payload_max, k_net + n, k_loc, k_dash, len(viewers), message_max,
                          asan)
    ceiling = sum(t[3] for t in terms)
    print("\nceiling = " + " + ".join(t[0] for t in terms))
    for name, formula, numbers, value in terms:
        print(f"  {name}: {formula} = {numbers} = {mb(value)}")
    print(f"  total {mb(ceiling)}")

    checks = []
    peak = max(hwm, peak_sampled)
    checks.append((peak <= baseline + ceiling,
                   f"peak RSS {mb(peak)} <= baseline {mb(baseline)} + ceiling {mb(ceiling)} = "
                   f"{mb(baseline + ceiling)}"))
    checks.append((tot["handed_in"] + tot["framing_errors"] == offered,
                   f"every frame offered was taken: handed in {tot['handed_in']} + framing "
                   f"errors {tot['framing_errors']} = offered {offered}"))
    unbalanced = [nd["id"] for nd in summary["nodes"]
                  if nd["handed_in"] != nd["delivered"] + sum(nd["lost"].values())
                  + nd["queue_dropped"] or nd["pending"] != 0]
    checks.append((not unbalanced and tot["pending"] == 0,
                   f"books balance per node and overall: handed in {tot['handed_in']} = "
                   f"delivered {tot['delivered']} + lost {lost} + queue-dropped "
                   f"{tot['queue_dropped']} (+ pending {tot['pending']})"
                   + (f"; NOT for nodes {unbalanced}" if unbalanced else "")))
    checks.append((agents_read <= tot["received"],
                   f"the agents read no more than the emulator handed them: {agents_read} <= "
                   f"{tot['received']}"))
    print()
    for passed, text in checks:
        print(("PASS " if passed else "FAIL ") + text)
        ok = ok and passed
    if args.csv:
        row = {"nodes": n, "duration_s": args.duration, "rate_per_node": args.rate,
               "payload_bytes": payload_len, "idle_connections": args.idle,
               "viewers": len(viewers), "asan": int(asan),
               "baseline_rss_mb": round(baseline / MIB, 1), "rss_10s_mb": round(rss_10 / MIB, 1),
               "rss_end_mb": round(rss_end / MIB, 1), "peak_rss_mb": round(peak / MIB, 1),
               "ceiling_mb": round(ceiling / MIB, 1), "offered": offered,
               "handed_in": tot["handed_in"], "delivered": tot["delivered"], "lost": lost,
               "queue_dropped": tot["queue_dropped"], "to_agent_dropped": tot["to_agent_dropped"],
               **{f"lost_{r}": tot["lost"][r] for r in LOSS_REASONS},
               "worst_lag_ms": float(lag.group(1)) if lag else float("nan"),
               "passed": int(ok)}
        os.makedirs(os.path.dirname(args.csv) or ".", exist_ok=True)
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(row))
            w.writeheader()
            w.writerow(row)
    return 0 if ok else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default="build/release/apps/rfsitl",
                    help="the rfsitl binary (release or ASan build)")
    ap.add_argument("--duration", type=float, default=60.0, help="seconds of flood")
    ap.add_argument("--nodes", type=int, default=64)
    ap.add_argument("--idle", type=int, default=500, help="idle connections")
    ap.add_argument("--viewers", type=int, default=4)
    ap.add_argument("--rate", type=float, default=200.0,
                    help="frames per second each agent offers")
    ap.add_argument("--payload", type=int, default=0,
                    help="payload bytes per frame (0: the PHY's largest)")
    ap.add_argument("--warmup-frames", type=int, default=2)
    ap.add_argument("--net-base", type=int, default=45500)
    ap.add_argument("--loc-base", type=int, default=45503)
    ap.add_argument("--dashboard-port", type=int, default=45505)
    ap.add_argument("--csv", default="", help="write the figures as one CSV row here")
    ap.add_argument("--log", default="", help="write the emulator's output here")
    args = ap.parse_args()
    try:
        return run(args)
    except (RuntimeError, OSError, ConnectionError) as e:
        print(f"overload: FAIL {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
