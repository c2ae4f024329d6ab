"""The SoapySDR module (driver=rfsitl, src/soapy/) against the real emulator:
SoapySDRUtil finds every waiting node and probes one; a python3-soapysdr
program on two nodes sends a timed burst from one and finds it in the other's
RX stream at that virtual time, sees readStream time out in time, a wrong
sample rate and a second claim refused, and gets an error (no hang) when the
emulator stops under it.

Needs soapysdr-tools and python3-soapysdr (scripts/setup.sh); skipped with a
message without them. The module is found through SOAPY_SDR_PLUGIN_PATH: the
build's src/soapy folder (RFSITL_SOAPY_DIR, set by tests/CMakeLists.txt)."""

import json
import os
import queue
import shutil
import subprocess
import threading
import time
import unittest

from harness import ARRIVAL_S, BIN, LOAD_TOLERANT, Emulator

PYTHON = "/usr/bin/python3"  # Debian's python3-soapysdr loads only there
MODULE_DIR = os.environ.get(
    "RFSITL_SOAPY_DIR", os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(BIN))),
                                     "src", "soapy"))


def soapy_missing():
    """Why the test cannot run here, or None."""
    if shutil.which("SoapySDRUtil") is None:
        return "SoapySDRUtil not installed (apt-get install soapysdr-tools)"
    r = subprocess.run([PYTHON, "-c", "import SoapySDR"], capture_output=True, text=True)
    if r.returncode != 0:
        return "python3-soapysdr not installed: " + r.stderr.strip()
    return None


def require_module():
    """Skips the calling test class where SoapySDR is missing; fails it where
    SoapySDR is there but the module was not built."""
    why = soapy_missing()
    if why:
        raise unittest.SkipTest(why)
    if not os.path.exists(os.path.join(MODULE_DIR, "libSoapyRfsitl.so")):
        raise AssertionError("SoapySDR is installed but the module was not built in " + MODULE_DIR)


def soapy_env(module_dir=MODULE_DIR):
    """The environment for programs that load the module (from module_dir). A
    sanitized build's module needs the ASan runtime loaded first, which
    SoapySDRUtil and python are not built with."""
    env = dict(os.environ, SOAPY_SDR_PLUGIN_PATH=module_dir)
    module = os.path.join(module_dir, "libSoapyRfsitl.so")
    ldd = subprocess.run(["ldd", module], capture_output=True, text=True).stdout
    if "libasan" in ldd:
        def lib(name):
            return subprocess.run(["gcc", f"-print-file-name={name}"], capture_output=True,
                                  text=True).stdout.strip()
        # libstdc++ too: python does not link it, and without it loaded at
        # start ASan's __cxa_throw interceptor finds no real one to call.
        env["LD_PRELOAD"] = f"{lib('libasan.so')} {lib('libstdc++.so')}"
        # python and SoapySDRUtil keep memory to their end; only the module is ours.
        env["ASAN_OPTIONS"] = "detect_leaks=0"
    return env


def line_reader(stream):
    """A thread that reads `stream` line by line; returns next_line(timeout),
    which gives the next line, "" at the end of the stream, or None when none
    came within `timeout` seconds: a silent program never blocks a test."""
    lines = queue.Queue()

    def pump():
        for line in stream:
            lines.put(line)
        lines.put("")
    threading.Thread(target=pump, daemon=True).start()

    def next_line(timeout):
        try:
            return lines.get(timeout=max(timeout, 0))
        except queue.Empty:
            return None
    return next_line


def run_program(test, text, *args, context=lambda: ""):
    """Runs `text` in a python of its own (soapy_env), ended with the test.
    Returns until(step, timeout): waits for the program's JSON line of that
    step ({"step": ..., ...}, one a line) and returns it, failing the test
    with the program's output (and `context()`) if it does not come in time.
    until.proc is the process (stdin a pipe), until.lines what it printed."""
    proc = subprocess.Popen([PYTHON, "-u", "-c", text, *args], env=soapy_env(),
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    test.addCleanup(proc.stdout.close)
    test.addCleanup(proc.stdin.close)
    test.addCleanup(lambda: proc.poll() is None and (proc.kill(), proc.wait(10)))
    next_line = line_reader(proc.stdout)
    steps, lines = {}, []

    def until(step, timeout=180):
        deadline = time.monotonic() + timeout
        while step not in steps:
            line = next_line(deadline - time.monotonic())
            if not line:
                test.fail(f"no '{step}' from the Soapy program:\n" + "".join(lines) + context())
            lines.append(line)
            if line.startswith("{"):
                j = json.loads(line)
                steps[j["step"]] = j
        return steps[step]
    until.proc, until.lines = proc, lines
    return until


def start_emulator(test, wait_for_nodes=True, socket=None, tick_samples=None):
    """An emulator with nodes 1 and 2 external, stopped with the test;
    `wait_for_nodes`: it waits for both before it runs, else it runs without
    them after 1 s (they still wait for a program). `socket`: its external
    socket (default /tmp/rfsitl-NET_BASE.sock); `tick_samples`: B (default the
    harness's). Returns (emulator, socket path)."""
    extra = "external:\n  start_timeout_s: %d\n" % (300 if wait_for_nodes else 1)
    if socket:
        extra += "  socket: %s\n" % socket
    timing = list(LOAD_TOLERANT)
    if tick_samples:
        timing[timing.index("--tick") + 1] = str(tick_samples)
    emu = Emulator({1: (0, 0, 10), 2: (15, 0, 10)},
                   node_phy={1: {"type": "external"}, 2: {"type": "external"}},
                   extra_yaml=extra,
                   ready_marker="waiting up to" if wait_for_nodes else "rfsitl: ready",
                   args=["--external-timeout", "5", *timing])
    emu.__enter__()
    test.addCleanup(emu.__exit__, None, None, None)
    return emu, socket or f"/tmp/rfsitl-{emu.net_base}.sock"


def soapy_util(*args, timeout=60):
    r = subprocess.run(["SoapySDRUtil", *args], capture_output=True, text=True,
                       env=soapy_env(), timeout=timeout)
    return r.stdout + r.stderr


# Runs in a python of its own (see soapy_env); prints one JSON line per step.
NODE_PROGRAM = r"""
import json, subprocess, sys, time
import numpy as np
import SoapySDR
from SoapySDR import (SOAPY_SDR_RX, SOAPY_SDR_TX, SOAPY_SDR_CF32, SOAPY_SDR_HAS_TIME,
                      SOAPY_SDR_END_BURST, SOAPY_SDR_TIMEOUT, SOAPY_SDR_TIME_ERROR,
                      SOAPY_SDR_STREAM_ERROR)

sock = sys.argv[1]
def say(**kw):
    print(json.dumps(kw), flush=True)

a = SoapySDR.Device(dict(driver="rfsitl", socket=sock, node="1"))
b = SoapySDR.Device(dict(driver="rfsitl", socket=sock, node="2"))
# A second make in this process shares the device (as GNU Radio's Soapy source
# and sink do); another process is refused.
shared = SoapySDR.Device(dict(driver="rfsitl", socket=sock, node="1"))
default = a.getGain(SOAPY_SDR_RX, 0)
shared.setGain(SOAPY_SDR_RX, 0, default - 3.0)
gain = a.getGain(SOAPY_SDR_RX, 0)
# Out of range is clamped (as UHD does), not refused.
shared.setGain(SOAPY_SDR_RX, 0, 1000.0)
say(step="shared", default=default, gain=gain, clamped=a.getGain(SOAPY_SDR_RX, 0),
    maximum=a.getGainRange(SOAPY_SDR_RX, 0).maximum())
shared.setGain(SOAPY_SDR_RX, 0, default)
shared = None
claim = subprocess.run([sys.executable, "-c", "import SoapySDR, sys; SoapySDR.Device("
                        "dict(driver='rfsitl', socket=sys.argv[1], node='1'))", sock],
                       capture_output=True, text=True, timeout=60)
say(step="second_claim", error=claim.stderr if claim.returncode else None)
fs = a.getSampleRate(SOAPY_SDR_RX, 0)
try:
    a.setSampleRate(SOAPY_SDR_RX, 0, 2 * fs)
    say(step="wrong_rate", error=None)
except RuntimeError as e:
    say(step="wrong_rate", error=str(e))

rx = b.setupStream(SOAPY_SDR_RX, SOAPY_SDR_CF32)
tx = a.setupStream(SOAPY_SDR_TX, SOAPY_SDR_CF32)
mtu = b.getStreamMTU(rx)
b.activateStream(rx)
a.activateStream(tx)
buf = np.zeros(mtu, np.complex64)

def read(timeout_us):
    r = b.readStream(rx, [buf], mtu, timeoutUs=timeout_us)
    return r.ret, r.flags, r.timeNs, buf[:max(r.ret, 0)].copy()

# The emulator runs once both nodes joined: wait for the clock to move.
deadline = time.monotonic() + 60
while a.getHardwareTime() == 0 and time.monotonic() < deadline:
    time.sleep(0.01)
tick_ns = mtu * 1e9 / fs
burst = np.full(2000, 0.7, np.complex64)
# Far enough ahead that the pump has not built that tick yet, even when the
# machine is busy; a late burst is reported and retried further ahead.
margin = 25
for attempt in range(4):
    when = a.getHardwareTime() + int(margin * tick_ns)
    n = a.writeStream(tx, [burst], len(burst), SOAPY_SDR_HAS_TIME | SOAPY_SDR_END_BURST, when).ret
    st = a.readStreamStatus(tx, timeoutUs=int(2 * margin * tick_ns / 1e3 / 0.1))
    if st.ret != SOAPY_SDR_TIME_ERROR:
        break
    margin *= 4
say(step="write", written=n, when=when, status=st.ret)

# Everything from two ticks before the burst's time to three after it, then
# its first loud sample: the level is the burst's own, whatever the path loss.
times, samples, gaps, last_end, reads = [], [], 0, None, 0
deadline = time.monotonic() + 120
while (last_end is None or last_end < when + 3 * tick_ns) and time.monotonic() < deadline:
    ret, flags, t, x = read(200000)
    if ret <= 0:
        continue
    reads += 1
    if not flags & SOAPY_SDR_HAS_TIME:
        say(step="error", what="no SOAPY_SDR_HAS_TIME")
    if last_end is not None and abs(t - last_end) > 1:
        gaps += 1
    last_end = t + ret * 1e9 / fs
    if last_end >= when - 2 * tick_ns:
        times.append(t + np.arange(ret) * 1e9 / fs)
        samples.append(x)
found = None
if samples:
    x, ts = np.abs(np.concatenate(samples)), np.concatenate(times)
    found = float(ts[np.nonzero(x > 0.3 * x.max())[0][0]])
say(step="rx", found=found, when=when, tick_ns=tick_ns, gaps=gaps, reads=reads)

b.deactivateStream(rx)
t0 = time.monotonic()
ret = read(50000)[0]
say(step="timeout", ret=ret, waited=time.monotonic() - t0)

b.activateStream(rx)
say(step="streaming")
t0 = time.monotonic()
ret = 0
while time.monotonic() - t0 < 120:
    ret = read(100000)[0]
    if ret < 0 and ret != SOAPY_SDR_TIMEOUT:
        break
say(step="stopped", ret=ret, waited=time.monotonic() - t0)
b.closeStream(rx)
a.closeStream(tx)
a = b = None
say(step="closed")
"""


class SoapyModuleTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        require_module()

    def start(self, wait_for_nodes=True, socket=None, tick_samples=None):
        return start_emulator(self, wait_for_nodes, socket, tick_samples)

    def program(self, text, *args, context=lambda: ""):
        """Runs `text` in a python of its own (soapy_env); returns its step
        reader (run_program)."""
        return run_program(self, text, *args, context=context)

    def test_find_lists_every_waiting_node_and_probe_shows_the_device(self):
        emu, sock = self.start(wait_for_nodes=False)
        out = soapy_util(f"--find=driver=rfsitl,socket={sock}")
        for node in (1, 2):
            self.assertIn(f"node = {node}", out)
            self.assertIn(f"integration-test node {node}", out)
        # Without socket= the module scans /tmp/rfsitl-*.sock (the default path).
        self.assertIn(f"serial = {sock}#1", soapy_util("--find=driver=rfsitl"))
        out = soapy_util(f"--probe=driver=rfsitl,socket={sock},node=1")
        for text in ("Channels: 1 Rx, 1 Tx", "CF32", "CS16", "CS8", "Native format: CF32",
                     "Sample rates: 1 MSps", "Full gain range: [0, 96] dB",
                     "Full gain range: [-60, 0] dB", "driver=rfsitl"):
            self.assertIn(text, out)
        # The probe's claim ended with it: both nodes are free again, once the
        # emulator has seen the probe's connection close (at its next tick).
        deadline = time.monotonic() + ARRIVAL_S
        out = soapy_util(f"--find=driver=rfsitl,socket={sock}")
        while out.count("claimed = 0") != 2 and time.monotonic() < deadline:
            time.sleep(0.2)
            out = soapy_util(f"--find=driver=rfsitl,socket={sock}")
        self.assertEqual(out.count("claimed = 0"), 2, out)
        summary = emu.stop()
        self.assertEqual(summary["external"]["rejected_connections"], 0)

    def test_timed_burst_arrives_at_its_virtual_time(self):
        emu, sock = self.start()
        until = self.program(NODE_PROGRAM, sock, context=lambda: "".join(emu.output[-30:]))
        lines = until.lines

        shared = until("shared")
        self.assertEqual(shared["gain"], shared["default"] - 3.0)
        self.assertEqual(shared["clamped"], shared["maximum"])
        self.assertIn("already claimed by another program; pass takeover=1",
                      until("second_claim")["error"] or "")
        self.assertIn("setSampleRate(2000000.000000) is not supported",
                      until("wrong_rate")["error"] or "")
        w = until("write")
        self.assertEqual(w["written"], 2000)
        self.assertEqual(w["status"], -1, "late burst (SOAPY_SDR_TIME_ERROR) or other status")
        rx = until("rx")
        self.assertIsNotNone(rx["found"], "the burst never showed up: " + "".join(lines))
        self.assertLessEqual(abs(rx["found"] - rx["when"]), rx["tick_ns"], rx)
        self.assertEqual(rx["gaps"], 0, "RX timestamps not contiguous")
        t = until("timeout")
        self.assertEqual(t["ret"], -1)  # SOAPY_SDR_TIMEOUT
        self.assertGreaterEqual(t["waited"], 0.045)
        self.assertLess(t["waited"], 5.0)
        until("streaming")
        emu.stop()
        s = until("stopped", timeout=ARRIVAL_S)
        self.assertEqual(s["ret"], -2)  # SOAPY_SDR_STREAM_ERROR
        until("closed", timeout=ARRIVAL_S)
        self.assertEqual(until.proc.wait(ARRIVAL_S), 0, "".join(lines))

    def test_overflows_of_a_program_that_never_reads_reach_the_node_counters(self):
        emu, sock = self.start(wait_for_nodes=False)
        until = self.program(NEVER_READS, sock)
        seen = until("overflowed")["rx_overflows"]
        self.assertGreater(seen, 0)
        # Reported with the module's next answer to a tick: /api/stats has it.
        emu.wait_until(lambda st: any(n["id"] == 1 and n["external_overflows"] > 0
                                      for n in st["nodes"]), what="node 1's overflows")
        until.proc.stdin.write("done\n")
        until.proc.stdin.flush()
        last = until("closed")["rx_overflows"]
        self.assertEqual(until.proc.wait(ARRIVAL_S), 0, "".join(until.lines))
        summary = emu.stop()
        counted = [n["external_overflows"] for n in summary["nodes"] if n["id"] == 1][0]
        # Every report the emulator read is a total the device had reached.
        self.assertGreater(counted, 0)
        self.assertLessEqual(counted, last)
        self.assertEqual([n["external_overflows"] for n in summary["nodes"] if n["id"] == 2],
                         [0])

    def test_device_rejoins_an_emulator_restarted_on_its_socket(self):
        sock = os.path.join(self.tmp_dir(), "emu.sock")
        first, _ = self.start(wait_for_nodes=False, socket=sock)
        until = self.program(REJOINS, sock)
        until("streaming")
        first.stop()
        self.assertEqual(until("lost")["ret"], -2)  # SOAPY_SDR_STREAM_ERROR
        second, _ = self.start(wait_for_nodes=False, socket=sock)
        back = until("back", timeout=ARRIVAL_S * 2)
        self.assertEqual(back["rejoins"], "1")
        self.assertEqual(back["link"], "connected")
        self.assertGreater(back["read"], 0)
        self.assertEqual(back["connected"], "true")
        # Samples and hardware time are the second emulator's: within the RX
        # buffer (1 s of virtual time) of each other.
        self.assertLess(abs(back["hw_time_ns"] - back["time_ns"]), 1.1e9, back)
        until("closed")
        self.assertEqual(until.proc.wait(ARRIVAL_S), 0, "".join(until.lines))
        summary = second.stop()
        joined = [n for n in summary["external"]["nodes"] if n["id"] == 1][0]
        self.assertEqual(joined["joins"], 1)

    def test_device_does_not_rejoin_an_emulator_with_another_tick_and_says_why(self):
        sock = os.path.join(self.tmp_dir(), "emu.sock")
        first, _ = self.start(wait_for_nodes=False, socket=sock)
        until = self.program(REJOINS, sock)
        until("streaming")
        first.stop()
        until("lost")
        second, _ = self.start(wait_for_nodes=False, socket=sock, tick_samples=2000)
        stuck = until("stopped", timeout=ARRIVAL_S * 2)
        self.assertIn("2000 per tick; this device has", stuck["link"])
        self.assertIn("make a new device", stuck["link"])
        self.assertEqual(until.proc.wait(ARRIVAL_S), 0, "".join(until.lines))

    def test_of_two_programs_claiming_one_node_at_once_one_gets_it(self):
        emu, sock = self.start(wait_for_nodes=False)
        # Both pass the discovery check (the node is free), then both claim;
        # the emulator admits the first exclusive claim only.
        procs = [subprocess.Popen([PYTHON, "-u", "-c", CLAIM_AT_ONCE, sock], env=soapy_env(),
                                  stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True)
                 for _ in range(2)]
        for p in procs:
            self.addCleanup(lambda p=p: p.poll() is None and p.kill())
        # "claimed" (then it holds the node until its stdin closes), or an
        # exit with the error: each comes without the other process's help.
        first_lines = [p.stdout.readline() for p in procs]
        outs = [p.communicate(timeout=120) for p in procs]
        got = [line for line in first_lines if line.startswith("claimed")]
        refused = [e for _, e in outs if "refused the claim" in e or "already claimed" in e]
        self.assertEqual((len(got), len(refused)), (1, 1), (first_lines, outs))

    def test_bad_device_arguments_raise_errors_that_name_them(self):
        emu, sock = self.start(wait_for_nodes=False)
        expected = {
            "node=abc": "node=abc is not a node id (1..254)",
            "node=0": "node=0 is not a node id (1..254)",
            "node=255": "node=255 is not a node id (1..254)",
            "node=7": f"node 7 is not a node with phy: {{type: external}} at {sock}",
            "node=1,takeover=maybe": "takeover=maybe (expected 1 or 0)",
            "node=1,buffer_ms=0": "buffer_ms=0 (expected 1 .. 60000)",
            "node=1,buffer_ms=1e9": "buffer_ms=1e9 (expected 1 .. 60000)",
            "node=1,buffer_ms=10ms": "buffer_ms=10ms (expected 1 .. 60000)",
        }
        until = self.program(BAD_ARGUMENTS, sock, *expected)
        for extra, text in expected.items():
            self.assertIn(text, until(extra)["error"] or "no error", extra)
        missing = os.path.join(self.tmp_dir(), "none.sock")
        until = run_program(self, BAD_ARGUMENTS, missing, "node=1")
        self.assertIn(missing, until("node=1")["error"] or "no error")
        self.assertEqual(until.proc.wait(ARRIVAL_S), 0)
        # None of them claimed a node or upset the emulator.
        summary = emu.stop()
        self.assertEqual([n["joins"] for n in summary["external"]["nodes"]], [0, 0])

    def test_takeover_takes_a_held_node_and_the_holder_rejoins_once_it_is_free(self):
        sock = os.path.join(self.tmp_dir(), "emu.sock")
        emu, _ = self.start(wait_for_nodes=False, socket=sock)
        holder = self.program(REJOINS, sock)
        holder("streaming")
        # A program that restarts after a crash takes its node back with
        # takeover=1, although the old claim still holds it.
        taker = self.program(TAKES_OVER, sock)
        took = taker("took")
        self.assertGreater(took["read"], 0)
        self.assertEqual(took["connected"], "true")
        self.assertEqual(holder("lost")["ret"], -2)  # SOAPY_SDR_STREAM_ERROR
        taker.proc.stdin.write("go on\n")
        taker.proc.stdin.flush()
        releasing = taker("releasing")
        self.assertGreater(releasing["read"], 0, "the taker's stream stopped while it held")
        self.assertEqual(releasing["connected"], "true")
        taker("closed")
        self.assertEqual(taker.proc.wait(ARRIVAL_S), 0, "".join(taker.lines))
        # The holder's rejoins (exclusive) were refused while the taker held
        # the node, and one succeeds once it is free.
        back = holder("back", timeout=ARRIVAL_S * 2)
        self.assertEqual(back["rejoins"], "1")
        self.assertGreater(back["wall"], releasing["wall"])
        holder("closed")
        self.assertEqual(holder.proc.wait(ARRIVAL_S), 0, "".join(holder.lines))
        summary = emu.stop()
        joined = [n for n in summary["external"]["nodes"] if n["id"] == 1][0]
        self.assertEqual(joined["joins"], 3)  # holder, taker, holder again

    def tmp_dir(self):
        import tempfile
        d = tempfile.TemporaryDirectory(prefix="rfsitl-soapy-")
        self.addCleanup(d.cleanup)
        return d.name


# Activates RX and never reads, with a 20 ms buffer: it overflows at once.
NEVER_READS = r"""
import json, sys, time
import SoapySDR
from SoapySDR import SOAPY_SDR_RX, SOAPY_SDR_CF32
d = SoapySDR.Device(dict(driver="rfsitl", socket=sys.argv[1], node="1", buffer_ms="20"))
rx = d.setupStream(SOAPY_SDR_RX, SOAPY_SDR_CF32)
d.activateStream(rx)
def count():
    return int(d.getHardwareInfo()["rx_overflows"])
deadline = time.monotonic() + 120
while count() == 0 and time.monotonic() < deadline:
    time.sleep(0.05)
print(json.dumps({"step": "overflowed", "rx_overflows": count()}), flush=True)
sys.stdin.readline()  # until the test has seen the emulator count it
d.deactivateStream(rx)
d.closeStream(rx)
print(json.dumps({"step": "closed", "rx_overflows": count()}), flush=True)
"""

# Streams, loses its emulator, and reads on until it is back (or says why not).
REJOINS = r"""
import json, sys, time
import numpy as np
import SoapySDR
from SoapySDR import SOAPY_SDR_RX, SOAPY_SDR_CF32, SOAPY_SDR_TIMEOUT, SOAPY_SDR_OVERFLOW
def say(**kw):
    print(json.dumps(kw), flush=True)
d = SoapySDR.Device(dict(driver="rfsitl", socket=sys.argv[1], node="1"))
rx = d.setupStream(SOAPY_SDR_RX, SOAPY_SDR_CF32)
d.activateStream(rx)
buf = np.zeros(d.getStreamMTU(rx), np.complex64)
def read():
    return d.readStream(rx, [buf], len(buf), timeoutUs=100000)
deadline = time.monotonic() + 120
while read().ret <= 0 and time.monotonic() < deadline:
    pass
say(step="streaming")
r = read()
while r.ret >= 0 or r.ret in (SOAPY_SDR_TIMEOUT, SOAPY_SDR_OVERFLOW):
    r = read()
say(step="lost", ret=r.ret)
deadline = time.monotonic() + 120
info = d.getHardwareInfo()
while time.monotonic() < deadline:
    r = read()
    info = d.getHardwareInfo()
    if r.ret > 0 or info["link"].startswith("stopped"):
        break
if r.ret > 0:
    say(step="back", read=r.ret, time_ns=r.timeNs, hw_time_ns=d.getHardwareTime(),
        rejoins=info["rejoins"], link=info["link"], connected=d.readSensor("connected"),
        wall=time.time())
else:
    say(step="stopped", link=info["link"], connected=d.readSensor("connected"))
d.deactivateStream(rx)
d.closeStream(rx)
d = None
say(step="closed")
"""

# Takes node 1 over from the program that holds it (takeover=1), streams from
# it until the test says so, and lets it go.
TAKES_OVER = r"""
import json, sys, time
import numpy as np
import SoapySDR
from SoapySDR import SOAPY_SDR_RX, SOAPY_SDR_CF32
def say(**kw):
    print(json.dumps(kw), flush=True)
d = SoapySDR.Device(dict(driver="rfsitl", socket=sys.argv[1], node="1", takeover="1"))
rx = d.setupStream(SOAPY_SDR_RX, SOAPY_SDR_CF32)
d.activateStream(rx)
buf = np.zeros(d.getStreamMTU(rx), np.complex64)
read = 0
deadline = time.monotonic() + 120
while read == 0 and time.monotonic() < deadline:
    read = max(d.readStream(rx, [buf], len(buf), timeoutUs=100000).ret, 0)
say(step="took", read=read, connected=d.readSensor("connected"))
sys.stdin.readline()  # holds the node, reading, until the test has seen the holder lose it
more = sum(max(d.readStream(rx, [buf], len(buf), timeoutUs=100000).ret, 0) for _ in range(5))
say(step="releasing", read=more, connected=d.readSensor("connected"), wall=time.time())
d.deactivateStream(rx)
d.closeStream(rx)
d = None
say(step="closed")
"""

# Makes a device from each argument string of argv[2:] (after "socket=SOCK,")
# and prints what SoapySDR raised, or null if it made one.
BAD_ARGUMENTS = r"""
import json, sys
import SoapySDR
for extra in sys.argv[2:]:
    args = dict(kv.split("=", 1)
                for kv in ("driver=rfsitl,socket=" + sys.argv[1] + "," + extra).split(","))
    try:
        SoapySDR.Device(args)
        error = None
    except RuntimeError as e:
        error = str(e)
    print(json.dumps({"step": extra, "error": error}), flush=True)
"""

# Claims node 1 and holds it, so that the other claim meets it.
CLAIM_AT_ONCE = r"""
import sys
import SoapySDR
d = SoapySDR.Device(dict(driver="rfsitl", socket=sys.argv[1], node="1"))
print("claimed", flush=True)
sys.stdin.read()  # holds the node until the test closes stdin
"""


if __name__ == "__main__":
    unittest.main(verbosity=2)
