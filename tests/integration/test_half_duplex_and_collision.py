"""(c) Half-duplex and (d) collisions and capture, through real TCP. The run is
slowed to 1/20 of real time so that frames sent back to back by the test start
in the same (or the next) 1 ms tick: either way they overlap on the air."""

import time
import unittest

from harness import Emulator, assert_accounted

SLOW = ("--speed", "0.05")


class HalfDuplexTest(unittest.TestCase):
    def test_node_that_is_transmitting_does_not_decode_a_frame_meanwhile(self):
        with Emulator({1: (0, 0, 10), 2: (6, 0, 10)}, args=SLOW) as emu:
            a1, a2 = emu.agent(1), emu.agent(2)
            for i in range(3):
                a1.send(1, 2, b"one to two %d" % i + bytes(60))
                a2.send(2, 1, b"two to one %d" % i + bytes(60))
                self.assertEqual(a1.receive(1, timeout=0.5), [])
                self.assertEqual(a2.receive(1, timeout=0.5), [])
            summary = emu.stop()
        for node_id in (1, 2):
            n = emu.node(node_id)
            self.assertEqual(n["transmitted"], 3)
            self.assertEqual(n["lost"]["half_duplex"], 3, n)
        assert_accounted(self, summary)


class CollisionTest(unittest.TestCase):
    def test_equal_power_frames_collide_and_both_are_lost(self):
        # Nodes 1 and 3 are equally far from node 2.
        with Emulator({1: (-5, 0, 10), 2: (0, 0, 10), 3: (5, 0, 10)}, args=SLOW) as emu:
            a1, a2, a3 = emu.agent(1), emu.agent(2), emu.agent(3)
            for i in range(3):
                a1.send(1, 2, b"from one %d" % i + bytes(60))
                a3.send(3, 2, b"from three %d" % i + bytes(60))
                self.assertEqual(a2.receive(1, timeout=0.5), [])
            summary = emu.stop()
        self.assertEqual(emu.node(1)["lost"]["collision"], 3, emu.node(1))
        self.assertEqual(emu.node(3)["lost"]["collision"], 3, emu.node(3))
        assert_accounted(self, summary)

    def test_much_closer_transmitter_captures_the_receiver(self):
        # Node 1 is 2 m from node 2, node 3 is 40 m away: 68 dB stronger.
        with Emulator({1: (-2, 0, 10), 2: (0, 0, 10), 3: (40, 0, 10)}, args=SLOW) as emu:
            a1, a2, a3 = emu.agent(1), emu.agent(2), emu.agent(3)
            for i in range(3):
                a3.send(3, 2, b"weak %d" % i + bytes(60))
                a1.send(1, 2, b"strong %d" % i + bytes(60))
                self.assertEqual(a2.receive(1, timeout=0.5),
                                 [(1, 2, b"strong %d" % i + bytes(60))])
                time.sleep(0.2)
            summary = emu.stop()
        self.assertEqual(emu.node(1)["delivered"], 3)
        self.assertEqual(emu.node(3)["lost"]["collision"], 3, emu.node(3))
        assert_accounted(self, summary)


if __name__ == "__main__":
    unittest.main()
