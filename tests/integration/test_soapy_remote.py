"""SoapyRemote (Debian's soapyremote-server and soapysdr-module-remote): the
rfsitl devices served by SoapySDRServer from a network namespace of their
own, reached over a veth link by driver=remote from this one, as an SDR
application on another host would reach them. find lists the waiting nodes
through the server; a remote node's timed burst arrives in a local node's RX
stream.

The server runs where the emulator is (the Unix socket is a file, which
network namespaces share); only SoapyRemote's TCP and UDP cross the link.
Needs root (ip netns), iproute2, SoapySDRServer and the remote module;
skipped with a message without them. Everything it creates (namespace, veth
pair, server, emulator) goes again at the end, also when a step fails."""

import os
import shutil
import signal
import subprocess
import time
import unittest

from harness import ARRIVAL_S
from test_soapy import (MODULE_DIR, line_reader, run_program, soapy_env, soapy_missing,
                        start_emulator)

REMOTE_MODULE = "/usr/lib/x86_64-linux-gnu/SoapySDR/modules0.8/libremoteSupport.so"
# SoapySDRServer cannot serve a sanitized module (see setUpClass), so this test
# takes a release build's module when it is given one (scripts/test.sh builds it).
REMOTE_MODULE_DIR = os.environ.get("RFSITL_SOAPY_RELEASE_DIR", MODULE_DIR)
SERVER_PORT = 47132  # this project's range (47000-47999); inside the test's namespace


def remote_missing():
    why = soapy_missing()
    if why:
        return why
    if os.geteuid() != 0:
        return "needs root for ip netns"
    if shutil.which("ip") is None:
        return "iproute2 not installed"
    if shutil.which("SoapySDRServer") is None or not os.path.exists(REMOTE_MODULE):
        return ("SoapyRemote not installed (apt-get install soapyremote-server "
                "soapysdr-module-remote)")
    if shutil.which("avahi-daemon") is None or shutil.which("dbus-daemon") is None:
        return "avahi-daemon and dbus-daemon needed by SoapySDRServer (apt-get install avahi-daemon)"
    return None


def run(*cmd):
    subprocess.run(cmd, check=True, capture_output=True, text=True, timeout=30)


# Debian's SoapySDRServer publishes itself through Avahi and exits at once
# ("DNS-SD daemon disconnected... Exiting prematurely") when no Avahi daemon
# answers on the D-Bus system bus. So the namespace gets its own: a private
# /run (mount namespace) for a system bus and an avahi-daemon that see only
# the namespace's interfaces, then the server. $1: the bind address.
SERVER_SCRIPT = r"""
set -e
mount -t tmpfs tmpfs /run
mkdir -p /run/dbus /run/avahi-daemon
chown avahi:avahi /run/avahi-daemon
dbus-daemon --system --fork
avahi-daemon --daemonize --no-chroot --no-rlimits
exec env LD_PRELOAD="$SERVER_PRELOAD" SoapySDRServer --bind="$1"
"""


# Runs in the test's namespace (the application's side): node 1 through the
# server transmits a timed burst, node 2 (local) finds it in its RX stream.
REMOTE_PROGRAM = r"""
import json, sys, time
import numpy as np
import SoapySDR
from SoapySDR import (SOAPY_SDR_RX, SOAPY_SDR_TX, SOAPY_SDR_CF32, SOAPY_SDR_HAS_TIME,
                      SOAPY_SDR_END_BURST)
server, sock = sys.argv[1], sys.argv[2]
def say(**kw):
    print(json.dumps(kw), flush=True)
found = SoapySDR.Device.enumerate(dict(driver="remote", remote=server,
                                       **{"remote:driver": "rfsitl"}, socket=sock))
say(step="find", nodes=sorted(int(f["node"]) for f in found))
remote = SoapySDR.Device(dict(driver="remote", remote=server, **{"remote:driver": "rfsitl"},
                              socket=sock, node="1"))
local = SoapySDR.Device(dict(driver="rfsitl", socket=sock, node="2"))
fs = remote.getSampleRate(SOAPY_SDR_TX, 0)
say(step="remote", driver=remote.getDriverKey(), rate=fs,
    hardware=dict(remote.getHardwareInfo()))
rx = local.setupStream(SOAPY_SDR_RX, SOAPY_SDR_CF32)
tx = remote.setupStream(SOAPY_SDR_TX, SOAPY_SDR_CF32)
local.activateStream(rx)
remote.activateStream(tx)
mtu = local.getStreamMTU(rx)
buf = np.zeros(mtu, np.complex64)
deadline = time.monotonic() + 60
while local.getHardwareTime() == 0 and time.monotonic() < deadline:
    time.sleep(0.01)
tick_ns = mtu * 1e9 / fs
# Far ahead: the remote path adds network round trips to the write.
when = local.getHardwareTime() + int(100 * tick_ns)
burst = np.full(2000, 0.7, np.complex64)
# SoapyRemote takes what fits its datagrams per call: the rest follows
# untimed, right after (each piece ends the burst so far: no underflow).
n, flags = 0, SOAPY_SDR_HAS_TIME
while n < len(burst):
    r = remote.writeStream(tx, [burst[n:]], len(burst) - n, flags | SOAPY_SDR_END_BURST, when)
    if r.ret <= 0:
        break
    n, flags = n + r.ret, 0
say(step="write", written=n, when=when)
# Everything from two ticks before the burst's time to three after it, then
# its first loud sample (relative to the loudest: whatever the path loss).
times, samples, last_end = [], [], None
deadline = time.monotonic() + 120
while (last_end is None or last_end < when + 3 * tick_ns) and time.monotonic() < deadline:
    r = local.readStream(rx, [buf], mtu, timeoutUs=200000)
    if r.ret <= 0:
        continue
    last_end = r.timeNs + r.ret * 1e9 / fs
    if last_end >= when - 2 * tick_ns:
        times.append(r.timeNs + np.arange(r.ret) * 1e9 / fs)
        samples.append(buf[:r.ret].copy())
found_at = None
if samples:
    x, ts = np.abs(np.concatenate(samples)), np.concatenate(times)
    found_at = float(ts[np.nonzero(x > 0.3 * x.max())[0][0]])
say(step="rx", found=found_at, when=when, tick_ns=tick_ns)
local.deactivateStream(rx)
remote.deactivateStream(tx)
local.closeStream(rx)
remote.closeStream(tx)
remote = local = None
say(step="closed")
"""


class SoapyRemoteTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        why = remote_missing()
        if why:
            raise unittest.SkipTest(why)
        module = os.path.join(REMOTE_MODULE_DIR, "libSoapyRfsitl.so")
        if not os.path.exists(module):
            raise AssertionError("the module was not built in " + REMOTE_MODULE_DIR)
        ldd = subprocess.run(["ldd", module], capture_output=True, text=True).stdout
        if "libasan" in ldd:
            # With the ASan runtime preloaded (which a sanitized module needs),
            # Debian's SoapySDRServer hangs in its Avahi client and never serves.
            raise unittest.SkipTest(
                "SoapySDRServer cannot load a sanitized module (it hangs connecting to Avahi "
                "with libasan preloaded): point RFSITL_SOAPY_RELEASE_DIR at a release build's "
                "src/soapy (scripts/build.sh release rfsitl_soapy)")

    def namespace(self):
        """A network namespace (the project's prefix h14) joined to this one by
        a veth pair; returns (namespace, its address, ours)."""
        tag = os.getpid() % 100000
        ns = f"h14soapy{tag}"
        ours, theirs = f"h14v{tag}a", f"h14v{tag}b"
        net = f"10.214.{tag % 64 * 4}"
        run("ip", "netns", "add", ns)
        self.addCleanup(subprocess.run, ["ip", "netns", "del", ns], capture_output=True)
        # Before the namespace goes: every process started in it (the server,
        # its bus and Avahi daemons), which would otherwise outlive the test.
        self.addCleanup(self.end_processes_in, ns)
        run("ip", "link", "add", ours, "type", "veth", "peer", "name", theirs)
        # Deleting the namespace deletes its end and so the pair; this is for
        # a failure before the move.
        self.addCleanup(subprocess.run, ["ip", "link", "del", ours], capture_output=True)
        run("ip", "link", "set", theirs, "netns", ns)
        run("ip", "addr", "add", f"{net}.1/30", "dev", ours)
        run("ip", "link", "set", ours, "up")
        run("ip", "netns", "exec", ns, "ip", "addr", "add", f"{net}.2/30", "dev", theirs)
        run("ip", "netns", "exec", ns, "ip", "link", "set", theirs, "up")
        run("ip", "netns", "exec", ns, "ip", "link", "set", "lo", "up")
        return ns, f"{net}.2", f"{net}.1"

    @staticmethod
    def end_processes_in(ns):
        pids = subprocess.run(["ip", "netns", "pids", ns], capture_output=True,
                              text=True).stdout.split()
        for pid in pids:
            try:
                os.kill(int(pid), signal.SIGKILL)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + 10
        while pids and time.monotonic() < deadline:
            pids = subprocess.run(["ip", "netns", "pids", ns], capture_output=True,
                                  text=True).stdout.split()
            time.sleep(0.05)

    def test_nodes_served_from_another_namespace_are_found_and_stream(self):
        ns, server_ip, _ = self.namespace()
        emu, sock = start_emulator(self)  # runs once both nodes joined

        env = soapy_env(REMOTE_MODULE_DIR)
        env["SERVER_PRELOAD"] = env.pop("LD_PRELOAD", "")  # the server only, not the daemons
        server = subprocess.Popen(["ip", "netns", "exec", ns, "unshare", "-m",
                                   "--propagation", "private", "sh", "-c", SERVER_SCRIPT, "sh",
                                   f"{server_ip}:{SERVER_PORT}"],
                                  env=env, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True)
        self.addCleanup(server.stdout.close)
        self.addCleanup(lambda: server.poll() is None and (server.kill(), server.wait(10)))
        server_lines = []
        next_line = line_reader(server.stdout)
        deadline = time.monotonic() + ARRIVAL_S
        while not any("Press Ctrl+C to stop the server" in line for line in server_lines):
            line = next_line(deadline - time.monotonic())
            if not line:
                self.fail("SoapySDRServer did not start:\n" + "".join(server_lines))
            server_lines.append(line)

        until = run_program(self, REMOTE_PROGRAM, f"tcp://{server_ip}:{SERVER_PORT}", sock,
                            context=lambda: "".join(emu.output[-20:] + server_lines[-20:]))
        lines = until.lines

        self.assertEqual(until("find")["nodes"], [1, 2])
        remote = until("remote")
        self.assertEqual(remote["driver"], "rfsitl")  # the server's device
        self.assertEqual(remote["rate"], 1e6)
        self.assertEqual(until("write")["written"], 2000)
        rx = until("rx")
        self.assertIsNotNone(rx["found"], "the remote node's burst never arrived: "
                             + "".join(lines))
        self.assertLessEqual(abs(rx["found"] - rx["when"]), rx["tick_ns"], rx)
        until("closed")
        self.assertEqual(until.proc.wait(ARRIVAL_S), 0, "".join(lines))


if __name__ == "__main__":
    unittest.main(verbosity=2)
