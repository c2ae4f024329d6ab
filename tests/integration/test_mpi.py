"""A distributed run (`mpirun -n K rfsitl run ...`, Open MPI, oversubscribed on
this machine) gives the per-node counters of one process: a seeded
virtual-time run with traffic, collisions, moving nodes and frames decided by
the noise, also with every transceiver in a child process (--arch split) and
with a program in the "samples" role as one node (it hears and sends the same
samples whichever rank serves it).
Also: ranks given different scenarios are refused, and a real-time run with
IP on every node carries pings between nodes of different ranks (root only).
"""

import cmath
import glob
import json
import os
import random
import re
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

from harness import (ARRIVAL_S, BIN, LOAD_TOLERANT, ExternalSamplesNode, assert_accounted,
                     pack_samples, pick_port_bases)
from test_ip import ip_tools_missing, netns_names, remove_netns, wait_reachable

MPIRUN = shutil.which("mpirun")
# As root (CI), Open MPI wants both flags; oversubscribe: more ranks than cores.
MPI_FLAGS = ["--oversubscribe", "--allow-run-as-root", "--mca", "btl", "self,vader,tcp",
             "--bind-to", "none"]
HERE = os.path.dirname(os.path.abspath(__file__))
# Open MPI keeps memory until exit on purpose; with its components kept loaded
# their frames have names, which lsan_openmpi.supp names (ASan builds only).
MPI_ENV = dict(os.environ, OMPI_MCA_mca_base_component_disable_dlclose="1",
               LSAN_OPTIONS=f"suppressions={HERE}/lsan_openmpi.supp:print_suppressions=0",
               ASAN_OPTIONS=os.environ.get("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=1")
               + ":fast_unwind_on_malloc=0")
SCENARIO = """name: mpi-test
seed: 11
time: {mode: virtual, duration_s: 1.0, tick_samples: 1000}
channel: {noise_power_db: -93}
engine: {mobility_update_s: 0.01}
nodes:
  - {id: 1, position: {x: 0, y: 0, z: 10}}
  - {id: 2, position: {x: 30, y: 0, z: 10}}
  - {id: 3, mobility: {type: orbit, centre_x_m: 20, radius_m: 40, speed_mps: 30, altitude_m: 10}}
  - {id: 4, position: {x: 25, y: 25, z: 10}}
  - {id: 5, mobility: {type: orbit, centre_x_m: -10, radius_m: 60, speed_mps: 20, altitude_m: 20, phase_rad: 2}}
  - {id: 6, position: {x: 0, y: 40, z: 10}}
traffic:
  - {at_s: 0.01, src: 1, dst: 2, size_bytes: 80, repeat: 60, interval_s: 0.013}
  - {at_s: 0.015, src: 4, dst: 3, size_bytes: 120, repeat: 60, interval_s: 0.011}
  - {at_s: 0.02, src: 2, dst: 4, size_bytes: 60, repeat: 60, interval_s: 0.0097}
  - {at_s: 0.03, src: 3, dst: 255, size_bytes: 40, repeat: 40, interval_s: 0.017}
  - {at_s: 0.01, src: 5, dst: 6, size_bytes: 80, repeat: 60, interval_s: 0.013}
  - {at_s: 0.012, src: 6, dst: 1, size_bytes: 80, repeat: 60, interval_s: 0.015}
"""
COMPARED = ("handed_in", "transmitted", "delivered", "lost", "received", "rx_crc_failures")
NODES = {i: None for i in range(1, 7)}


def write(d, text, name="s.yaml"):
    path = os.path.join(d, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def run(d, name, ranks, scenario=SCENARIO, extra=()):
    """ranks 0: one process without mpirun. Returns (process, summary or None)."""
    net_base, loc_base = pick_port_bases(NODES)
    path = write(d, scenario)
    summary = os.path.join(d, f"{name}.json")
    cmd = [BIN, "run", path, "--net-base", str(net_base), "--loc-base", str(loc_base),
           "--no-dashboard", "--summary-json", summary, *extra]
    if ranks > 0:
        cmd = [MPIRUN, "-n", str(ranks), *MPI_FLAGS, *cmd]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600, env=MPI_ENV)
    if not os.path.exists(summary):
        return r, None
    with open(summary) as f:
        return r, json.load(f)


class MpiRun:
    """A real-time `mpirun ...` started for a test: its output in a file of
    `d`, in a session of its own so that stop() (a cleanup of the test) ends
    mpirun and any rank it left behind. Waits for rank 0's "rfsitl: ready"."""

    def __init__(self, test, d, cmd, ready_within=120, env=None):
        self.test = test
        self.log = open(os.path.join(d, "out.log"), "w+b")
        test.addCleanup(self.log.close)
        self.proc = subprocess.Popen(cmd, stdout=self.log, stderr=subprocess.STDOUT,
                                     env=env or MPI_ENV, start_new_session=True)
        test.addCleanup(self.stop)
        deadline = time.monotonic() + ready_within
        while "rfsitl: ready" not in self.output():
            test.assertIsNone(self.proc.poll(), self.output()[-3000:])
            test.assertLess(time.monotonic(), deadline, self.output()[-3000:])
            time.sleep(0.1)

    def output(self):
        # pread: the ranks write through the same open file, whose offset stays
        # theirs; and it reads even after the test's folder is gone.
        fd = self.log.fileno()
        return os.pread(fd, os.fstat(fd).st_size, 0).decode(errors="replace")

    def stop(self):
        """SIGTERM to mpirun (it forwards it to the ranks), SIGKILL to what is
        left after 60 s; returns the output."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(60)
            except subprocess.TimeoutExpired:
                pass
        try:
            os.killpg(self.proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.proc.wait()
        return self.output()


@unittest.skipIf(MPIRUN is None, "Open MPI's mpirun is not installed (scripts/setup.sh)")
class MpiTest(unittest.TestCase):
    def test_ranks_give_the_counters_of_one_process(self):
        with tempfile.TemporaryDirectory() as d:
            r, one = run(d, "one", 0)
            self.assertEqual(r.returncode, 0, r.stderr[-2000:])
            assert_accounted(self, one)
            total = lambda key: sum(n[key] for n in one["nodes"])
            lost = lambda reason: sum(n["lost"][reason] for n in one["nodes"])
            self.assertGreater(total("delivered"), 30)
            self.assertGreater(lost("collision"), 0)
            self.assertGreater(lost("below_sensitivity") + lost("decode_failure"), 10)
            for ranks in (2, 4):
                with self.subTest(ranks=ranks):
                    r, many = run(d, f"ranks{ranks}", ranks)
                    self.assertEqual(r.returncode, 0, r.stdout[-3000:] + r.stderr[-3000:])
                    self.assertIn(f"distributed run on {ranks} ranks", r.stdout)
                    self.assertEqual(many["distributed"]["ranks"], ranks)
                    self.assertEqual(len(many["distributed"]["per_rank"]), ranks)
                    # Every rank owns some node, and every node one rank.
                    self.assertEqual(sorted(set(many["distributed"]["owner_rank"])),
                                     list(range(ranks)))
                    for a, b in zip(one["nodes"], many["nodes"]):
                        for key in COMPARED:
                            self.assertEqual(a[key], b[key], f"node {a['id']} {key}")
                    # Something crossed between the ranks.
                    self.assertTrue(all(p["exchanged_bytes"] > 0
                                        for p in many["distributed"]["per_rank"]))
                    # The banner puts each node's ports on its own rank's host.
                    owners = many["distributed"]["owner_rank"]
                    for node, owner in zip(many["nodes"], owners):
                        line = re.search(rf"^  node +{node['id']}: .*$", r.stdout, re.M)
                        self.assertIsNotNone(line, r.stdout[-3000:])
                        self.assertNotIn("another rank", line.group(0))
                        if owner:
                            self.assertIn(f" on rank {owner} ", line.group(0))
                        else:
                            self.assertIn("location 127.0.0.1:", line.group(0))

    def test_ranks_with_different_scenarios_are_refused(self):
        with tempfile.TemporaryDirectory() as d:
            other = write(d, SCENARIO.replace("seed: 11", "seed: 12"), "other.yaml")
            net_base, loc_base = pick_port_bases(NODES)
            common = ["--net-base", str(net_base), "--loc-base", str(loc_base), "--no-dashboard"]
            # MPMD: rank 0 runs s.yaml, rank 1 other.yaml.
            path = write(d, SCENARIO)
            r = subprocess.run([MPIRUN, *MPI_FLAGS, "-n", "1", BIN, "run", path, *common, ":",
                                "-n", "1", BIN, "run", other, *common],
                               capture_output=True, text=True, timeout=120, env=MPI_ENV)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("rank 1 was given another scenario or other flags than rank 0",
                          r.stderr)

    def test_split_transceivers_on_two_ranks_give_the_counters_of_one_process(self):
        # --arch split: every node's PHY in an `rfsitl node` child, each rank
        # starting its own nodes' children on a socket of its own.
        with tempfile.TemporaryDirectory() as d:
            r, one = run(d, "one", 0)
            self.assertEqual(r.returncode, 0, r.stderr[-2000:])
            r, split = run(d, "split2", 2, extra=["--arch", "split"])
            self.assertEqual(r.returncode, 0, r.stdout[-3000:] + r.stderr[-3000:])
            for a, b in zip(one["nodes"], split["nodes"]):
                for key in COMPARED:
                    self.assertEqual(a[key], b[key], f"node {a['id']} {key}")
            ext = split["external"]
            self.assertEqual([n["id"] for n in ext["nodes"]], list(range(1, 7)))
            self.assertTrue(all(n["joins"] >= 1 and n["role"] == "transceiver"
                                for n in ext["nodes"]), ext)
            self.assertEqual(len(ext["sockets"]), 2)
            self.assertTrue(all(p.endswith(f".rank{k}.sock") for k, p in enumerate(ext["sockets"])),
                            ext["sockets"])

SAMPLES_SCENARIO = """name: mpi-samples
seed: 5
time: {mode: virtual, duration_s: 0.4, tick_samples: 1000}
nodes:
  - {id: 1, position: {x: 0, y: 0, z: 10}}
  - {id: 2, position: {x: 20, y: 0, z: 10}}
  - {id: 3, position: {x: 10, y: 3, z: 10}, phy: {type: external}}
  - {id: 4, position: {x: 0, y: 20, z: 10}}
traffic:
  - {at_s: 0.005, src: 1, dst: 2, size_bytes: 80, repeat: 30, interval_s: 0.011}
  - {at_s: 0.007, src: 4, dst: 1, size_bytes: 60, repeat: 30, interval_s: 0.013}
"""
SAMPLES_TICK = 1000


class Jammer:
    """Node 3: noise bursts in three ticks of every seven, the same bursts on
    every run (seeded), and a record of what it heard."""

    def __init__(self, socket_path):
        rng = random.Random(5)
        burst = pack_samples([0.3 * cmath.exp(2j * cmath.pi * rng.random())
                              for _ in range(SAMPLES_TICK)])
        self.node = ExternalSamplesNode(socket_path, 3, lambda tick: burst if tick % 7 < 3 else b"")


def run_with_jammer(d, name, ranks, net_base, loc_base):
    """The samples scenario with node 3 a Jammer on the socket of the rank
    that serves it (found by its name). Returns (process, summary, jammer)."""
    path = write(d, SAMPLES_SCENARIO, f"{name}.yaml")
    summary = os.path.join(d, f"{name}.json")
    cmd = [BIN, "run", path, "--net-base", str(net_base), "--loc-base", str(loc_base),
           "--no-dashboard", "--summary-json", summary]
    if ranks > 0:
        cmd = [MPIRUN, "-n", str(ranks), *MPI_FLAGS, *cmd]
    pattern = f"/tmp/rfsitl-{net_base}.rank*.sock" if ranks else f"/tmp/rfsitl-{net_base}.sock"
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=MPI_ENV)
    jammer = None
    try:
        deadline = time.monotonic() + 120
        while not glob.glob(pattern):
            if proc.poll() is not None or time.monotonic() > deadline:
                raise AssertionError(f"no socket {pattern}: {proc.communicate()[0][-3000:]}")
            time.sleep(0.05)
        jammer = Jammer(glob.glob(pattern)[0])
        out = proc.communicate(timeout=300)[0]
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        if jammer:
            jammer.node.close()
    if not os.path.exists(summary):
        return proc, out, None, jammer
    with open(summary) as f:
        return proc, out, json.load(f), jammer


@unittest.skipIf(MPIRUN is None, "Open MPI's mpirun is not installed (scripts/setup.sh)")
class MpiSamplesProgramTest(unittest.TestCase):
    def test_a_samples_program_on_either_rank_gives_the_run_of_one_process(self):
        with tempfile.TemporaryDirectory() as d:
            net_base, loc_base = pick_port_bases({i: None for i in range(1, 5)})
            proc, out, one, jam_one = run_with_jammer(d, "one", 0, net_base, loc_base)
            self.assertEqual(proc.returncode, 0, out[-3000:])
            proc, out, two, jam_two = run_with_jammer(d, "two", 2, net_base, loc_base)
            self.assertEqual(proc.returncode, 0, out[-3000:])
        # The bursts collide with some frames and not others.
        lost = sum(n["lost"]["collision"] + n["lost"]["decode_failure"] for n in one["nodes"])
        self.assertGreater(lost, 0)
        self.assertGreater(sum(n["delivered"] for n in one["nodes"]), 10)
        for a, b in zip(one["nodes"], two["nodes"]):
            for key in COMPARED:
                self.assertEqual(a[key], b[key], f"node {a['id']} {key}")
        # The program heard the same samples, tick by tick, from another rank's
        # transmitters as from the same process's.
        self.assertGreater(len(jam_one.node.rx_power), 10)
        self.assertEqual(jam_one.node.rx_power, jam_two.node.rx_power)
        self.assertEqual(jam_two.node.discontinuities, 0)
        self.assertEqual([n["id"] for n in two["external"]["nodes"]], [3])
        self.assertEqual(sum(s is not None for s in two["external"]["sockets"]), 1)


# Every tick needs both ranks scheduled, so on a loaded machine the run uses
# the harness's load-tolerant ticks (4000 samples at a tenth of real time: 25
# exchanges a wall second), without a MAC (csma's slots would be whole 4 ms
# ticks, and a ping's wall-clock wait is 1 s).
SQUARE = """nodes:
  - {id: 1, position: {x: 0, y: 0, z: 10}}
  - {id: 2, position: {x: 10, y: 0, z: 10}}
  - {id: 3, position: {x: 0, y: 10, z: 10}}
  - {id: 4, position: {x: 10, y: 10, z: 10}}
"""  # four nodes 10 m apart, in real time
IP_SCENARIO = "name: mpi-ip-test\ntime: {mode: realtime}\nip: {enabled: true}\n" + SQUARE


@unittest.skipIf(MPIRUN is None, "Open MPI's mpirun is not installed (scripts/setup.sh)")
@unittest.skipIf(ip_tools_missing(), ip_tools_missing() or "")
class MpiIpTest(unittest.TestCase):
    def test_real_time_ip_nodes_on_two_ranks_reach_each_other(self):
        # Two ranks, each serving two nodes' namespaces; rank 0 lists all four.
        # Node 1 pings every other node, so frames cross between the ranks'
        # TAP interfaces both ways, in real time (a barrier per tick).
        with tempfile.TemporaryDirectory() as d:
            net_base, loc_base = pick_port_bases({i: None for i in range(1, 5)})
            prefix = f"rfsitl-{net_base}"
            self.addCleanup(remove_netns, prefix)
            summary = os.path.join(d, "ip.json")
            run = MpiRun(self, d, [MPIRUN, "-n", "2", *MPI_FLAGS, BIN, "run",
                                   write(d, IP_SCENARIO), "--net-base", str(net_base),
                                   "--loc-base", str(loc_base), "--no-dashboard",
                                   "--summary-json", summary, *LOAD_TOLERANT])
            banner = run.output()
            for i in range(1, 5):
                self.assertIn(f"netns {prefix}-{i}", banner)
            self.assertEqual(netns_names(prefix), [f"{prefix}-{i}" for i in range(1, 5)])
            for i in (2, 3, 4):
                wait_reachable(f"{prefix}-1", f"10.77.0.{i}", timeout=3 * ARRIVAL_S)
            # Open MPI 4.1's mpirun exits 1 after it forwarded a SIGTERM; the
            # ranks' own ends are in its output (a rank that failed is named).
            text = run.stop()
            self.assertNotIn("non-zero status", text)
            self.assertNotIn("exited on signal", text)
            self.assertEqual(text.count("rfsitl: SIGTERM received, shutting down"), 2, text[-3000:])
            self.assertIn("rfsitl summary:", text)
            with open(summary) as f:
                j = json.load(f)
        owners = j["distributed"]["owner_rank"]
        self.assertEqual(sorted(set(owners)), [0, 1])
        self.assertEqual([n["id"] for n in j["ip"]["nodes"]], [1, 2, 3, 4])
        self.assertEqual(netns_names(prefix), [], "namespaces left after the run")
        # Replies came from both ranks' nodes: every node delivered frames.
        for n in j["nodes"]:
            self.assertGreater(n["delivered"], 0, n)
        for rank in j["distributed"]["per_rank"]:
            self.assertGreater(rank["wall_s"], 0)


DASHBOARD_SCENARIO = "name: mpi-dashboard-test\ntime: {mode: realtime}\n" + SQUARE + """traffic:
  - {at_s: 0.02, src: 1, dst: 2, size_bytes: 60, repeat: 100000, interval_s: 0.05}
  - {at_s: 0.03, src: 4, dst: 3, size_bytes: 60, repeat: 100000, interval_s: 0.05}
"""


@unittest.skipIf(MPIRUN is None, "Open MPI's mpirun is not installed (scripts/setup.sh)")
class MpiDashboardTest(unittest.TestCase):
    def test_rank_zero_s_dashboard_shows_the_nodes_of_every_rank(self):
        # Node 2 is rank 1's, and so are its decodes of node 1's frames: rank
        # 0's dashboard shows them (link counts, constellation, spectrum) from
        # what rank 1's live view shares.
        from test_all_faces_at_once import WebSocketViewer
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)  # after the run's stop(): cleanups run last first
        d = tmp.name
        net_base, loc_base = pick_port_bases({i: None for i in range(1, 5)})
        run = MpiRun(self, d, [MPIRUN, "-n", "2", *MPI_FLAGS, BIN, "run",
                               write(d, DASHBOARD_SCENARIO), "--net-base", str(net_base),
                               "--loc-base", str(loc_base), "--dashboard-port", "0",
                               *LOAD_TOLERANT])
        text = run.output()
        self.assertIn("rank 1: node(s) 2 4", text)
        port = int(re.search(r"rfsitl: dashboard http://[^/]*:(\d+)/", text).group(1))
        viewer = WebSocketViewer(port)
        self.addCleanup(viewer.close)
        viewer.send({"type": "watch", "node": 2})

        def links_to_2():
            snaps = viewer.of_type("snapshot")
            if not snaps:
                return 0
            links = snaps[-1]["links"]
            return links["received"][0 * links["n"] + 1]  # node 1 -> node 2

        deadline = time.monotonic() + 3 * ARRIVAL_S
        while not (links_to_2() > 0 and viewer.of_type("spectrum")
                   and any(m["node"] == 2 for m in viewer.of_type("constellation"))):
            self.assertLess(time.monotonic(), deadline,
                            f"links to node 2 {links_to_2()}, "
                            f"{len(viewer.of_type('spectrum'))} spectra, constellations of "
                            f"{[m['node'] for m in viewer.of_type('constellation')]}")
            time.sleep(0.1)
        spectrum = viewer.of_type("spectrum")[-1]
        self.assertEqual(spectrum["node"], 2)
        # Counted once: node 2's decodes of node 1's frames (rank 1's)
        # are at most what node 1 sent (rank 0's counter).
        last = viewer.of_type("snapshot")[-1]
        sent = next(n for n in last["nodes"] if n["id"] == 1)["transmitted"]
        self.assertLessEqual(last["links"]["received"][1], sent)
        run.stop()


if __name__ == "__main__":
    unittest.main()
