"""Radios on their own frequencies, in the real emulator process and virtual
time: two pairs on 802.11 channels 1 and 11 do not hear each other; on
channels 1 and 2 they collide, with the SINR the channel computes within 1 dB
of the adjacent-channel figure the test works out itself from the standard's
transmit mask; an FDD pair sends and receives at the same time."""

import math
import tempfile
import unittest

from harness import Emulator, run_batch

ROUNDS = 20
CARRIER_HZ = 2.437e9
FS = 20e6
NOISE_FIGURE_DB = 7.0
BOLTZMANN = 1.380649e-23
C = 299792458.0

# Pair A: 1 -> 2; pair B: 3 -> 4. Node 3 is as far from node 2 as node 1 is:
# on one channel, B's frames arrive at 2 as strong as A's.
POSITIONS = {1: (0, 0, 10), 2: (10, 0, 10), 3: (20, 0, 10), 4: (30, 0, 10)}


def scenario(channel_a, channel_b, duration_s):
    nodes = "".join(
        f"  - {{id: {i}, channel: wifi24/{channel_a if i <= 2 else channel_b}, "
        f"position: {{x: {p[0]}, y: {p[1]}, z: {p[2]}}}}}\n" for i, p in POSITIONS.items())
    return (f"name: spectrum-test\nseed: 3\n"
            f"time: {{mode: virtual, duration_s: {duration_s}, sample_rate_hz: {FS:g},"
            f" tick_samples: 2000}}\n"
            "phy: {type: ofdm, rate_mbps: 12}\n"
            f"radio: {{carrier_hz: {CARRIER_HZ:g}, tx_power_dbm: 0,"
            f" noise_figure_db: {NOISE_FIGURE_DB}}}\n"
            "channel: {stages: [{type: path_loss, model: free_space}]}\n"
            "spectrum:\n  plans:\n"
            "    wifi24: {first_hz: 2.412e9, spacing_hz: 5e6, channels: 13, bandwidth_hz: 20e6}\n"
            "nodes:\n" + nodes +
            "traffic:\n"
            f"  - {{at_s: 0.01, src: 1, dst: 2, size_bytes: 200, repeat: {ROUNDS},"
            " interval_s: 0.01}\n"
            f"  - {{at_s: 0.01, src: 3, dst: 4, size_bytes: 200, repeat: {ROUNDS},"
            " interval_s: 0.01}\n")


def node(summary, node_id):
    return next(n for n in summary["nodes"] if n["id"] == node_id)


def standard_mask_fraction(df_mhz, width_mhz=20.0):
    """The fraction of a 20 MHz OFDM transmitter's power inside a receiver's
    band df_mhz away: IEEE 802.11 clause 17's transmit mask (0 dBr to 9 MHz,
    -20 dBr at 11, -28 at 20, -40 at 30, linear in dB between), integrated
    here by the trapezoid rule."""
    corners = [(0.0, 0.0), (9.0, 0.0), (11.0, -20.0), (20.0, -28.0), (30.0, -40.0)]

    def density(f):
        f = abs(f)
        if f > 30.0:
            return 0.0
        for (f0, d0), (f1, d1) in zip(corners, corners[1:]):
            if f <= f1:
                return 10 ** ((d0 + (d1 - d0) * (f - f0) / (f1 - f0)) / 10)
        return 0.0

    def integral(lo, hi, steps=60000):
        h = (hi - lo) / steps
        return h * (0.5 * (density(lo) + density(hi)) +
                    sum(density(lo + k * h) for k in range(1, steps)))

    return integral(-df_mhz - width_mhz / 2, -df_mhz + width_mhz / 2) / integral(-30.0, 30.0)


def free_space_gain(d_m):
    return (C / (4 * math.pi * d_m * CARRIER_HZ)) ** 2


def distance(a, b):
    return math.dist(POSITIONS[a], POSITIONS[b])


class ChannelPlanTest(unittest.TestCase):
    def run_pairs(self, channel_a, channel_b):
        with tempfile.TemporaryDirectory() as d:
            return run_batch(d, f"ch{channel_a}_ch{channel_b}",
                             scenario(channel_a, channel_b, 0.25))

    def test_channels_1_and_11_do_not_collide(self):
        summary = self.run_pairs(1, 11)
        for src, dst in ((1, 2), (3, 4)):
            self.assertEqual(node(summary, src)["transmitted"], ROUNDS)
            self.assertEqual(node(summary, src)["delivered"], ROUNDS, node(summary, src))
            self.assertEqual(node(summary, dst)["received"], ROUNDS, node(summary, dst))

    def test_channels_1_and_2_collide(self):
        # Control for the test above: the same pairs, 5 MHz apart, lose frames.
        summary = self.run_pairs(1, 2)
        self.assertEqual(node(summary, 1)["transmitted"], ROUNDS)
        self.assertLess(node(summary, 2)["received"], ROUNDS // 2, node(summary, 2))

    def test_the_channels_sinr_is_the_standard_masks_adjacent_channel_figure(self):
        emu = Emulator(POSITIONS)
        with open(emu.scenario, "w") as f:  # the harness's scenario, with plans and channels
            f.write(scenario(1, 2, 0))  # virtual time until stopped
        with emu:
            stats = emu.wait_until(lambda st: st["links"]["snr_db"][0 * 4 + 1] is not None,
                                   what="the link table")
            emu.stop()
        snr = stats["links"]["snr_db"]
        signal_db = snr[0 * 4 + 1]        # 1 -> 2, the same channel
        interference_db = snr[2 * 4 + 1]  # 3 -> 2, channel 2 into channel 1
        sinr_channel = signal_db - 10 * math.log10(1 + 10 ** (interference_db / 10))
        noise_mw = BOLTZMANN * 290 * FS * 10 ** (NOISE_FIGURE_DB / 10) * 1e3
        signal = free_space_gain(distance(1, 2))  # 0 dBm = 1 mW
        leaked = free_space_gain(distance(3, 2)) * standard_mask_fraction(5.0)
        sinr_expected = 10 * math.log10(signal / (noise_mw + leaked))
        self.assertAlmostEqual(sinr_channel, sinr_expected, delta=1.0)
        # And the leak is the mask's, not the whole signal's: on one channel the
        # SINR would be 0 dB; 5 MHz apart it is the mask's 1.2 dB better.
        self.assertGreater(sinr_channel, 0.5)


def fdd_scenario(duplex):
    """Nodes 1 and 2 send to each other at the same times, each transmitting
    on the frequency the other receives on (channels 1 and 11's centres)."""
    return ("name: fdd-test\nseed: 5\n"
            "time: {mode: virtual, duration_s: 0.15, sample_rate_hz: 20e6, tick_samples: 2000}\n"
            "phy: {type: ofdm, rate_mbps: 12}\n"
            "radio: {carrier_hz: 2.437e9, tx_power_dbm: 20}\n"
            "channel: {stages: [{type: path_loss, model: free_space}]}\n"
            "nodes:\n"
            f"  - {{id: 1, tx_hz: 2.412e9, rx_hz: 2.462e9, bandwidth_hz: 20e6, duplex: {duplex},"
            " position: {x: 0, y: 0, z: 10}}\n"
            f"  - {{id: 2, tx_hz: 2.462e9, rx_hz: 2.412e9, bandwidth_hz: 20e6, duplex: {duplex},"
            " position: {x: 30, y: 0, z: 10}}\n"
            "traffic:\n"
            f"  - {{at_s: 0.01, src: 1, dst: 2, size_bytes: 300, repeat: {ROUNDS}, interval_s: 0.005}}\n"
            f"  - {{at_s: 0.01, src: 2, dst: 1, size_bytes: 300, repeat: {ROUNDS}, interval_s: 0.005}}\n")


class FullDuplexTest(unittest.TestCase):
    def run_fdd(self, duplex):
        with tempfile.TemporaryDirectory() as d:
            return run_batch(d, f"fdd_{duplex}", fdd_scenario(duplex))

    def test_an_fdd_pair_sends_and_receives_at_the_same_time(self):
        summary = self.run_fdd("full")
        for node_id in (1, 2):
            n = node(summary, node_id)
            self.assertEqual(n["transmitted"], ROUNDS, n)
            self.assertEqual(n["delivered"], ROUNDS, n)
            self.assertEqual(n["received"], ROUNDS, n)
            self.assertEqual(n["lost"]["half_duplex"], 0, n)

    def test_the_same_pair_half_duplex_loses_its_frames(self):
        summary = self.run_fdd("half")
        for node_id in (1, 2):
            n = node(summary, node_id)
            self.assertEqual(n["received"], 0, n)
            self.assertEqual(n["lost"]["half_duplex"], ROUNDS, n)


if __name__ == "__main__":
    unittest.main()
