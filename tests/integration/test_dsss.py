"""DSSS nodes through the real emulator: pairs with different codes and
modulations (one with code adaptation on) exchange 80-byte frames and replies."""

import unittest

from harness import Emulator, assert_accounted

PAIRS = (("barker11", "dbpsk"), ("barker11", "dqpsk"), ("mseq31", "dbpsk"),
         ("gold31", "dbpsk", True))


class DsssTest(unittest.TestCase):
    def test_two_dsss_nodes_exchange_80_byte_frames_for_each_code(self):
        nodes, phys = {}, {}
        for i, (code, modulation, *adaptive) in enumerate(PAIRS):
            for j, node_id in enumerate((2 * i + 1, 2 * i + 2)):
                nodes[node_id] = (4.0 * i, 5.0 * j, 10.0)
                phys[node_id] = {"type": "dsss", "code": code, "modulation": modulation,
                                 "adaptive": "true" if adaptive else "false"}
        with Emulator(nodes, node_phy=phys) as emu:
            agents = {n: emu.agent(n) for n in nodes}
            for i, (code, modulation, *_) in enumerate(PAIRS):
                src, dst = 2 * i + 1, 2 * i + 2
                payload = bytes((i * 11 + k) & 0xFF for k in range(80))
                agents[src].send(src, dst, payload)
                self.assertEqual(agents[dst].receive(1), [(src, dst, payload)],
                                 f"{code} {modulation}")
                agents[dst].send(dst, src, b"ack")
                self.assertEqual(agents[src].receive(1), [(dst, src, b"ack")],
                                 f"{code} {modulation} reply")
            summary = emu.stop()
        self.assertTrue(any("dsss mseq31 dbpsk" in line for line in emu.output), emu.output[:10])
        for n in nodes:
            self.assertEqual(emu.node(n)["delivered"], 1, emu.node(n))
        assert_accounted(self, summary)


if __name__ == "__main__":
    unittest.main()
