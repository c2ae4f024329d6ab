"""A distributed run across hosts (`mpirun --hostfile`), on this one machine:
each host is a network namespace this test makes, with its own network stack,
host name and /run, joined to the other by a bridge; Open MPI starts its
daemons there through mpi_netns_agent.sh as it would through ssh, and the
ranks talk over TCP between the hosts only (no shared-memory transport).

- The seeded virtual-time scenario of test_mpi.py gives the per-node counters
  of one process with one rank on each host.
- With IP on every node (real time), each host makes the namespaces of its own
  rank's nodes under its own /run, and node 1 (host a) reaches every other
  node, those on host b included.

Root only (ip netns, bridges); skipped without mpirun, ip or unshare. The
hosts, the bridge and every process in them go at the end, also on failure."""

import json
import os
import re
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

from harness import ARRIVAL_S, BIN, LOAD_TOLERANT, assert_accounted, pick_port_bases
from test_ip import ip_tools_missing
from test_mpi import (COMPARED, IP_SCENARIO, MPI_ENV, MPIRUN, NODES, SCENARIO, MpiRun, run,
                      write)

HERE = os.path.dirname(os.path.abspath(__file__))
# Ranks in network namespaces, started through mpi_netns_agent.sh: once in six
# full-suite runs (2026-11-28, a loaded machine) LeakSanitizer's stop-the-world
# at exit failed there ("LeakSanitizer has encountered a fatal error", no leak
# reported) and aborted a rank after a run whose results were complete. Leaks
# of the same code are checked by test_mpi's ranks (one host) and every
# one-process test; here the exit's leak check is left out.
HOSTS_ENV = dict(MPI_ENV, ASAN_OPTIONS=MPI_ENV["ASAN_OPTIONS"] + ":detect_leaks=0")
AGENT = os.path.join(HERE, "mpi_netns_agent.sh")


def hosts_missing():
    if MPIRUN is None:
        return "Open MPI's mpirun is not installed (scripts/setup.sh)"
    if os.geteuid() != 0:
        return "needs root for ip netns"
    for tool in ("ip", "unshare", "nsenter"):
        if shutil.which(tool) is None:
            return f"{tool} is not installed"
    return None


def sh(*cmd):
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    if r.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)}: {r.stderr.strip()}")
    return r.stdout


class Hosts:
    """Two "hosts", a and b: network namespaces on a bridge of this test's
    own, 10.218.T.0/24 (T from the test's pid). make() returns their names."""

    def __init__(self, test):
        self.test = test
        tag = os.getpid() % 200 + 20
        self.subnet = f"10.218.{tag}.0/24"
        self.bridge = f"rfh{tag}br"
        self.names = [f"rfsitl-host{tag}-{c}" for c in "ab"]
        self.veths = [f"rfh{tag}v{c}" for c in "ab"]
        self.tag = tag

    def make(self):
        self.test.addCleanup(self.remove)
        self.remove()  # a killed earlier run's leftovers
        sh("ip", "link", "add", self.bridge, "type", "bridge")
        sh("ip", "addr", "add", f"10.218.{self.tag}.1/24", "dev", self.bridge)
        sh("ip", "link", "set", self.bridge, "up")
        for i, (name, veth) in enumerate(zip(self.names, self.veths)):
            sh("ip", "netns", "add", name)
            sh("ip", "link", "add", veth, "type", "veth", "peer", "name", "eth0", "netns", name)
            sh("ip", "link", "set", veth, "master", self.bridge, "up")
            sh("ip", "-n", name, "addr", "add", f"10.218.{self.tag}.{i + 2}/24", "dev", "eth0")
            sh("ip", "-n", name, "link", "set", "eth0", "up")
            sh("ip", "-n", name, "link", "set", "lo", "up")
            # mpirun (here, outside both hosts) is reached through the bridge.
            sh("ip", "-n", name, "route", "add", "default", "via", f"10.218.{self.tag}.1")
        return self.names

    def pids(self, name):
        r = subprocess.run(["ip", "netns", "pids", name], capture_output=True, text=True)
        return [int(p) for p in r.stdout.split()]

    def remove(self):
        for name in self.names:
            for pid in self.pids(name):
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            deadline = time.monotonic() + 10
            while self.pids(name) and time.monotonic() < deadline:
                time.sleep(0.05)
            subprocess.run(["ip", "netns", "del", name], capture_output=True)
        subprocess.run(["ip", "link", "del", self.bridge], capture_output=True)
        # The kernel tears a deleted namespace's veth pair down after `ip netns
        # del` returns; a make() right after (the next test, same names) would
        # meet "File exists". Wait until the host ends are gone.
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and any(
                subprocess.run(["ip", "link", "show", veth], capture_output=True).returncode == 0
                for veth in self.veths):
            time.sleep(0.05)

    def mpirun(self, d, ranks_per_host=1):
        """mpirun's command line for one rank per host (the hostfile in d)."""
        hostfile = write(d, "".join(f"{n} slots={ranks_per_host}\n" for n in self.names),
                         "hostfile")
        return [MPIRUN, "-n", str(len(self.names) * ranks_per_host), "--hostfile", hostfile,
                "--allow-run-as-root", "--bind-to", "none", "--display-map",
                "--mca", "plm_rsh_agent", AGENT, "--mca", "routed", "direct",
                "--mca", "oob_tcp_if_include", self.subnet,
                "--mca", "btl_tcp_if_include", self.subnet, "--mca", "btl", "self,tcp"]


def rank_hosts(output):
    """{rank: host} from mpirun's --display-map."""
    hosts, host = {}, None
    for line in output.splitlines():
        m = re.search(r"Data for node: (\S+)", line)
        if m:
            host = m.group(1)
        m = re.search(r"Process OMPI jobid: \[\d+,\d+\] App: \d+ Process rank: (\d+)", line)
        if m:
            hosts[int(m.group(1))] = host
    return hosts


def rfsitl_pid(hosts, name):
    """The rfsitl rank running on host `name`."""
    for pid in hosts.pids(name):
        try:
            with open(f"/proc/{pid}/comm") as f:
                if f.read().strip() == "rfsitl":
                    return pid
        except FileNotFoundError:
            pass
    return None


def on_host(pid, *cmd, timeout=60):
    """Runs cmd in the mount namespace of process pid (its host's /run)."""
    return subprocess.run(["nsenter", "--target", str(pid), "--mount", *cmd],
                          capture_output=True, text=True, timeout=timeout)


@unittest.skipIf(hosts_missing(), hosts_missing() or "")
class MpiHostsTest(unittest.TestCase):
    def shared_dir(self):
        d = tempfile.TemporaryDirectory(dir="/var/tmp", prefix="rfsitl-mpi-hosts-")
        self.addCleanup(d.cleanup)
        return d.name

    def test_one_rank_on_each_host_gives_the_counters_of_one_process(self):
        d = self.shared_dir()  # removed after the hosts and what ran on them
        hosts = Hosts(self)
        a, b = hosts.make()
        r, one = run(d, "one", 0)
        self.assertEqual(r.returncode, 0, r.stderr[-2000:])
        net_base, loc_base = pick_port_bases(NODES)
        summary = os.path.join(d, "hosts.json")
        r = subprocess.run(
            [*hosts.mpirun(d), BIN, "run", write(d, SCENARIO), "--net-base", str(net_base),
             "--loc-base", str(loc_base), "--no-dashboard", "--summary-json", summary],
            capture_output=True, text=True, timeout=600, env=HOSTS_ENV)
        self.assertEqual(r.returncode, 0, r.stdout[-3000:] + r.stderr[-3000:])
        self.assertEqual(rank_hosts(r.stdout), {0: a, 1: b}, r.stdout[-3000:])
        self.assertIn(f"distributed run on 2 ranks (this is rank 0 on {a})", r.stdout)
        self.assertRegex(r.stdout, rf"rank 1: node\(s\) [\d ]+ \(cost [\d.]+\) on {b}\n")
        with open(summary) as f:
            many = json.load(f)
        assert_accounted(self, many)
        self.assertEqual([p["host"] for p in many["distributed"]["per_rank"]], [a, b])
        self.assertEqual(sorted(set(many["distributed"]["owner_rank"])), [0, 1])
        for x, y in zip(one["nodes"], many["nodes"]):
            for key in COMPARED:
                self.assertEqual(x[key], y[key], f"node {x['id']} {key}")
        # Both ranks sent their transmitters' samples over TCP between hosts.
        self.assertTrue(all(p["exchanged_bytes"] > 0 for p in many["distributed"]["per_rank"]))

    @unittest.skipIf(ip_tools_missing(), ip_tools_missing() or "")
    def test_ip_nodes_live_on_their_rank_s_host_and_reach_each_other(self):
        d = self.shared_dir()  # removed after the hosts and what ran on them
        hosts = Hosts(self)
        a, b = hosts.make()
        net_base, loc_base = pick_port_bases({i: None for i in range(1, 5)})
        prefix = f"rfsitl-{net_base}"
        summary = os.path.join(d, "ip.json")
        run = MpiRun(self, d, [*hosts.mpirun(d), BIN, "run", write(d, IP_SCENARIO),
                               "--net-base", str(net_base), "--loc-base", str(loc_base),
                               "--no-dashboard", "--summary-json", summary, *LOAD_TOLERANT],
                     ready_within=3 * ARRIVAL_S, env=HOSTS_ENV)
        owners = {}
        for rank, nodes in re.findall(r"rank (\d): node\(s\) ([\d ]+) \(cost", run.output()):
            for node in nodes.split():
                owners[int(node)] = int(rank)
        self.assertEqual(sorted(owners), [1, 2, 3, 4], run.output()[-3000:])
        pids = {name: rfsitl_pid(hosts, name) for name in (a, b)}
        self.assertTrue(all(pids.values()), f"no rfsitl rank on each host: {pids}")
        # Each host holds exactly its rank's nodes' namespaces, under its own
        # /run; none is in this machine's own /run.
        for rank, name in enumerate((a, b)):
            listed = on_host(pids[name], "ip", "netns", "list").stdout
            mine = sorted(n for n, r in owners.items() if r == rank)
            self.assertEqual(sorted(int(x) for x in re.findall(rf"{prefix}-(\d+)", listed)),
                             mine, f"host {name}: {listed}")
        self.assertNotIn(prefix, sh("ip", "netns", "list"))
        # Node 1 reaches every node, those on the other host included.
        self.assertEqual(owners[1], 0)
        for i in (2, 3, 4):
            deadline = time.monotonic() + 3 * ARRIVAL_S
            while on_host(pids[a], "ip", "netns", "exec", f"{prefix}-1", "ping", "-c", "1",
                          "-W", "1", f"10.77.0.{i}").returncode != 0:
                self.assertLess(time.monotonic(), deadline, f"10.77.0.{i} never answered")
                time.sleep(0.2)  # a ping that fails at once (no route yet) does not spin
        text = run.stop()
        self.assertEqual(text.count("rfsitl: SIGTERM received, shutting down"), 2, text[-3000:])
        with open(summary) as f:
            j = json.load(f)
        self.assertEqual([n["id"] for n in j["ip"]["nodes"]], [1, 2, 3, 4])
        for n in j["nodes"]:
            self.assertGreater(n["delivered"], 0, n)
        # Open MPI's daemons and the ranks end with mpirun.
        for name in (a, b):
            deadline = time.monotonic() + ARRIVAL_S
            while hosts.pids(name) and time.monotonic() < deadline:
                time.sleep(0.1)
            self.assertEqual(hosts.pids(name), [], f"processes left on host {name}")


if __name__ == "__main__":
    unittest.main()
