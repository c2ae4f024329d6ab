"""GNU Radio flowgraphs as nodes (examples/gnuradio/gmsk_node.py: stock
gr-digital GMSK between our emulator source and sink, its own net port)
through the real emulator: two of them exchange packets; they share the
channel with native nodes and interfere with them; and one killed mid-run
leaves the others working and rejoins when restarted.

Needs the gr-rfsitl module installed (scripts/build_gr.sh, run by
scripts/test.sh); without it this test fails and says so."""

import subprocess
import time
import unittest

from harness import (ARRIVAL_S, LOAD_TOLERANT, Emulator, GnuRadioNode, NetClient,
                     assert_accounted, wait_for_output)


BURST = 30  # node 1's long frames in the interference test


def gr_available():
    r = subprocess.run(["/usr/bin/python3", "-c", "from gnuradio import rfsitl"],
                       capture_output=True, text=True)
    return r.returncode == 0, r.stderr


def intact(frames, src, dst, size):
    """Numbers of the frames exchange() sent that are among `frames`, intact."""
    return {p_[0] for s_, d_, p_ in frames
            if (s_, d_, len(p_)) == (src, dst, size) and p_[1:] == bytes(size - 1)}


def exchange(a, b, src, dst, count, size=80, timeout=1.0, settle=ARRIVAL_S):
    """Sends `count` numbered frames a -> b, each after the previous arrived (or
    `timeout` passed); returns how many distinct ones arrived intact, late ones
    included: stragglers are awaited up to `settle` s (a lagging emulator delays
    frames, it does not lose them)."""
    arrived = set()
    for i in range(count):
        payload = bytes([i & 0xFF]) + bytes(size - 1)
        a.send(src, dst, payload)
        deadline = time.monotonic() + timeout
        while i not in arrived and time.monotonic() < deadline:
            arrived |= intact(b.receive(1, timeout=max(0.0, deadline - time.monotonic())),
                              src, dst, size)
    deadline = time.monotonic() + settle
    while len(arrived) < count and time.monotonic() < deadline:
        arrived |= intact(b.receive(1, timeout=deadline - time.monotonic()), src, dst, size)
    return len(arrived)


class GnuRadioNodesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        ok, err = gr_available()
        if not ok:
            raise AssertionError("gr-rfsitl is not installed (bash scripts/build_gr.sh): " + err)

    def start(self, nodes, node_phy, gr_ids):
        emu = Emulator(nodes, node_phy=node_phy, ready_marker="waiting up to",
                       args=["--external-timeout", "2", *LOAD_TOLERANT])
        emu.__enter__()
        self.addCleanup(emu.__exit__, None, None, None)
        grs = {}
        for i in gr_ids:
            grs[i] = GnuRadioNode(emu, i).start()
            self.addCleanup(grs[i].stop)
        self.assertTrue(wait_for_output(emu, "rfsitl: ready"), "".join(emu.output))
        return emu, grs

    def test_two_gnuradio_nodes_exchange_packets_through_the_emulator(self):
        emu, _ = self.start({1: (0, 0, 10), 2: (15, 0, 10)},
                            {1: {"type": "external"}, 2: {"type": "external"}}, [1, 2])
        a1, a2 = NetClient(emu.net_port(1)), NetClient(emu.net_port(2))
        self.addCleanup(a1.close)
        self.addCleanup(a2.close)
        self.assertGreaterEqual(exchange(a1, a2, 1, 2, 20), 19)
        self.assertGreaterEqual(exchange(a2, a1, 2, 1, 20), 19)
        summary = emu.stop()
        ext = {n["id"]: n for n in summary["external"]["nodes"]}
        self.assertEqual([(ext[i]["role"], ext[i]["joins"], ext[i]["drops"]) for i in (1, 2)],
                         [("samples", 1, 0)] * 2)

    def test_native_and_gnuradio_nodes_share_the_channel_and_interfere(self):
        # GNU Radio pair 3 -> 4 (10 m), and native node 1 only 3 m from node 4:
        # while node 1 sends, node 4 hears it 26 dB above node 3.
        nodes = {1: (33, 0, 10), 2: (43, 0, 10), 3: (20, 0, 10), 4: (30, 0, 10)}
        emu, _ = self.start(nodes, {3: {"type": "external"}, 4: {"type": "external"}}, [3, 4])
        a1, a2 = emu.agent(1), emu.agent(2)
        a3, a4 = NetClient(emu.net_port(3)), NetClient(emu.net_port(4))
        self.addCleanup(a3.close)
        self.addCleanup(a4.close)
        self.assertGreaterEqual(exchange(a1, a2, 1, 2, 20), 19)
        self.assertGreaterEqual(exchange(a3, a4, 3, 4, 20), 19)
        # Node 1 fills its queue with 30 long frames: about 1 s on the air, back
        # to back (10 s of wall time at LOAD_TOLERANT's tenth of real time).
        for i in range(BURST):
            a1.send(1, 2, bytes([i]) + bytes(1999))
        emu.wait_until(lambda st: st["nodes"][0]["transmitted"] >= 21, timeout=120,
                       what="node 1 on the air")
        # Ten GNU Radio frames at once while node 1 is on the air. The flowgraphs
        # run in lock-step with the emulator, so however far the run lags behind
        # the wall clock they go out now in its time, inside node 1's burst.
        for i in range(10):
            a3.send(3, 4, bytes([i]) + bytes(79))
        self.assertGreater(emu.stats()["nodes"][0]["queue_depth"], 0, "node 1 stopped too early")
        # Whatever of them decodes has reached node 4's agent by the time node
        # 1's burst is over.
        emu.wait_until(lambda st: st["nodes"][0]["pending"] == 0, timeout=120,
                       what="node 1's burst to end")
        during = len(intact(a4.receive(10, timeout=2.0), 3, 4, 80))
        self.assertLessEqual(during, 3, "GNU Radio frames survived a much stronger native signal")
        # Afterwards the GNU Radio link works again, and node 2 got node 1's frames.
        self.assertEqual(len(a2.receive(BURST, timeout=120)), BURST)
        self.assertGreaterEqual(exchange(a3, a4, 3, 4, 10), 9)
        summary = emu.stop()
        node1 = next(n for n in summary["nodes"] if n["id"] == 1)
        self.assertEqual(node1["delivered"], 20 + BURST)

    def test_killed_gnuradio_node_leaves_others_working_and_rejoins_when_restarted(self):
        nodes = {1: (0, 0, 10), 2: (15, 0, 10), 3: (0, 15, 10), 4: (15, 15, 10)}
        emu, grs = self.start(nodes, {3: {"type": "external"}, 4: {"type": "external"}}, [3, 4])
        a1, a2 = emu.agent(1), emu.agent(2)
        a3 = NetClient(emu.net_port(3))
        a4 = NetClient(emu.net_port(4))
        self.assertGreaterEqual(exchange(a3, a4, 3, 4, 5), 4)
        a4.close()
        grs[4].kill()
        # The emulator notices at its next tick (the socket closes) and goes on.
        self.assertTrue(wait_for_output(emu, "node 4: external transceiver"), "".join(emu.output))
        self.assertGreaterEqual(exchange(a1, a2, 1, 2, 10), 9)
        grs[4] = GnuRadioNode(emu, 4).start()
        a4 = NetClient(emu.net_port(4))
        self.addCleanup(a4.close)
        deadline = time.monotonic() + ARRIVAL_S
        got = 0
        while got < 3 and time.monotonic() < deadline:
            got += exchange(a3, a4, 3, 4, 1, timeout=0.5, settle=2.0)
        self.assertGreaterEqual(got, 3, "node 4 did not rejoin")
        a3.close()
        summary = emu.stop()
        ext = {n["id"]: n for n in summary["external"]["nodes"]}
        self.assertEqual(ext[4]["joins"], 2)
        self.assertGreaterEqual(ext[4]["drops"], 1)
        self.assertEqual((ext[3]["joins"], ext[3]["drops"]), (1, 0))


if __name__ == "__main__":
    unittest.main()
