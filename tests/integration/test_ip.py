"""IP on every node (`rfsitl run --ip`): stock ping between network
namespaces across the radio channel, bad frames refused and counted, no
namespace left behind, a killed run's namespaces removed by the next start.

Needs root (network namespaces, TAP devices); skips with the reason otherwise.
Every namespace a test makes is named after its emulator's random port base and
removed in tearDown whatever happened."""

import os
import re
import shutil
import signal
import subprocess
import time
import unittest

from harness import ARRIVAL_S, BIN, Emulator

TWO = {1: (0, 0, 10), 2: (5, 0, 10)}

# A bounded TCP transfer: node 2 listens, node 1 sends TCP_BYTES of seeded
# random bytes; each prints what it saw (count and SHA-256), nothing else.
TCP_BYTES = 60000
TCP_SINK = f"""
import hashlib, socket
s = socket.create_server(("10.77.0.2", 5201))
s.settimeout(90)
c, _ = s.accept()
c.settimeout(90)
h, n = hashlib.sha256(), 0
while n < {TCP_BYTES}:
    b = c.recv(65536)
    if not b:
        break
    h.update(b)
    n += len(b)
print(n, h.hexdigest())
"""
TCP_SOURCE = f"""
import hashlib, random, socket, time
data = random.Random(5).randbytes({TCP_BYTES})
end = time.monotonic() + 30
while True:
    try:
        c = socket.create_connection(("10.77.0.2", 5201), timeout=90)
        break
    except OSError:
        if time.monotonic() > end:
            raise
        time.sleep(0.2)
c.sendall(data)
c.shutdown(socket.SHUT_WR)
c.settimeout(90)
c.recv(1)
print(hashlib.sha256(data).hexdigest())
"""


def netns_names(prefix):
    out = subprocess.run(["ip", "netns", "list"], capture_output=True, text=True, timeout=10)
    return sorted(line.split()[0] for line in out.stdout.splitlines()
                  if line.split() and line.split()[0].startswith(prefix + "-"))


def remove_netns(prefix):
    """What a test's runs may have left: namespaces and the run's claim file
    (a run killed with SIGKILL leaves both; its emulators are gone by now)."""
    for name in netns_names(prefix):
        subprocess.run(["ip", "netns", "delete", name], capture_output=True, timeout=10)
    try:
        os.remove(f"/run/rfsitl/{prefix}.pid")
    except FileNotFoundError:
        pass


def in_netns(name, *cmd, timeout=60):
    return subprocess.run(["ip", "netns", "exec", name, *cmd], capture_output=True, text=True,
                          timeout=timeout)


def wait_reachable(netns, address, timeout=ARRIVAL_S):
    """Pings until one reply comes back (bounded by timeout)."""
    ping_until_replies(netns, address, 1, timeout, wait_s=1)


def ping_until_replies(netns, address, replies, timeout, wait_s=3):
    """Pings `address` once at a time, each waiting up to `wait_s` for its
    reply, until `replies` have come back (bounded by timeout); returns how
    many pings that took."""
    deadline = time.monotonic() + timeout
    got = sent = 0
    while got < replies:
        if time.monotonic() > deadline:
            raise AssertionError(f"{got} of {sent} pings from {netns} to {address} answered "
                                 f"within {timeout} s ({replies} wanted)")
        sent += 1
        got += in_netns(netns, "ping", "-c", "1", "-W", str(wait_s), address).returncode == 0
    return sent


def ping_replies(output):
    m = re.search(r"(\d+) received", output)
    assert m, output
    return int(m.group(1))


# Sends raw Ethernet frames out of rf0 from inside a namespace (AF_PACKET).
SEND_RAW = """
import socket, sys
s = socket.socket(socket.AF_PACKET, socket.SOCK_RAW)
s.bind(("rf0", 0))
src = bytes([2, 0, 0, 0, 0, 1])
for dst, ethertype in ((bytes([2, 0, 0, 0, 0, 2]), 0x88B5),   # not IP
                       (bytes([2, 0, 0, 0, 0, 9]), 0x0800)):  # a MAC that names no node
    s.send(dst + src + ethertype.to_bytes(2, "big") + bytes(46))
"""


def ip_tools_missing():
    if os.geteuid() != 0:
        return "needs root: network namespaces and TAP devices"
    if not os.path.exists("/dev/net/tun"):
        return "needs /dev/net/tun"
    for tool in ("ip", "ping"):
        if shutil.which(tool) is None:
            return f"needs `{tool}` (iproute2, iputils-ping)"
    return None


@unittest.skipIf(ip_tools_missing(), ip_tools_missing() or "")
class IpNetworking(unittest.TestCase):
    def setUp(self):
        self.prefixes = []

    def tearDown(self):
        for prefix in self.prefixes:
            remove_netns(prefix)

    def emulator(self, nodes=TWO, args=(), **kw):
        emu = Emulator(nodes, args=["--ip", *args], **kw)
        self.prefixes.append(f"rfsitl-{emu.net_base}")
        return emu

    def test_stock_ping_crosses_the_radio_and_nothing_is_left(self):
        with self.emulator() as emu:
            prefix = f"rfsitl-{emu.net_base}"
            self.assertEqual(netns_names(prefix), [f"{prefix}-1", f"{prefix}-2"])
            banner = "".join(emu.output)
            self.assertIn(f"netns {prefix}-1", banner)
            self.assertIn("10.77.0.2/24", banner)
            # At link-up both kernels announce themselves at once (IPv6 router
            # solicitations, multicast listener reports): with no MAC yet those
            # frames can collide with the first ARP request, whose retry comes
            # a second later. Wait until node 2 answers, then measure.
            wait_reachable(f"{prefix}-1", "10.77.0.2")
            ping = in_netns(f"{prefix}-1", "ping", "-c", "20", "-i", "0.2", "-W", "3",
                            "10.77.0.2")
            replies = ping_replies(ping.stdout)
            self.assertGreaterEqual(replies, 15, ping.stdout)
            wait_reachable(f"{prefix}-2", "fd72:6673:6974:1::1")
            ping6 = in_netns(f"{prefix}-2", "ping", "-6", "-c", "5", "-i", "0.2", "-W", "3",
                             "fd72:6673:6974:1::1")
            self.assertGreaterEqual(ping_replies(ping6.stdout), 3, ping6.stdout)
            summary = emu.stop()
        # The frames crossed the emulator: every request and reply was handed in
        # from a TAP, put on the air and decoded by the other node's radio.
        n1, n2 = summary["nodes"][0], summary["nodes"][1]
        self.assertGreaterEqual(n1["handed_in"], 20)
        self.assertGreaterEqual(n1["transmitted"], 20)
        self.assertGreaterEqual(n2["received"], replies)
        self.assertGreaterEqual(n1["received"], replies)
        self.assertGreaterEqual(summary["ip"]["frames_from_tap"], 2 * replies)
        self.assertGreaterEqual(summary["ip"]["frames_to_tap"], 2 * replies)
        self.assertEqual([n["mtu"] for n in summary["ip"]["nodes"]], [2033, 2033])
        self.assertEqual(netns_names(prefix), [], "namespaces left after the run")

    def test_tcp_crosses_the_radio_under_csma_and_the_acks_are_counted_apart(self):
        # Without a MAC, TCP's data and its acks going the other way collide
        # (README); csma's carrier sense, ACKs and retries carry it.
        with self.emulator(args=["--mac", "csma"]) as emu:
            prefix = f"rfsitl-{emu.net_base}"
            self.assertIn("rfsitl: mac csma: slot", "".join(emu.output))
            wait_reachable(f"{prefix}-1", "10.77.0.2")
            server = subprocess.Popen(
                ["ip", "netns", "exec", f"{prefix}-2", "/usr/bin/python3", "-c", TCP_SINK],
                stdout=subprocess.PIPE, text=True)
            try:
                sent = in_netns(f"{prefix}-1", "/usr/bin/python3", "-c", TCP_SOURCE, timeout=120)
                self.assertEqual(sent.returncode, 0, sent.stderr)
                out, _ = server.communicate(timeout=60)
            finally:
                server.kill()
                server.wait()
            summary = emu.stop()
        self.assertEqual(out.split(), [str(TCP_BYTES), sent.stdout.strip()], "bytes, sha256")
        n1, n2 = summary["nodes"][0], summary["nodes"][1]
        self.assertEqual(summary["mac"]["type"], "csma")
        # Every frame handed in was delivered or lost once, however many
        # attempts it took; the receiver's ACKs are counted apart.
        for n in (n1, n2):
            self.assertEqual(n["pending"] + n["delivered"] + sum(n["lost"].values()) +
                             n["queue_dropped"], n["handed_in"])
        # At most 2031 bytes of IP a frame: node 2 acknowledged at least that
        # many data frames, node 1 the TCP acks going back.
        self.assertGreaterEqual(n2["mac_control_sent"], TCP_BYTES // 2031)
        self.assertGreater(n1["mac_control_sent"], 0)
        self.assertEqual([n["mtu"] for n in summary["ip"]["nodes"]], [2031, 2031])

    def test_frames_that_are_not_ip_or_name_no_node_are_refused_and_counted(self):
        with self.emulator() as emu:
            prefix = f"rfsitl-{emu.net_base}"
            sent = in_netns(f"{prefix}-1", "/usr/bin/python3", "-c", SEND_RAW)
            self.assertEqual(sent.returncode, 0, sent.stderr)
            emu.wait_until(lambda st: st["nodes"][0]["ip_refused"] >= 2, what="2 refused frames")
            summary = emu.stop()
        self.assertEqual(summary["nodes"][0]["ip_refused"], 2)
        log = "".join(emu.output)
        self.assertIn("refused: not_ip", log)
        self.assertIn("refused: unknown_mac", log)

    def test_a_killed_runs_namespaces_are_removed_by_the_next_start(self):
        emu = self.emulator()
        emu.__enter__()
        prefix = f"rfsitl-{emu.net_base}"
        try:
            self.assertEqual(len(netns_names(prefix)), 2)
            emu.proc.send_signal(signal.SIGKILL)
            emu.proc.wait(30)
            self.assertEqual(len(netns_names(prefix)), 2, "SIGKILL leaves them behind")
        finally:
            emu._reader.join(10)
            emu.proc.stdout.close()
            emu.dir.cleanup()
        again = Emulator(TWO, args=["--ip"])
        # The killed run's port bases: its prefix is the one to sweep.
        for flag, value in (("--net-base", emu.net_base), ("--loc-base", emu.loc_base)):
            again.args[again.args.index(flag) + 1] = str(value)
        again.net_base, again.loc_base = emu.net_base, emu.loc_base
        with again:
            log = "".join(again.output)
            self.assertIn(f"removed network namespace {prefix}-1", log)
            self.assertIn(f"removed network namespace {prefix}-2", log)
            self.assertEqual(len(netns_names(prefix)), 2)  # this run's own
        self.assertEqual(netns_names(prefix), [])

    def test_a_second_run_on_the_same_base_is_refused_and_leaves_the_first_alone(self):
        with self.emulator() as emu:
            prefix = f"rfsitl-{emu.net_base}"
            second = subprocess.run(
                [BIN, "run", "--nodes", "2", "--ip", "--net-base", str(emu.net_base),
                 "--loc-base", str(emu.loc_base + 1), "--no-dashboard", "--duration", "1",
                 "--mode", "virtual"],
                capture_output=True, text=True, timeout=60)
            self.assertEqual(second.returncode, 2, second.stdout + second.stderr)
            self.assertIn(str(emu.proc.pid), second.stderr)
            self.assertEqual(len(netns_names(prefix)), 2)
            wait_reachable(f"{prefix}-1", "10.77.0.2")
            ping = in_netns(f"{prefix}-1", "ping", "-c", "3", "-i", "0.2", "-W", "3", "10.77.0.2")
            self.assertGreaterEqual(ping_replies(ping.stdout), 2, ping.stdout)

    def test_a_namespace_to_attach_that_does_not_exist_stops_the_start(self):
        emu = Emulator(TWO, args=["--ip"])
        self.prefixes.append(f"rfsitl-{emu.net_base}")
        # The scenario names node 2's namespace; none of that name exists.
        with open(emu.scenario) as f:
            text = f.read().replace("  - id: 2\n",
                                    "  - id: 2\n    netns: rfsitl-no-such-namespace\n")
        with open(emu.scenario, "w") as f:
            f.write(text)
        run = subprocess.run(emu.args, capture_output=True, text=True, timeout=60)
        emu.dir.cleanup()
        self.assertEqual(run.returncode, 2, run.stdout + run.stderr)
        self.assertIn("rfsitl-no-such-namespace", run.stderr)
        self.assertEqual(netns_names(f"rfsitl-{emu.net_base}"), [], "node 1's was not removed")


# Node 1 and node 3 are 120 m apart: below the default GMSK's sensitivity
# (SNR 120 - 60 log10(121) = -5 dB); each is 60 m from node 2 (12.9 dB).
LINE = {1: (0, 0, 10), 2: (60, 0, 10), 3: (120, 0, 10)}
BABEL_CONFIG = [
    # babeld treats a TAP as wired; as wired, split horizon would keep node 2
    # from announcing node 3's route back out of the interface it came in on.
    "interface rf0 type wireless hello-interval 0.5 update-interval 2",
    # Every node's own /32 (the /24 is on-link for everyone and would hide them).
    "redistribute local ip 10.77.0.0/24 ge 32",
    "redistribute local deny",
]


def live_node(emu, node_id):
    """A node's counters now, from the running emulator's /api/stats."""
    return next(n for n in emu.stats()["nodes"] if n["id"] == node_id)


def route_to(netns, address):
    out = in_netns(netns, "ip", "route", "get", address, timeout=10)
    return out.stdout + out.stderr


@unittest.skipIf(ip_tools_missing() or shutil.which("babeld") is None,
                 ip_tools_missing() or "needs babeld (Debian package babeld; "
                 "scripts/setup.sh installs it)")
class IpAttach(unittest.TestCase):
    @unittest.skipIf(ip_tools_missing() or shutil.which("unshare") is None,
                     ip_tools_missing() or "needs unshare (util-linux)")
    def test_a_node_attaches_to_a_running_processs_namespace(self):
        # A stand-in for a container: a process in a network namespace of its
        # own, made here and ended here.
        holder = subprocess.Popen(["unshare", "--net", "sleep", "120"])
        emu = Emulator(TWO, args=["--ip"])
        prefix = f"rfsitl-{emu.net_base}"
        try:
            with open(emu.scenario) as f:
                text = f.read().replace("  - id: 2\n", f"  - id: 2\n    netns: pid:{holder.pid}\n")
            with open(emu.scenario, "w") as f:
                f.write(text)
            # unshare execs sleep once the namespace exists: wait for that.
            deadline = time.monotonic() + ARRIVAL_S
            while (os.readlink(f"/proc/{holder.pid}/ns/net") == os.readlink("/proc/self/ns/net")
                   and time.monotonic() < deadline):
                time.sleep(0.01)
            with emu:
                self.assertIn(f"netns pid:{holder.pid} (attached)", "".join(emu.output))
                self.assertEqual(netns_names(prefix), [f"{prefix}-1"])
                wait_reachable(f"{prefix}-1", "10.77.0.2")
                # Node 2's interface is inside the process's namespace.
                inside = subprocess.run(["nsenter", "-t", str(holder.pid), "-n", "ip", "-br",
                                         "addr", "show", "rf0"], capture_output=True, text=True,
                                        timeout=10)
                self.assertIn("10.77.0.2/24", inside.stdout, inside.stdout + inside.stderr)
            # The attached namespace outlives the run (its process still holds it).
            self.assertIsNone(holder.poll())
            self.assertEqual(netns_names(prefix), [])
        finally:
            holder.kill()
            holder.wait(10)
            remove_netns(prefix)


# babeld and ping run on the wall clock, so the emulator must keep real time
# even on a loaded machine (stress-ng --cpu 6 beside the suite): a quarter of
# the default sample rate (GMSK at 125 kbit/s) in 4 ms ticks costs it a
# sixteenth of the ticks and a quarter of the samples. (Slowing the emulator
# down instead, as LOAD_TOLERANT does, multiplies babeld's traffic in virtual
# time and saturates the channel.)
MESH_TIMING = ["--sample-rate", "250000", "--tick", "1000"]


class IpMesh(unittest.TestCase):
    def test_three_nodes_in_a_line_route_through_the_middle_and_reconverge(self):
        emu = Emulator(LINE, args=["--ip", *MESH_TIMING])
        prefix = f"rfsitl-{emu.net_base}"
        babels, logs = [], []
        try:
            with emu:
                ns = {i: f"{prefix}-{i}" for i in LINE}
                forwarding = in_netns(ns[2], "sysctl", "-qw", "net.ipv4.ip_forward=1")
                self.assertEqual(forwarding.returncode, 0, forwarding.stderr)
                for i in LINE:
                    cmd = ["ip", "netns", "exec", ns[i], "babeld", "-d", "0",
                           "-I", os.path.join(emu.dir.name, f"babeld{i}.pid"),
                           "-S", os.path.join(emu.dir.name, f"babeld{i}.state")]
                    for line in BABEL_CONFIG:
                        cmd += ["-C", line]
                    logs.append(open(os.path.join(emu.dir.name, f"babeld{i}.log"), "w"))
                    babels.append(subprocess.Popen(cmd + ["rf0"], stdout=subprocess.DEVNULL,
                                                   stderr=logs[-1]))
                # Node 3 is reachable from node 1 only through node 2, once the
                # three babelds have heard each other and announced their
                # routes: on a loaded machine (babeld's timers run on the wall
                # clock, the frames wait for the emulator) that can take longer
                # than one frame's ARRIVAL_S.
                wait_reachable(ns[1], "10.77.0.3", timeout=3 * ARRIVAL_S)
                self.assertIn("via 10.77.0.2", route_to(ns[1], "10.77.0.3"))
                relayed_before = live_node(emu, 2)["handed_in"]
                # Seven round trips through node 2, one ping at a time: on a
                # loaded machine a lagging emulator bunches frames into one
                # tick, where they collide (no MAC), so a count of replies out
                # of a fixed number of pings would measure the machine's load.
                sent = ping_until_replies(ns[1], "10.77.0.3", 7, timeout=3 * ARRIVAL_S)
                # Node 2 put every relayed request and reply on the air itself.
                self.assertGreaterEqual(live_node(emu, 2)["handed_in"] - relayed_before, 14,
                                        f"{sent} pings sent")

                # Node 2 flies 2 km away: no route to node 3 is left.
                feed = emu.feed(2)
                feed.move_local(60, 2000, 10)
                emu.wait_until(lambda st: "via 10.77.0.2" not in route_to(ns[1], "10.77.0.3"),
                               timeout=3 * ARRIVAL_S, what="the route through node 2 to break")
                lost = in_netns(ns[1], "ping", "-c", "3", "-i", "0.3", "-W", "1", "10.77.0.3")
                self.assertNotEqual(lost.returncode, 0, lost.stdout)  # "No route to host"
                self.assertNotRegex(lost.stdout, r"[1-9]\d* received")

                # Back in the middle: the route comes back.
                feed.move_local(60, 0, 10)
                wait_reachable(ns[1], "10.77.0.3", timeout=3 * ARRIVAL_S)
                self.assertIn("via 10.77.0.2", route_to(ns[1], "10.77.0.3"))
        finally:
            for b in babels:
                b.terminate()
            for b in babels:
                try:
                    b.wait(10)
                except subprocess.TimeoutExpired:
                    b.kill()
                    b.wait(10)
            for f in logs:
                f.close()
            remove_netns(prefix)
        self.assertEqual(netns_names(prefix), [])


class IpPrivileges(unittest.TestCase):
    @unittest.skipIf(shutil.which("setpriv") is None, "needs setpriv (util-linux)")
    def test_without_privileges_ip_is_refused_with_what_is_missing(self):
        # The two capabilities taken out of the bounding set: even root then
        # runs without them (and the binary need not be readable by another
        # user, as it is not in CI's private temporary folder).
        run = subprocess.run(
            ["setpriv", "--bounding-set=-net_admin,-sys_admin", BIN, "run", "--nodes", "2",
             "--ip", "--no-dashboard", "--duration", "1", "--mode", "virtual"],
            capture_output=True, text=True, timeout=60)
        self.assertEqual(run.returncode, 2, run.stdout + run.stderr)
        self.assertIn("CAP_NET_ADMIN", run.stderr)
        self.assertIn("root", run.stderr)


if __name__ == "__main__":
    unittest.main()
