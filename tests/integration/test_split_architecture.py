"""The split architecture and external transceivers, through the real
emulator: built-in transceivers in `rfsitl node` child processes give the same
results as in the emulator's threads; a child that dies is restarted and its
node rejoins while the others keep working (also when it died idle: its drop
is counted all the same); and a program in the "samples"
role (written here from the protocol description alone) shares the channel
with native nodes, is dropped when it hangs, and rejoins."""

import cmath
import os
import random
import signal
import threading
import time
import unittest

from harness import (ARRIVAL_S, LOAD_TOLERANT, LOAD_TOLERANT_TICK, Emulator, ExternalSamplesNode,
                     assert_accounted, child_pid, pack_samples, wait_for_output)

TRAFFIC = """time: {mode: virtual, duration_s: 0.6}
traffic:
  - {at_s: 0.01, src: 1, dst: 2, size_bytes: 80, repeat: 40, interval_s: 0.013}
  - {at_s: 0.015, src: 4, dst: 3, size_bytes: 120, repeat: 40, interval_s: 0.011}
  - {at_s: 0.02, src: 2, dst: 4, size_bytes: 60, repeat: 40, interval_s: 0.0097}
  - {at_s: 0.03, src: 3, dst: 255, size_bytes: 40, repeat: 30, interval_s: 0.017}
"""
FOUR = {1: (0, 0, 10), 2: (30, 0, 10), 3: (0, 40, 10), 4: (25, 25, 10)}
COMPARED = ("handed_in", "transmitted", "delivered", "lost", "received", "rx_crc_failures")


class Jammer:
    """What a samples-role program sends each tick: `samples` while on, nothing
    while off. Counts the ticks answered since the last switch, so that a test
    waits until a switch has reached the air instead of sleeping."""

    def __init__(self, samples):
        self.samples = samples
        self.on = False
        self.answered = 0
        self.lock = threading.Lock()

    def __call__(self, tick):
        with self.lock:
            self.answered += 1
            return self.samples if self.on else b""

    def switch(self, on, ticks=2):
        """Switches, then waits until `ticks` ticks were answered the new way."""
        with self.lock:
            self.on, self.answered = on, 0
        deadline = time.monotonic() + ARRIVAL_S
        while time.monotonic() < deadline:
            with self.lock:
                if self.answered >= ticks:
                    return
            time.sleep(0.01)
        state = "on" if on else "off"
        raise AssertionError(f"the program answered no tick after switching {state}")


def run_virtual(args=(), node_phy=None):
    with Emulator(FOUR, TRAFFIC, args=args, node_phy=node_phy) as emu:
        emu.proc.wait(120)
        return emu.stop()


class SplitArchitectureTest(unittest.TestCase):
    def test_threads_split_and_mixed_give_identical_counters_in_virtual_time(self):
        threads = run_virtual(["--arch", "threads"])
        split = run_virtual(["--arch", "split"])
        mixed = run_virtual(node_phy={2: {"process": "child"}, 4: {"process": "child"}})
        for run in (threads, split, mixed):
            assert_accounted(self, run)
        # The traffic is busy enough to exercise deliveries and several loss reasons.
        total = lambda key: sum(n[key] for n in threads["nodes"])
        self.assertGreater(total("delivered"), 50)
        self.assertGreater(sum(n["lost"]["collision"] for n in threads["nodes"]), 0)
        self.assertGreater(sum(n["lost"]["half_duplex"] for n in threads["nodes"]), 0)
        for other, name in ((split, "split"), (mixed, "mixed")):
            for a, b in zip(threads["nodes"], other["nodes"]):
                for key in COMPARED:
                    self.assertEqual(a[key], b[key], f"{name}: node {a['id']} {key}")
        self.assertNotIn("external", threads)
        self.assertEqual([n["id"] for n in split["external"]["nodes"]], [1, 2, 3, 4])
        self.assertEqual([n["id"] for n in mixed["external"]["nodes"]], [2, 4])
        for n in split["external"]["nodes"] + mixed["external"]["nodes"]:
            self.assertEqual((n["role"], n["joins"], n["drops"]), ("transceiver", 1, 0))

    def test_killed_child_is_restarted_and_its_node_rejoins_while_others_keep_working(self):
        nodes = {1: (0, 0, 10), 2: (10, 0, 10), 3: (0, 10, 10)}
        with Emulator(nodes, args=["--arch", "split", *LOAD_TOLERANT]) as emu:
            socket_path = f"/tmp/rfsitl-{emu.net_base}.sock"
            a1, a2, a3 = emu.agent(1), emu.agent(2), emu.agent(3)
            a1.send(1, 3, b"before")
            self.assertEqual(a3.receive(1), [(1, 3, b"before")])
            pid = child_pid(socket_path, 3)
            self.assertIsNotNone(pid, "node 3's child process not found")
            os.kill(pid, signal.SIGKILL)
            # Nodes 1 and 2 keep exchanging frames while node 3 is down or restarting.
            got = []
            for i in range(10):
                a1.send(1, 2, b"during-%d" % i)
                got += a2.receive(1, timeout=1)
            got += a2.receive(10 - len(got))  # a lagging run delivers them late
            self.assertGreaterEqual(len(got), 9, got)
            # The supervisor restarts the child; node 3 hears again.
            deadline = time.monotonic() + ARRIVAL_S
            heard = []
            while not heard and time.monotonic() < deadline:
                a1.send(1, 3, b"after")
                heard = a3.receive(1, timeout=0.5)
            self.assertEqual(heard, [(1, 3, b"after")])
            new_pid = child_pid(socket_path, 3)
            self.assertNotIn(new_pid, (None, pid))
            summary = emu.stop()
        ext = {n["id"]: n for n in summary["external"]["nodes"]}
        # One process died, one took over: joins - drops is the one live connection.
        self.assertEqual((ext[3]["joins"], ext[3]["drops"]), (2, 1))
        self.assertEqual((ext[1]["joins"], ext[1]["drops"]), (1, 0))
        self.assertEqual(summary["external"]["child_restarts"], 1)
        self.assertIn("killed by signal", "".join(emu.output))

    def test_idle_child_killed_is_counted_as_a_drop_and_its_restart_as_a_join(self):
        # No traffic at all: no round trip would ever notice the dead process.
        nodes = {1: (0, 0, 10), 2: (10, 0, 10)}
        joined = "node 2: external transceiver 'rfsitl node' joined"
        with Emulator(nodes, args=["--arch", "split"]) as emu:
            socket_path = f"/tmp/rfsitl-{emu.net_base}.sock"
            # Adopted at the first tick after the hello (ready comes before).
            self.assertTrue(wait_for_output(emu, joined), "node 2 never joined")
            pid = child_pid(socket_path, 2)
            self.assertIsNotNone(pid, "node 2's child process not found")
            os.kill(pid, signal.SIGKILL)
            self.assertTrue(wait_for_output(emu, "node 2: external transceiver 'rfsitl node' "
                                            "dropped: the process closed the connection"),
                            "the idle child's death was not noticed:\n" + "".join(emu.output))
            deadline = time.monotonic() + 30
            while (sum(joined in line for line in emu.output) < 2
                   and time.monotonic() < deadline):
                time.sleep(0.05)
            self.assertEqual(sum(joined in line for line in emu.output), 2,
                             "the restarted child did not rejoin:\n" + "".join(emu.output))
            summary = emu.stop()
        ext = {n["id"]: n for n in summary["external"]["nodes"]}
        self.assertEqual((ext[2]["joins"], ext[2]["drops"], ext[2]["timeouts"]), (2, 1, 0))
        self.assertEqual((ext[1]["joins"], ext[1]["drops"]), (1, 0))
        self.assertEqual(summary["external"]["child_restarts"], 1)
        text = "".join(emu.output)
        self.assertRegex(text, r"node\s+2 transceiver\s+joins 2, drops 1")

    def test_samples_role_program_interferes_hangs_is_dropped_and_rejoins(self):
        nodes = {1: (0, 0, 10), 2: (20, 0, 10), 3: (10, 2, 10)}
        rng = random.Random(5)
        # A continuous, strong, noise-like carrier: unit-power random phases.
        jammer = Jammer(pack_samples([cmath.exp(2j * cmath.pi * rng.random())
                                      for _ in range(LOAD_TOLERANT_TICK)]))
        # The emulator opens its ports, then waits for node 3 before the first tick.
        with Emulator(nodes, args=["--external-timeout", "2", *LOAD_TOLERANT],
                      node_phy={3: {"type": "external"}},
                      ready_marker="waiting up to") as emu:
            socket_path = f"/tmp/rfsitl-{emu.net_base}.sock"
            ext = ExternalSamplesNode(socket_path, 3, jammer)
            self.assertEqual(ext.welcome["tick_samples"], LOAD_TOLERANT_TICK)
            a1, a2 = emu.agent(1), emu.agent(2)
            quiet = self._exchange(a1, a2, 10)
            self.assertGreaterEqual(quiet, 9)
            # The external program hears the native transmissions.
            self.assertGreater(max(p for _, p in ext.rx_power), 100.0)
            # Ten frames while it jams: every one of them lost. Each starts at a
            # tick after the jam did and the jam lasts until all ten are settled
            # (a run behind the wall clock starts them late).
            emu.wait_settled()
            jammer.switch(True)
            for i in range(10):
                a1.send(1, 2, b"j%03d" % i + bytes(60))
            emu.wait_until(lambda st: st["nodes"][0]["handed_in"] == 20
                           and st["nodes"][0]["pending"] == 0, what="the jammed frames settled")
            self.assertEqual(a2.receive(1, timeout=0.3), [])
            jammer.switch(False)
            ext.answer = False  # hangs: dropped after 2 s, the run goes on
            deadline = time.monotonic() + ARRIVAL_S
            while not ext.closed and time.monotonic() < deadline:
                time.sleep(0.05)
            self.assertTrue(ext.closed, "the emulator did not drop the hung program")
            # The log line may reach our reader just after the socket closed.
            self.assertTrue(wait_for_output(emu, "no reply within 2000 ms", timeout=10),
                            "".join(emu.output))
            self.assertGreaterEqual(self._exchange(a1, a2, 10), 9)
            ext.close()
            again = ExternalSamplesNode(socket_path, 3, jammer)
            deadline = time.monotonic() + ARRIVAL_S
            while again.ticks < 50 and time.monotonic() < deadline:
                time.sleep(0.05)
            self.assertGreaterEqual(again.ticks, 50)
            self.assertEqual(again.discontinuities, 0)
            again.close()
            summary = emu.stop()
        n3 = summary["external"]["nodes"][0]
        self.assertEqual((n3["id"], n3["role"], n3["joins"], n3["timeouts"]), (3, "samples", 2, 1))
        node1 = next(n for n in summary["nodes"] if n["id"] == 1)
        self.assertEqual(node1["lost"]["collision"], 10)  # the ten sent while node 3 jammed
        # The hang stalled the engine once, counted with the node's own counters.
        node3 = next(n for n in summary["nodes"] if n["id"] == 3)
        self.assertEqual((node1["external_stalls"], node3["external_stalls"]), (0, 1))
        assert_accounted(self, summary)

    @staticmethod
    def _exchange(a1, a2, count):
        """Sends `count` frames 1 -> 2, each after the previous arrived (or 2 s
        passed); how many arrived, late ones included (a lagging run delays
        frames, it does not lose them)."""
        got = 0
        for i in range(count):
            a1.send(1, 2, b"x%03d" % i + bytes(60))
            got += len(a2.receive(1, timeout=2.0))
        return got + len(a2.receive(count - got))


if __name__ == "__main__":
    unittest.main()
