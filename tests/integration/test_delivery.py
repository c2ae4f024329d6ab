"""(a) Frames cross the emulator in range with the right src, dst and payload;
net-port contract details: broadcast, split writes, probes, replacement,
forged senders, oversized frames."""

import socket
import time
import unittest

from harness import ARRIVAL_S, Emulator, assert_accounted


def node_of(stats, node_id):
    return next(n for n in stats["nodes"] if n["id"] == node_id)

NODES = {1: (0, 0, 10), 2: (6, 0, 10), 3: (0, 6, 10)}


class DeliveryTest(unittest.TestCase):
    def test_unicast_frames_arrive_with_src_dst_and_payload_bytes(self):
        with Emulator(NODES) as emu:
            a1, a2, a3 = emu.agent(1), emu.agent(2), emu.agent(3)
            sent = [bytes((i * 37 + k) & 0xFF for k in range(80)) for i in range(5)]
            got = []
            for payload in sent:
                a1.send(1, 2, payload)
                got += a2.receive(1)
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
            emu.wait_settled()  # a broadcast settles after every receiver's verdict
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

    def test_probe_does_not_disturb_a_live_agent(self):
        with Emulator(NODES) as emu:
            agent = emu.agent(2)
            emu.wait_for_agent(2)
            for _ in range(12):  # more than the port keeps waiting
                probe = socket.create_connection(("127.0.0.1", emu.net_port(2)))
                probe.close()  # like `nc -z` or a health check
            emu.agent(1).send(1, 2, b"still the agent")
            self.assertEqual(agent.receive(1), [(1, 2, b"still the agent")])
            self.assertFalse(agent.closed_by_peer(timeout=0.2))
            summary = emu.stop()
        self.assertEqual(emu.node(2)["to_agent_dropped"], 0)
        assert_accounted(self, summary)

    def test_connection_that_sends_replaces_the_agent_and_is_logged(self):
        with Emulator(NODES) as emu:
            a1 = emu.agent(1)
            old = emu.agent(2)
            emu.wait_for_agent(2)
            new = emu.agent(2)
            new.send(2, 1, b"the new agent speaks")
            self.assertTrue(old.closed_by_peer(), "the replaced agent's connection is closed")
            # Node 2 is on the air until node 1 has its frame (half-duplex).
            self.assertEqual(a1.receive(1), [(2, 1, b"the new agent speaks")])
            a1.send(1, 2, b"to the newest agent")
            self.assertEqual(new.receive(1), [(1, 2, b"to the newest agent")])
            summary = emu.stop()
        self.assertTrue(any("net port" in line and "replaces the agent" in line
                            for line in emu.output), emu.output)
        self.assertEqual(emu.node(2)["handed_in"], 1)
        assert_accounted(self, summary)

    def test_silent_connection_inherits_the_port_when_the_agent_leaves(self):
        with Emulator(NODES) as emu:
            old = emu.agent(2)
            emu.wait_for_agent(2)
            listener = emu.agent(2)  # receive-only: it never sends
            old.close()
            deadline = time.monotonic() + ARRIVAL_S
            a1 = emu.agent(1)
            got = []
            while not got and time.monotonic() < deadline:
                a1.send(1, 2, b"to whoever holds node 2")
                got = listener.receive(1, timeout=0.5)
            self.assertEqual(got, [(1, 2, b"to whoever holds node 2")])
            emu.wait_settled()  # the tries before the hand-over, still on the air when lagging
            summary = emu.stop()
        assert_accounted(self, summary)

    def test_frame_claiming_another_sender_is_refused_and_counted(self):
        with Emulator(NODES) as emu:
            a1, a2 = emu.agent(1), emu.agent(2)
            a1.send(3, 2, b"forged src")
            a1.send(1, 2, b"honest")
            self.assertEqual(a2.receive(1), [(1, 2, b"honest")])
            summary = emu.stop()
        self.assertEqual(emu.node(1)["framing_errors"], 1)
        self.assertEqual(emu.node(1)["handed_in"], 1)
        self.assertTrue(any("src byte 3 is not this port's node id 1" in line
                            for line in emu.output), emu.output)
        assert_accounted(self, summary)

    def test_frame_cut_off_by_a_disconnect_is_counted(self):
        with Emulator(NODES) as emu:
            a1 = emu.agent(1)
            a1.send_raw(bytes([1, 2]) + b"never terminated")
            a1.close()
            emu.wait_until(lambda st: node_of(st, 1)["framing_errors"] == 1,
                           what="the cut-off frame to be counted")
            emu.stop()
        self.assertTrue(any("connection ended inside a frame (18 bytes" in line
                            for line in emu.output), emu.output)

    def test_bad_location_line_reaches_the_log_escaped(self):
        # The client's bytes are quoted in the log: shown, never acted on (here
        # a terminal escape that would clear the screen).
        with Emulator(NODES) as emu:
            feed = emu.feed(2)
            feed.sock.sendall(b"\x1b[2Jforged 1 2\n")
            emu.wait_until(lambda st: node_of(st, 2)["source"]["errors"] == 1,
                           what="the bad line to be counted")
            emu.stop()
        self.assertTrue(any("latitude '\\x1b[2Jforged' is not a number" in line
                            for line in emu.output), emu.output)
        self.assertFalse(any("\x1b" in line for line in emu.output), emu.output)

    def test_last_location_line_without_newline_is_used(self):
        with Emulator(NODES) as emu:
            feed = emu.feed(3)
            feed.sock.sendall(b'{"x": 0, "y": 7, "z": 10}')  # no newline, then EOF
            feed.close()
            emu.wait_until(lambda st: node_of(st, 3)["source"]["updates"] == 1,
                           what="the unterminated last line")
            emu.stop()

    def test_location_probe_keeps_the_feed(self):
        with Emulator(NODES) as emu:
            feed = emu.feed(2)
            feed.send_line('{"x": 6, "y": 0, "z": 10}')
            emu.wait_until(lambda st: node_of(st, 2)["source"]["updates"] == 1,
                           what="the first position")
            probe = socket.create_connection(("127.0.0.1", emu.loc_port(2)))
            probe.close()
            feed.send_line('{"x": 7, "y": 0, "z": 10}')
            emu.wait_until(lambda st: node_of(st, 2)["source"]["updates"] == 2,
                           what="the position sent after the probe")
            emu.stop()
        self.assertEqual(emu.node(2)["source"]["errors"], 0)

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
