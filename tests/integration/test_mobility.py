"""(b) The channel follows the location ports: moving the destination far away
stops delivery, moving it back restores it. Bad lines are counted and the last
good position stays."""

import unittest

from harness import Emulator, assert_accounted

NODES = {1: (0, 0, 10), 2: (8, 0, 10)}


def node_of(stats, node_id):
    return next(n for n in stats["nodes"] if n["id"] == node_id)


def counted(node_id, key, value):
    """A wait_until predicate: node_id's location-port counter `key` (in its
    `source` block) has reached `value`. A feed's position is in the engine's
    inbox before it is counted, so a frame sent afterwards goes on the air with it."""
    return lambda st: node_of(st, node_id)["source"][key] >= value


def nmea(body):
    checksum = 0
    for ch in body:
        checksum ^= ord(ch)
    return f"${body}*{checksum:02X}"


class MobilityTest(unittest.TestCase):
    def exchange(self, a1, a2, tag, expected=True):
        """Sends tag 1 -> 2; what arrives (waiting long for an expected frame,
        briefly for one that should not arrive)."""
        a1.send(1, 2, tag)
        return a2.receive(1) if expected else a2.receive(1, timeout=1.0)

    def test_moving_destination_away_stops_delivery_and_back_restores_it(self):
        with Emulator(NODES) as emu:
            a1, a2 = emu.agent(1), emu.agent(2)
            feed = emu.feed(2)
            self.assertEqual(self.exchange(a1, a2, b"near"), [(1, 2, b"near")])

            feed.move_local(1000, 0, 10)  # 1 km: SNR = 120 - 60 log10(1001) < 0 dB
            emu.wait_until(counted(2, "updates", 1), what="the move away")
            for i in range(3):
                self.assertEqual(self.exchange(a1, a2, b"far %d" % i, expected=False), [])
            # All three on the air and lost before node 2 comes back (a lagging
            # run may still hold them in the queue).
            emu.wait_until(lambda st: node_of(st, 1)["pending"] == 0
                           and node_of(st, 1)["handed_in"] == 4, what="the far frames' outcome")

            # Back next to node 1, this time as WGS84 "lat lon alt" at the scenario origin.
            feed.send_line("43.00085 -78.7890 10")
            emu.wait_until(counted(2, "updates", 2), what="the move back")
            self.assertEqual(self.exchange(a1, a2, b"back"), [(1, 2, b"back")])
            summary = emu.stop()
        n1 = emu.node(1)
        self.assertEqual(n1["delivered"], 2)
        self.assertEqual(n1["lost"]["below_sensitivity"], 3)
        self.assertEqual(emu.node(2)["source"]["updates"], 2)
        assert_accounted(self, summary)

    def test_bad_lines_are_counted_and_the_last_good_position_stays(self):
        with Emulator(NODES) as emu:
            a1, a2 = emu.agent(1), emu.agent(2)
            feed = emu.feed(2)
            feed.move_local(5, 0, 10)
            bad = [
                "91.0 0 10",                       # latitude out of range
                "43.0 -78.0",                      # two numbers
                '{"x": 1, "lat": 2}',              # mixed key sets
                "{not json",                       # malformed JSON
                nmea("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,")[:-2]
                + "00",                            # checksum mismatch
                nmea("GPGGA,123519,4807.038,N,01131.000,E,0,00,,,M,,M,,"),  # no fix
            ]
            for line in bad:
                feed.send_line(line)
            emu.wait_until(counted(2, "errors", len(bad)), what="the bad lines")
            self.assertEqual(self.exchange(a1, a2, b"still here"), [(1, 2, b"still here")])
            # A valid NMEA GGA moves it far away: the feed stayed connected.
            feed.send_line(nmea("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"))
            emu.wait_until(counted(2, "updates", 2), what="the move away")
            self.assertEqual(self.exchange(a1, a2, b"gone", expected=False), [])
            emu.wait_settled()
            summary = emu.stop()
        n2 = emu.node(2)
        self.assertEqual(n2["source"]["errors"], len(bad))
        self.assertEqual(n2["source"]["updates"], 2)
        self.assertTrue(any("checksum" in line for line in emu.output))
        assert_accounted(self, summary)


if __name__ == "__main__":
    unittest.main()
