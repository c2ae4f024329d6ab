"""Cognitive interference avoidance through the real emulator. Node 5 transmits
continuously on the common Gold code, 4 m from both receivers; a fixed-code link
(1 -> 2) and an adaptive link (3 -> 4) send the same traffic in the same run,
one frame at a time. The adaptive receiver measures the interference, asks its
peer (in the control field of the frames it sends) for the Gold code with the
best output SINR, and the peer switches."""

import time
import unittest

from harness import Emulator, assert_accounted

FRAMES = 16


class InterferenceAvoidanceTest(unittest.TestCase):
    def test_adaptive_link_keeps_most_frames_where_fixed_code_link_loses_most(self):
        base = {"type": "dsss", "code": "gold127", "max_payload_bytes": 100}
        fixed = dict(base, adaptive="false")
        adaptive = dict(base, adaptive="true")
        jammer = dict(base, adaptive="false", tx_queue_frames=1000)
        nodes = {1: (-10, 0, 10), 2: (0, 0, 10), 3: (0, -10, 10), 4: (0, -2, 10),
                 5: (4, -1, 10), 6: (40, 40, 10)}
        phys = {1: fixed, 2: fixed, 3: adaptive, 4: adaptive, 5: jammer, 6: fixed}
        with Emulator(nodes, node_phy=phys) as emu:
            a = {n: emu.agent(n) for n in (1, 2, 3, 4, 5)}
            # The jammer floods frames to a far node: continuous interference.
            a[5].send_raw(b"".join(bytes([5, 6]) + bytes([i]) * 90 + b"\r\r\n\n"
                                   for i in range(200)))
            time.sleep(0.5)
            got = {2: 0, 4: 0}
            for i in range(FRAMES):
                for src, dst in ((1, 2), (3, 4)):
                    # The receiver's agent speaks first: its frames carry its code request.
                    a[dst].send(dst, src, b"hello %d" % i)
                    a[src].receive(1, timeout=0.3)
                    a[src].send(src, dst, bytes([i]) * 60)
                    got[dst] += len(a[dst].receive(1, timeout=0.4))
            summary = emu.stop()
        pdr_fixed, pdr_adaptive = got[2] / FRAMES, got[4] / FRAMES
        print(f"packet delivery ratio: fixed code {pdr_fixed:.2f}, adaptive {pdr_adaptive:.2f}")
        self.assertLessEqual(pdr_fixed, 0.25, emu.node(1))
        self.assertGreaterEqual(pdr_adaptive, 0.5, emu.node(3))
        # The jammer's backlog is still queued at shutdown; every other frame
        # has its outcome.
        links = dict(summary, nodes=[n for n in summary["nodes"] if n["id"] in (1, 2, 3, 4)])
        assert_accounted(self, links)
        self.assertGreaterEqual(emu.node(1)["lost"]["collision"], FRAMES // 2, emu.node(1))


if __name__ == "__main__":
    unittest.main()
