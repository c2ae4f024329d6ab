"""(e) Every loss and drop is counted with its reason; bad scenarios and busy
ports give clear errors instead of crashes."""

import os
import resource
import socket
import subprocess
import tempfile
import time
import unittest

from harness import (BIN, LOSS_REASONS, Emulator, assert_accounted, pick_port_bases,
                     without_ubsan_vptr_checks)


def node_of(stats, node_id):
    return next(n for n in stats["nodes"] if n["id"] == node_id)


class AccountingTest(unittest.TestCase):
    def test_full_tx_queue_drops_are_counted_and_books_balance(self):
        extra = "phy:\n  tx_queue_frames: 4\n"
        with Emulator({1: (0, 0, 10), 2: (6, 0, 10)}, extra_yaml=extra) as emu:
            a1, a2 = emu.agent(1), emu.agent(2)
            burst = b"".join(bytes([1, 2]) + bytes([i]) * 200 + b"\r\r\n\n" for i in range(40))
            a1.send_raw(burst)
            st = emu.wait_until(lambda st: node_of(st, 1)["handed_in"] == 40
                                and node_of(st, 1)["pending"] == 0, what="every frame's outcome")
            delivered = a2.receive(node_of(st, 1)["delivered"])
            self.assertEqual(a2.receive(1, timeout=0.3), [])
            summary = emu.stop()
        n1 = emu.node(1)
        self.assertEqual(n1["handed_in"], 40)
        self.assertGreater(n1["queue_dropped"], 0)
        self.assertEqual(n1["delivered"], len(delivered))
        self.assertEqual([len(p) for _, _, p in delivered], [200] * len(delivered))
        self.assertEqual(n1["delivered"] + n1["queue_dropped"] + sum(n1["lost"].values()), 40)
        assert_accounted(self, summary)

    def test_frame_to_unknown_node_is_lost_as_unknown_destination(self):
        with Emulator({1: (0, 0, 10), 2: (6, 0, 10)}) as emu:
            emu.agent(1).send(1, 77, b"nobody")
            emu.wait_until(lambda st: node_of(st, 1)["lost"]["unknown_destination"] == 1,
                           what="the frame to be lost")
            summary = emu.stop()
        self.assertEqual(emu.node(1)["lost"]["unknown_destination"], 1)
        self.assertEqual(set(emu.node(1)["lost"]), set(LOSS_REASONS))
        assert_accounted(self, summary)

    def test_node_without_position_hears_nothing(self):
        with Emulator({1: (0, 0, 10), 2: None}) as emu:
            a1, a2 = emu.agent(1), emu.agent(2)
            a1.send(1, 2, b"into the void")
            emu.wait_until(lambda st: node_of(st, 1)["pending"] == 0
                           and node_of(st, 1)["handed_in"] == 1, what="the frame's outcome")
            self.assertEqual(a2.receive(1, timeout=0.3), [])
            summary = emu.stop()
        self.assertEqual(emu.node(1)["lost"]["below_sensitivity"], 1)
        assert_accounted(self, summary)


class DescriptorExhaustionTest(unittest.TestCase):
    def test_listener_recovers_once_descriptors_free_up(self):
        with without_ubsan_vptr_checks(Emulator({1: (0, 0, 10), 2: (6, 0, 10)})) as emu:
            # Every path a connection takes, once while descriptors are plenty
            # (UBSan checks a new kind of call through a pipe, which it could not
            # open at the limit): agent, replacement, probe, on both port kinds.
            old = emu.agent(2)
            emu.wait_for_agent(2)
            agent2 = emu.agent(2)
            agent2.send(2, 1, b"replacing")
            self.assertTrue(old.closed_by_peer())
            feed = emu.feed(2)
            feed.send_line('{"x": 6, "y": 0, "z": 10}')
            emu.feed(2).send_line('{"x": 6, "y": 0, "z": 10}')
            emu.wait_until(lambda st: next(n for n in st["nodes"] if n["id"] == 2)
                           ["source"]["updates"] == 2, what="both positions")
            # The dashboard's HTTP sessions too: a session's teardown runs after its
            # reply, so poll a few more times for the first ones to have finished
            # before the limit (UBSan cannot check a new kind of call without a
            # free descriptor).
            for _ in range(3):
                emu.stats()
            pid = emu.proc.pid
            limits = resource.prlimit(pid, resource.RLIMIT_NOFILE)
            in_use = len(os.listdir(f"/proc/{pid}/fd"))
            # `ulimit -n` at what is open now: the next accept fails with EMFILE.
            resource.prlimit(pid, resource.RLIMIT_NOFILE, (in_use, limits[1]))
            try:
                late = emu.agent(1)  # queued by the kernel, not yet accepted
                viewer = socket.create_connection(("127.0.0.1", emu.dashboard_port()), timeout=30)
                viewer.sendall(b"GET /api/stats HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                               b"Connection: close\r\n\r\n")
                deadline = time.monotonic() + 30
                logged = ("net port {}: cannot accept a connection (Too many open files)".format(
                    emu.net_port(1)), "dashboard: cannot accept a connection (Too many open files)")
                while not all(any(text in line for line in emu.output) for text in logged):
                    self.assertLess(time.monotonic(), deadline, "no accept failure was logged")
                    time.sleep(0.02)
            finally:
                resource.prlimit(pid, resource.RLIMIT_NOFILE, limits)
            # The dashboard tries again too, and answers the waiting request.
            reply = b""
            while chunk := viewer.recv(65536):
                reply += chunk
            viewer.close()
            self.assertTrue(reply.startswith(b"HTTP/1.1 200"), reply[:200])
            # The listener tries again and admits the waiting connection.
            got = []
            deadline = time.monotonic() + 30
            while not got and time.monotonic() < deadline:
                late.send(1, 2, b"after the shortage")
                got = agent2.receive(1, timeout=0.5)
            self.assertEqual(got[:1], [(1, 2, b"after the shortage")])
            emu.wait_settled()  # later tries may still be on the air when lagging
            summary = emu.stop()
        assert_accounted(self, summary)


class ErrorTest(unittest.TestCase):
    def run_cli(self, *args):
        return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=60)

    def test_port_in_use_names_the_port_and_node(self):
        net_base, loc_base = pick_port_bases([1, 2])
        blocker = socket.socket()
        blocker.bind(("127.0.0.1", net_base + 20))
        blocker.listen()
        try:
            r = self.run_cli("run", "--nodes", "2", "--net-base", str(net_base),
                             "--loc-base", str(loc_base), "--stats-interval", "0")
        finally:
            blocker.close()
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn(f"net port {net_base + 20} of node 2", r.stderr)
        self.assertIn("in use", r.stderr)

    def test_bad_scenario_names_file_line_and_key(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "bad.yaml")
            with open(path, "w") as f:
                f.write("name: bad\nnodes:\n  - id: 1\nphy:\n  bandwidth_time: 1.5\n")
            r = self.run_cli("run", path)
        self.assertEqual(r.returncode, 2)
        self.assertIn("bad.yaml:5", r.stderr)
        self.assertIn("phy.bandwidth_time", r.stderr)

    def test_too_long_socket_path_names_file_line_and_key(self):
        # Refused when the scenario loads, where its file and line are known,
        # not later by bind() with a bare path.
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "long.yaml")
            sock_path = "/tmp/" + "s" * 200 + ".sock"
            with open(path, "w") as f:
                f.write("nodes:\n  - {id: 1, phy: {type: external}}\n"
                        f"external:\n  socket: {sock_path}\n")
            r = self.run_cli("run", path)
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn(f"long.yaml:4: external.socket: '{sock_path}' is 210 bytes long; "
                      "a Unix socket path holds at most 107", r.stderr)

    def test_unknown_flag_is_an_error_and_help_works(self):
        r = self.run_cli("run", "--no-such-flag")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--no-such-flag", r.stderr + r.stdout)
        for cmd in ("run", "ping"):
            h = self.run_cli(cmd, "--help")
            self.assertEqual(h.returncode, 0)
            self.assertIn("--net-base", h.stdout)

    def test_unknown_command_is_named(self):
        r = self.run_cli("bogus")
        self.assertEqual(r.returncode, 2)
        self.assertIn("unknown command 'bogus'", r.stderr)

    def test_command_line_values_follow_the_scenario_rules(self):
        cases = [
            (("--noise-db", "400"), "--noise-db: channel.noise_power_db: must be in [-300, 300]"),
            (("--speed", "0"), "--speed: time.speed: must be > 0, got 0"),
            (("--tick", "0"), "--tick: time.tick_samples: must be in 1..1048576, got 0"),
        ]
        for args, expected in cases:
            r = self.run_cli("run", "--nodes", "2", *args)
            self.assertEqual(r.returncode, 2, args)
            self.assertIn(expected, r.stderr)
            self.assertLess(len(r.stderr), 300, r.stderr)

    def test_nodes_flag_with_a_scenario_file_is_refused(self):
        scenario = os.path.join(os.environ["RFSITL_SOURCE_DIR"], "scenarios", "mixed_phy.yaml")
        r = self.run_cli("run", scenario, "--nodes", "4")
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("--nodes builds the default formation and cannot be combined", r.stderr)

    def test_missing_scenario_file_names_it_and_the_reason(self):
        r = self.run_cli("run", "/nonexistent/scenario.yaml")
        self.assertEqual(r.returncode, 2)
        self.assertIn("/nonexistent/scenario.yaml: cannot read scenario file: No such file",
                      r.stderr)

    def test_unwritable_summary_path_fails_before_the_run(self):
        net_base, loc_base = pick_port_bases([1, 2])
        r = self.run_cli("run", "--nodes", "2", "--net-base", str(net_base), "--loc-base",
                         str(loc_base), "--summary-json", "/nonexistent/dir/summary.json")
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("--summary-json /nonexistent/dir/summary.json: cannot write", r.stderr)
        self.assertNotIn("rfsitl: ready", r.stdout)

    def test_bind_localhost_serves_every_port_and_the_dashboard(self):
        net_base, loc_base = pick_port_bases([1, 2])
        r = self.run_cli("run", "--nodes", "2", "--net-base", str(net_base), "--loc-base",
                         str(loc_base), "--bind", "localhost", "--mode", "virtual",
                         "--duration", "0.01", "--dashboard-port", "0")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("rfsitl: dashboard http://127.0.0.1:", r.stdout)
        self.assertIn(f"net 127.0.0.1:{net_base + 10}", r.stdout)


if __name__ == "__main__":
    unittest.main()
