"""802.11a/g OFDM nodes through the real emulator: two nodes exchange 80-byte
frames at every rate, pairs of nodes with different rates sharing one channel
(an OFDM receiver decodes whatever rate its SIGNAL field names)."""

import unittest

from harness import Emulator, assert_accounted

RATES = (6, 9, 12, 18, 24, 36, 48, 54)


def pairs_scenario():
    """Node 2i+1 -> 2i+2 at RATES[i]; all within a few metres (SNR > 50 dB)."""
    nodes = {}
    for i, _ in enumerate(RATES):
        nodes[2 * i + 1] = (3.0 * i, 0.0, 10.0)
        nodes[2 * i + 2] = (3.0 * i, 4.0, 10.0)
    return nodes


class OfdmTest(unittest.TestCase):
    def test_two_ofdm_nodes_exchange_80_byte_frames_at_every_rate(self):
        nodes = pairs_scenario()
        rates = {2 * i + 1: r for i, r in enumerate(RATES)}
        rates.update({2 * i + 2: r for i, r in enumerate(RATES)})
        with Emulator(nodes, node_phy={n: {"type": "ofdm", "rate_mbps": r}
                                       for n, r in rates.items()}) as emu:
            agents = {n: emu.agent(n) for n in nodes}
            for i, rate in enumerate(RATES):
                src, dst = 2 * i + 1, 2 * i + 2
                payload = bytes((rate + k) & 0xFF for k in range(80))
                agents[src].send(src, dst, payload)
                self.assertEqual(agents[dst].receive(1), [(src, dst, payload)],
                                 f"{rate} Mbit/s")
                reply = b"ack %d" % rate
                agents[dst].send(dst, src, reply)
                self.assertEqual(agents[src].receive(1), [(dst, src, reply)],
                                 f"{rate} Mbit/s reply")
            summary = emu.stop()
        self.assertTrue(any("ofdm 54 Mbit/s" in line for line in emu.output), emu.output[:20])
        for n in nodes:
            self.assertEqual(emu.node(n)["delivered"], 1, emu.node(n))
        assert_accounted(self, summary)


class MixedPhyTest(unittest.TestCase):
    def test_ofdm_transmission_collides_with_a_gmsk_frame_at_equal_power(self):
        # Node 2 (GMSK) hears GMSK node 1 and OFDM node 3 equally strongly. The
        # scenario's traffic in virtual time starts each GMSK frame in the same
        # tick as a longer OFDM one, whatever the machine's load: one GMSK frame
        # alone, then three at once with OFDM.
        nodes = {1: (-5, 0, 10), 2: (0, 0, 10), 3: (5, 0, 10), 4: (5, 5, 10)}
        ofdm = {"type": "ofdm", "rate_mbps": 6}
        traffic = ("time: {mode: virtual, duration_s: 0.3}\n"
                   "traffic:\n"
                   "  - {at_s: 0.01, src: 1, dst: 2, size_bytes: 76}\n"
                   "  - {at_s: 0.05, src: 1, dst: 2, size_bytes: 76, repeat: 3, interval_s: 0.05}\n"
                   # longer: covers the GMSK frame
                   "  - {at_s: 0.05, src: 3, dst: 4, size_bytes: 206, repeat: 3,"
                   " interval_s: 0.05}\n")
        with Emulator(nodes, traffic, node_phy={3: ofdm, 4: ofdm}, args=["--no-dashboard"]) as emu:
            emu.proc.wait(120)
            summary = emu.stop()
        n1 = emu.node(1)
        self.assertEqual(n1["delivered"], 1)
        self.assertEqual(n1["lost"]["collision"], 3, n1)
        self.assertEqual(emu.node(2)["received"], 1, emu.node(2))
        assert_accounted(self, summary)


if __name__ == "__main__":
    unittest.main()
