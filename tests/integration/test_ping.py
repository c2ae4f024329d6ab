"""The ping tool (the paper's COM manager) against the real emulator: its last
line has the contract format and its figures agree with its CSV."""

import csv
import os
import re
import statistics
import subprocess
import tempfile
import time
import unittest

from harness import BIN, Emulator, assert_accounted

LAST_LINE = re.compile(
    r"^rtt_ms mean=(\S+) p10=(\S+) p50=(\S+) p90=(\S+) lost=(\d+)/(\d+)$")


class PingTest(unittest.TestCase):
    def test_ping_reports_rtts_consistent_with_its_csv(self):
        with Emulator({1: (0, 0, 10), 2: (5, 0, 10), 3: (0, 5, 10)}) as emu, \
                tempfile.TemporaryDirectory() as d:
            csv_path = os.path.join(d, "rtt.csv")
            r = subprocess.run(
                [BIN, "ping", "--src", "1", "--dst", "3", "--count", "20", "--timeout", "10",
                 "--net-base", str(emu.net_base), "--csv", csv_path],
                capture_output=True, text=True, timeout=120)
            self.assertEqual(r.returncode, 0, r.stderr)
            last = r.stdout.strip().splitlines()[-1]
            m = LAST_LINE.match(last)
            self.assertIsNotNone(m, last)
            with open(csv_path) as f:
                rows = list(csv.DictReader(f))
            emu.wait_settled()
            summary = emu.stop()
        self.assertEqual(len(rows), 20)
        rtts = [float(row["rtt_ms"]) for row in rows if row["status"] == "ok"]
        self.assertEqual(int(m.group(5)), 20 - len(rtts))
        self.assertEqual(int(m.group(6)), 20)
        self.assertGreaterEqual(len(rtts), 18, "in range and alone on the air: nearly all arrive")
        self.assertAlmostEqual(float(m.group(1)), statistics.mean(rtts), delta=0.01)
        self.assertAlmostEqual(float(m.group(3)), statistics.median(rtts), delta=0.01)
        # Nothing can beat the air time: with the default GMSK at 1 Msps an 80-byte
        # frame is 1704 samples and an 8-byte ack 552, 2.256 ms together.
        self.assertGreater(min(rtts), 2.25)
        # Node 3 answered every ping it heard; node 1 sent every one.
        self.assertEqual(emu.node(1)["handed_in"], 20)
        assert_accounted(self, summary)

    def ping(self, emu, *args):
        return subprocess.run(
            [BIN, "ping", "--net-base", str(emu.net_base), "--connect-timeout", "30", *args],
            capture_output=True, text=True, timeout=120)

    def test_ping_refuses_to_displace_a_connected_agent(self):
        with Emulator({1: (0, 0, 10), 2: (5, 0, 10)}) as emu:
            agent = emu.agent(2)
            emu.wait_for_agent(2)
            r = self.ping(emu, "--src", "1", "--dst", "2", "--count", "1")
            self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
            self.assertIn("node 2's net port has an agent connected", r.stderr)
            self.assertIn("--take-over", r.stderr)
            emu.agent(1).send(1, 2, b"agent kept")
            self.assertEqual(agent.receive(1), [(1, 2, b"agent kept")])
            emu.stop()

    def test_take_over_replaces_the_agent_and_the_emulator_logs_it(self):
        with Emulator({1: (0, 0, 10), 2: (5, 0, 10)}) as emu:
            agent = emu.agent(2)
            emu.wait_for_agent(2)
            r = self.ping(emu, "--src", "1", "--dst", "2", "--count", "3", "--take-over",
                          "--timeout", "10")
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            self.assertTrue(agent.closed_by_peer())
            emu.stop()
        self.assertTrue(any("asked to take over" in line for line in emu.output), emu.output)

    def test_exit_status_is_1_when_nothing_comes_back(self):
        # Node 2 has no position, so no link: every ping is lost.
        with Emulator({1: (0, 0, 10), 2: None}) as emu:
            r = self.ping(emu, "--src", "1", "--dst", "2", "--count", "3", "--timeout", "0.2")
            emu.wait_settled()  # the pings it gave up on may still be on the air
            summary = emu.stop()
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertIn("lost=3/3", r.stdout)
        self.assertIn("no acknowledgement came back", r.stderr)
        assert_accounted(self, summary)

    def test_size_beyond_the_emulators_limit_is_refused_before_sending(self):
        with Emulator({1: (0, 0, 10), 2: (5, 0, 10)}) as emu:
            r = self.ping(emu, "--src", "1", "--dst", "2", "--count", "1", "--size", "2049")
            summary = emu.stop()
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("--size 2049 is more than node 1 accepts (phy.max_payload_bytes = 2048)",
                      r.stderr)
        self.assertEqual(emu.node(1)["handed_in"], 0)

    def test_a_node_not_in_the_run_is_named_at_once(self):
        # The old ping retried the missing node's port for the whole connect
        # timeout (30 s here) and then said "Connection refused".
        with Emulator({1: (0, 0, 10), 2: (5, 0, 10)}) as emu:
            for args, missing in ((("--src", "1", "--dst", "9"), 9),
                                  (("--src", "9", "--dst", "2"), 9)):
                started = time.monotonic()
                r = self.ping(emu, *args, "--count", "1")
                elapsed = time.monotonic() - started
                self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
                self.assertIn(f"node {missing} is not in this run (nodes: 1, 2)", r.stderr)
                self.assertLess(elapsed, 15, "named well before the 30 s connect timeout")
            summary = emu.stop()
        self.assertEqual(emu.node(1)["handed_in"], 0)
        self.assertEqual(emu.node(2)["handed_in"], 0)
        assert_accounted(self, summary)


if __name__ == "__main__":
    unittest.main()
