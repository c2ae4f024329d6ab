"""(c) Half-duplex and (d) collisions and capture, in the real emulator process.
The frames come from the scenario's traffic in virtual time, so the two frames
of each pair start in the same tick whatever the machine's load: frames sent by
a test over TCP in real time overlap only if both reach the emulator within a
frame's air time of each other, which a loaded machine does not promise."""

import unittest

from harness import Emulator, assert_accounted

ROUNDS = 3


def pair_traffic(first, second, size=72):
    """Two frames at once, ROUNDS times, 50 ms apart (each is about 1.6 ms long)."""
    items = "".join(
        f"  - {{at_s: 0.01, src: {src}, dst: {dst}, size_bytes: {size}, repeat: {ROUNDS},"
        f" interval_s: 0.05}}\n" for src, dst in (first, second))
    return "time: {mode: virtual, duration_s: 0.3}\ntraffic:\n" + items


def run(nodes, traffic):
    with Emulator(nodes, traffic, args=["--no-dashboard"]) as emu:
        emu.proc.wait(120)
        summary = emu.stop()
    return emu, summary


class HalfDuplexTest(unittest.TestCase):
    def test_node_that_is_transmitting_does_not_decode_a_frame_meanwhile(self):
        emu, summary = run({1: (0, 0, 10), 2: (6, 0, 10)}, pair_traffic((1, 2), (2, 1)))
        for node_id in (1, 2):
            n = emu.node(node_id)
            self.assertEqual(n["transmitted"], ROUNDS)
            self.assertEqual(n["lost"]["half_duplex"], ROUNDS, n)
            self.assertEqual(n["received"], 0, n)
        assert_accounted(self, summary)


class CollisionTest(unittest.TestCase):
    def test_equal_power_frames_collide_and_both_are_lost(self):
        # Nodes 1 and 3 are equally far from node 2.
        emu, summary = run({1: (-5, 0, 10), 2: (0, 0, 10), 3: (5, 0, 10)},
                           pair_traffic((1, 2), (3, 2)))
        self.assertEqual(emu.node(1)["lost"]["collision"], ROUNDS, emu.node(1))
        self.assertEqual(emu.node(3)["lost"]["collision"], ROUNDS, emu.node(3))
        self.assertEqual(emu.node(2)["received"], 0, emu.node(2))
        assert_accounted(self, summary)

    def test_much_closer_transmitter_captures_the_receiver(self):
        # Node 1 is 2 m from node 2, node 3 is 40 m away: 68 dB stronger.
        emu, summary = run({1: (-2, 0, 10), 2: (0, 0, 10), 3: (40, 0, 10)},
                           pair_traffic((3, 2), (1, 2)))
        self.assertEqual(emu.node(1)["delivered"], ROUNDS)
        self.assertEqual(emu.node(3)["lost"]["collision"], ROUNDS, emu.node(3))
        self.assertEqual(emu.node(2)["received"], ROUNDS, emu.node(2))
        assert_accounted(self, summary)


if __name__ == "__main__":
    unittest.main()
