"""(a) Frames cross the emulator in range with the right src, dst and payload;
net-port contract details: broadcast, split writes, probes, replacement,
oversized frames."""

import socket
import time
import unittest

from harness import Emulator, assert_accounted

NODES = {1: (0, 0, 10), 2: (6, 0, 10), 3: (0, 6, 10)}


class DeliveryTest(unittest.TestCase):
    def test_unicast_frames_arrive_with_src_dst_and_payload_bytes(self):
        with Emulator(NODES) as emu:
            a1, a2, a3 = emu.agent(1), emu.agent(2), emu.agent(3)
            sent = [bytes((i * 37 + k) & 0xFF for k in range(80)) for i in range(5)]
            got = []
            for payload in sent:
                a1.send(1, 2, payload)
                got += a2.receive(1, timeout=2.0)
            self.assertEqual(got, [(1, 2, p) for p in sent])
            self.assertEqual(a3.receive(1, timeout=0.3), [], "unicast to 2 must not reach 3")
            summary = emu.stop()
        self.assertEqual(emu.node(1)["delivered"], 5)
        self.assertEqual(emu.node(2)["received"], 5)
        self.assertEqual(emu.node(3)["received"], 0)
        assert_accounted(self, summary)

    def test_broadcast_reaches_every_other_node(self):
        with Emulator(NODES) as emu:
            a1, a2, a3 = emu.agent(1), emu.agent(2), emu.agent(3)
            a1.send(1, 255, b"hello swarm")
            self.assertEqual(a2.receive(1), [(1, 255, b"hello swarm")])
            self.assertEqual(a3.receive(1), [(1, 255, b"hello swarm")])
            self.assertEqual(a1.receive(1, timeout=0.3), [], "a node does not hear itself")
            summary = emu.stop()
        self.assertEqual(emu.node(1)["delivered"], 1)
        assert_accounted(self, summary)

    def test_frame_split_across_many_writes_is_reassembled(self):
        with Emulator(NODES) as emu:
            a1, a2 = emu.agent(1), emu.agent(2)
            raw = bytes([1, 2]) + b"split\r\r\nacross writes" + b"\r\r\n\n"
            for i in range(len(raw)):
                a1.send_raw(raw[i:i + 1])
                time.sleep(0.002)
            self.assertEqual(a2.receive(1), [(1, 2, b"split\r\r\nacross writes")])
            emu.stop()

    def test_probe_is_harmless_and_new_connection_replaces_old(self):
        with Emulator(NODES) as emu:
            probe = socket.create_connection(("127.0.0.1", emu.net_port(2)))
            probe.close()  # like `nc -z`
            old = emu.agent(2)
            new = emu.agent(2)
            time.sleep(0.1)
            emu.agent(1).send(1, 2, b"to the newest agent")
            self.assertEqual(new.receive(1), [(1, 2, b"to the newest agent")])
            self.assertEqual(old.receive(1, timeout=0.3), [])
            emu.stop()

    def test_oversized_frame_is_refused_counted_and_the_stream_recovers(self):
        with Emulator(NODES) as emu:
            a1, a2 = emu.agent(1), emu.agent(2)
            a1.send(1, 2, bytes(3000))  # limit is 2048
            a1.send(1, 2, b"after the oversized one")
            self.assertEqual(a2.receive(1), [(1, 2, b"after the oversized one")])
            summary = emu.stop()
        self.assertEqual(emu.node(1)["framing_errors"], 1)
        self.assertEqual(emu.node(1)["handed_in"], 1)
        self.assertTrue(any("payload limit" in line for line in emu.output), emu.output)
        assert_accounted(self, summary)


if __name__ == "__main__":
    unittest.main()
