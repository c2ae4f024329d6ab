"""Faults with nothing lost (issue 15, item 4), part two: the resources around
a run. Out of descriptors (`ulimit -n 64` and 200 connections), a port that
another program holds, and a disk that fills under the pcap trace and the
SigMF recording. The run survives what it can survive, says clearly what it
cannot, and its books balance (fault_checks.py, harness.assert_accounted)."""

import os
import resource
import socket
import subprocess
import tempfile
import time
import unittest

from fault_checks import count_lines, fd_count, node_in, wait_for, wait_settled
from harness import (BIN, LOAD_TOLERANT, Emulator, ExternalSamplesNode, assert_accounted,
                     child_pid, pick_port_bases, ports_free, scenario_yaml, wait_for_output,
                     without_ubsan_vptr_checks)

DESCRIPTOR_LIMIT = 64


def limited(emu, nofile):
    """The emulator, started as under `ulimit -n nofile` (env and prlimit exec
    the command, so emu.proc.pid is the emulator itself), without UBSan's vptr
    check, which cannot work without a free descriptor."""
    emu.args = ["prlimit", f"--nofile={nofile}:{nofile}", "--", *emu.args]
    return without_ubsan_vptr_checks(emu)


def exchange(a1, a2, tag, timeout=30.0):
    """A frame from 1 to 2, then one from 2 to 1 (one at a time: together they
    would collide), each sent again until it arrives; True if both did in time."""
    deadline = time.monotonic() + timeout
    for sender, receiver, src, dst in ((a1, a2, 1, 2), (a2, a1, 2, 1)):
        payload = b"to %d " % dst + tag
        while True:
            if time.monotonic() > deadline:
                return False
            sender.send(src, dst, payload)
            if (src, dst, payload) in receiver.receive(1, timeout=1.0):
                break
    return True


class DescriptorLimitTest(unittest.TestCase):
    def test_listeners_accept_again_after_200_connections_under_ulimit_64(self):
        # Node 3 is a "samples" program's: its socket is the third listener.
        nodes = {1: (0, 0, 10), 2: (6, 0, 10), 3: (3, 3, 10)}
        with limited(Emulator(nodes, extra_yaml="external: {start_timeout_s: 0}\n",
                              node_phy={3: {"type": "external"}}, args=LOAD_TOLERANT),
                     DESCRIPTOR_LIMIT) as emu:
            pid = emu.proc.pid
            self.assertEqual(resource.prlimit(pid, resource.RLIMIT_NOFILE),
                             (DESCRIPTOR_LIMIT, DESCRIPTOR_LIMIT))
            # Every path once while descriptors are plenty: agents that send,
            # are answered and leave; dashboard requests, and connections that
            # leave without one.
            a1, a2 = emu.agent(1), emu.agent(2)
            self.assertTrue(exchange(a1, a2, b"before"))
            a1.close()
            a2.close()
            for _ in range(3):
                emu.stats()
                socket.create_connection(("127.0.0.1", emu.dashboard_port())).close()
            wait_for(lambda: not emu.agent_connected(1) and not emu.agent_connected(2), 30,
                     "the agents' close")
            baseline = fd_count(pid)
            socket_path = f"/tmp/rfsitl-{emu.net_base}.sock"
            emfile = "{}: cannot accept a connection (Too many open files)"
            held = []
            try:
                # The dashboard's sessions fill the table (held only briefly:
                # an idle HTTP session times out after 30 s, a path not taken
                # above) ...
                for _ in range(60):
                    held.append(socket.create_connection(("127.0.0.1", emu.dashboard_port())))
                self.assertTrue(wait_for_output(emu, emfile.format("dashboard"), timeout=30))
                # ... so the net ports and the external socket find it full.
                for port in [emu.net_port(1)] * 70 + [emu.net_port(2)] * 70:
                    held.append(socket.create_connection(("127.0.0.1", port), timeout=10))
                for _ in range(40):
                    u = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
                    u.connect(socket_path)
                    held.append(u)
                for node in (1, 2):
                    what = emfile.format(f"net port {emu.net_port(node)}")
                    self.assertTrue(wait_for_output(emu, what, timeout=30), what)
                self.assertGreaterEqual(fd_count(pid), DESCRIPTOR_LIMIT - 2)
            finally:
                for s in held:
                    s.close()
            # Once the descriptors are free again, every listener accepts:
            # agents connect and exchange frames ...
            a1, a2 = emu.agent(1), emu.agent(2)
            self.assertTrue(exchange(a1, a2, b"after"), "no frames after the shortage")
            # ... the dashboard answers ...
            wait_for(lambda: self.answers(emu), 30, "the dashboard to answer /api/stats")
            # ... and a program joins on the external socket and runs.
            ext = ExternalSamplesNode(socket_path, 3)
            try:
                wait_for(lambda: ext.ticks >= 20, 30, "the external program to run")
            finally:
                ext.close()
            a1.close()
            a2.close()
            wait_for(lambda: fd_count(pid) <= baseline + 3, 30,
                     lambda: f"descriptors back near {baseline} (now {fd_count(pid)})")
            wait_settled(emu)
            summary = emu.stop()
        assert_accounted(self, summary)
        self.assertGreaterEqual(node_in(summary, 1)["delivered"], 2)
        self.assertEqual(summary["external"]["nodes"][0]["joins"], 1)

    @staticmethod
    def answers(emu):
        try:
            return "nodes" in emu.stats()
        except OSError:
            return False


def leftover_processes(*needles):
    """Processes (other than this one) whose command line holds any needle."""
    found = []
    for pid in os.listdir("/proc"):
        if not pid.isdigit() or int(pid) == os.getpid():
            continue
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                cmdline = f.read().decode(errors="replace").replace("\0", " ")
        except OSError:
            continue
        if any(n in cmdline for n in needles):
            found.append(f"{pid}: {cmdline}")
    return found


class PortInUseTest(unittest.TestCase):
    NODES = {1: (0, 0, 10), 2: (6, 0, 10)}

    def run_blocked(self, blocked_port, *args):
        """Runs rfsitl (split architecture: children and a socket to leave
        behind) while another program listens on blocked_port. Returns the
        completed process, the seconds it took, and the run's ports."""
        net_base, loc_base = pick_port_bases(list(self.NODES))
        blocked_port = blocked_port(net_base, loc_base)
        blocker = socket.socket()
        blocker.bind(("127.0.0.1", blocked_port))
        blocker.listen()
        with tempfile.TemporaryDirectory(prefix="rfsitl-it-") as d:
            scenario = os.path.join(d, "scenario.yaml")
            with open(scenario, "w") as f:
                f.write(scenario_yaml(self.NODES))
            try:
                started = time.monotonic()
                summary, trace = os.path.join(d, "summary.json"), os.path.join(d, "t.pcapng")
                r = subprocess.run([BIN, "run", scenario, "--net-base", str(net_base),
                                    "--loc-base", str(loc_base), "--arch", "split",
                                    "--stats-interval", "0", "--summary-json", summary,
                                    "--pcap", trace, *args],
                                   capture_output=True, text=True, timeout=60)
                took = time.monotonic() - started
            finally:
                blocker.close()
            # Nothing left behind: no child, no socket file, every port free.
            socket_path = f"/tmp/rfsitl-{net_base}.sock"
            self.assertEqual(leftover_processes(socket_path, scenario), [])
            self.assertIsNone(child_pid(socket_path, 1))
            self.assertFalse(os.path.exists(socket_path), socket_path)
            # No empty summary or trace that could pass for a run's results.
            self.assertFalse(os.path.exists(summary), "summary left behind")
            self.assertFalse(os.path.exists(trace), "trace left behind")
        ports = [b + 10 * n for b in (net_base, loc_base) for n in self.NODES]
        self.assertTrue(ports_free(ports), ports)
        self.assertNotIn("rfsitl: ready", r.stdout)
        self.assertLess(took, 20, "a port in use must fail fast")
        return r, blocked_port

    def test_net_port_in_use_fails_fast_naming_the_port_and_its_node(self):
        r, port = self.run_blocked(lambda net, loc: net + 20)
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertRegex(r.stderr, rf"net port {port} of node 2 on 127\.0\.0\.1: "
                                   r"Address already in use")

    def test_location_port_in_use_fails_fast_naming_the_port_and_its_node(self):
        r, port = self.run_blocked(lambda net, loc: loc + 10)
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertRegex(r.stderr, rf"location port {port} of node 1\b.*Address already in use")

    def test_dashboard_port_in_use_fails_fast_naming_it(self):
        # A port the user chose is not swapped for another: the run refuses.
        holder = socket.socket()
        holder.bind(("127.0.0.1", 0))
        free = holder.getsockname()[1]
        holder.close()
        r, port = self.run_blocked(lambda net, loc: free, "--dashboard-port", str(free))
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn(f"dashboard port {port} on 127.0.0.1: Address already in use", r.stderr)


class FullDiskTest(unittest.TestCase):
    def test_full_disk_stops_pcap_and_sigmf_with_an_error_and_the_run_goes_on(self):
        if os.geteuid() != 0:
            self.skipTest("mounting a small tmpfs (the full disk) needs root")
        mnt = tempfile.mkdtemp(prefix="rfsitl-full-disk-")
        mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", mnt],
                                 capture_output=True, text=True)
        if mounted.returncode != 0:
            os.rmdir(mnt)
            self.skipTest("cannot mount a tmpfs here: " + mounted.stderr.strip())
        try:
            self.fill_the_disk(mnt)
        finally:
            subprocess.run(["umount", mnt], check=True)
            os.rmdir(mnt)

    def fill_the_disk(self, mnt):
        pcap, iq = os.path.join(mnt, "trace.pcapng"), os.path.join(mnt, "iq")
        nodes = {1: (0, 0, 10), 2: (10, 0, 10)}
        # Every frame event traced into 256 KiB: the trace fills the disk.
        # Then, from 2 virtual seconds on, both receivers' I/Q is recorded
        # (8 MB per virtual second each) onto the full disk.
        errors = (f"pcap trace {pcap}: write failed: No space left on device; trace stopped",
                  f"sigmf: writing {iq}/node1.sigmf-data failed: No space left on device; "
                  "recording stopped",
                  f"sigmf: writing {iq}/node2.sigmf-data failed: No space left on device; "
                  "recording stopped")
        with Emulator(nodes, args=["--pcap", pcap, "--sigmf", iq,
                                   "--sigmf-start", "2", "--sigmf-duration", "1000"]) as emu:
            a1, a2 = emu.agent(1), emu.agent(2)
            sent = delivered = 0
            deadline = time.monotonic() + 60
            while not all(count_lines(emu, e) for e in errors):
                self.assertLess(time.monotonic(), deadline, "the disk never filled:\n"
                                + "".join(emu.output))
                a1.send(1, 2, b"%06d" % sent + bytes(1994))
                sent += 1
                delivered += len(a2.receive(1, timeout=10))
            self.assertEqual(delivered, sent, "frames lost while the disk filled")
            # The run goes on: frames keep arriving with the disk full.
            for i in range(20):
                a1.send(1, 2, b"after %d" % i)
                self.assertEqual(a2.receive(1, timeout=30), [(1, 2, b"after %d" % i)])
            wait_settled(emu)
            summary = emu.stop()  # exit status 0, or it raises
        assert_accounted(self, summary)
        self.assertEqual(node_in(summary, 1)["delivered"], sent + 20)
        # The summary says the recordings stopped, and why.
        # Events of about 2 KB until the 256 KiB were full (about 120).
        self.assertGreater(summary["pcap"]["events_written"], 80)
        self.assertEqual((summary["pcap"]["path"], summary["pcap"]["stopped"],
                          summary["pcap"]["error"]),
                         (pcap, True, "write failed: No space left on device"))
        full = "No space left on device"
        self.assertEqual([(n["id"], n["stopped"], n["error"]) for n in summary["sigmf"]["nodes"]],
                         [(1, True, full), (2, True, full)])
        output = "".join(emu.output)
        self.assertIn(f"rfsitl: pcap trace {pcap}: ", output)
        self.assertIn("; stopped early: write failed: No space left on device", output)
        self.assertIn(f"rfsitl: SigMF recording {iq}/node2.sigmf-data stopped early", output)
        print(f"full disk: {sent} frames until both recordings stopped, "
              f"{summary['pcap']['events_written']} frame events traced")


if __name__ == "__main__":
    unittest.main()
