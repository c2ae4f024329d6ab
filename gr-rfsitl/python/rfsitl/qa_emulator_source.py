#!/usr/bin/python3
"""QA for rfsitl.emulator_source against a fake emulator (fake_emulator.py):
received samples arrive unchanged and in order, rx_time tags mark every
(re)join and gap, and the block rejoins, waits for a late emulator and ends
the stream when the emulator is gone for good. Every wait is bounded."""

import os
import shutil
import tempfile
import threading
import time

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest
from gnuradio import rfsitl
from gnuradio.rfsitl.fake_emulator import FakeEmulator, wait_until

B = 250
FS = 1e6


def ramp(k, n=B):
    """Distinct, recognisable samples for tick k."""
    i = np.arange(n, dtype=np.float32)
    return (i + 1000.0 * k + 1j * (i - 7.0 * k)).astype(np.complex64)


def rx_time_tags(sink):
    """[(offset, (full_secs, frac_secs))] of the rx_time tags a vector_sink saw."""
    out = []
    for t in sink.tags():
        if pmt.symbol_to_string(t.key) == "rx_time":
            out.append((t.offset, (pmt.to_uint64(pmt.tuple_ref(t.value, 0)),
                                   pmt.to_double(pmt.tuple_ref(t.value, 1)))))
    return out


def wait_in_thread(tb, timeout):
    """tb.wait() with a bound: True if the flowgraph ended by itself in time."""
    t = threading.Thread(target=tb.wait, daemon=True)
    t.start()
    t.join(timeout)
    return not t.is_alive()


class qa_emulator_source(gr_unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="rfsitl_qa_")
        self.path = os.path.join(self.dir, "emu.sock")
        self.tb = gr.top_block()
        self.emu = None
        self.nodes = []

    def tearDown(self):
        # Stop first: closing a node while the flowgraph runs makes it rejoin.
        self.tb.stop()
        self.tb.wait()
        for node in self.nodes:
            node.close()
        if self.emu is not None:
            self.emu.close()
        shutil.rmtree(self.dir, ignore_errors=True)

    def accept(self, **kw):
        node = self.emu.accept(**kw)
        if node is not None:
            self.nodes.append(node)
        return node

    def make(self, node_id=1, timeout_ms=2000, reconnect_ms=5000):
        src = rfsitl.emulator_source(self.path, node_id, timeout_ms, reconnect_ms)
        snk = blocks.vector_sink_c()
        self.tb.connect(src, snk)
        return src, snk

    def test_001_samples_tags_and_gap(self):
        self.emu = FakeEmulator(self.path, sample_rate_hz=FS, tick_samples=B)
        src, snk = self.make(node_id=7)
        self.tb.start()
        # Start 2 s into the run so rx_time has a whole-seconds part.
        start = int(2 * FS) // B
        node = self.accept(timeout=10, start_tick=start)
        self.assertEqual(node.node_id, 7)
        self.assertEqual(node.hello["role"], "samples")
        self.assertEqual(len(node.tick(None)), 0)  # first tick: nothing received yet
        expected = []
        for k in range(1, 11):
            expected.append(ramp(k))
            self.assertEqual(len(node.tick(expected[-1])), 0)  # no sink: silent
        # Ticks start+11 .. start+19 never reach this node: a gap.
        gap_tick = start + 20
        expected.append(ramp(20))
        node.tick(expected[-1], index=gap_tick)
        expected.append(ramp(21))
        node.tick(expected[-1])
        total = len(expected) * B
        self.assertTrue(wait_until(lambda: len(snk.data()) >= total, 10))
        got = np.array(snk.data(), dtype=np.complex64)
        self.assertEqual(len(got), total)
        np.testing.assert_array_equal(got, np.concatenate(expected))
        # kTick k carries tick k-1's samples: the first sample is tick start's,
        # the gap resumes with tick gap_tick-1's.
        tags = rx_time_tags(snk)
        self.assertEqual([t[0] for t in tags], [0, 10 * B])
        self.assertEqual(tags[0][1][0], 2)
        self.assertAlmostEqual(tags[0][1][1], 0.0, places=12)
        t1 = (gap_tick - 1) * B / FS
        self.assertEqual(tags[1][1][0], int(t1))
        self.assertAlmostEqual(tags[1][1][1], t1 - int(t1), places=12)
        self.assertEqual(src.discontinuities(), 1)
        self.assertEqual(src.ticks(), 13)
        self.assertEqual(src.joins(), 1)
        self.assertEqual(src.tick_samples(), B)
        self.assertEqual(src.sample_rate(), FS)
        self.assertTrue(src.connected())

    def test_002_rejoins_after_drop(self):
        self.emu = FakeEmulator(self.path, sample_rate_hz=FS, tick_samples=B)
        src, snk = self.make()
        self.tb.start()
        node = self.accept(timeout=10)
        node.tick(None)
        node.tick(ramp(1))
        node.close()  # the emulator drops the node (as after a late answer)
        node = self.accept(timeout=10, start_tick=100)
        self.assertEqual(len(node.tick(None)), 0)
        node.tick(ramp(101))
        self.assertTrue(wait_until(lambda: len(snk.data()) >= 2 * B, 10))
        np.testing.assert_array_equal(np.array(snk.data(), dtype=np.complex64),
                                      np.concatenate([ramp(1), ramp(101)]))
        tags = rx_time_tags(snk)
        self.assertEqual([t[0] for t in tags], [0, B])
        self.assertAlmostEqual(tags[1][1][1], 100 * B / FS, places=12)
        self.assertEqual(src.joins(), 2)
        self.assertEqual(src.discontinuities(), 0)  # a rejoin is not a gap in one connection

    def test_003_waits_for_late_emulator(self):
        src, snk = self.make(reconnect_ms=10000)
        self.tb.start()
        time.sleep(0.6)  # several refused attempts
        self.assertFalse(src.connected())
        self.assertFalse(src.finished())
        self.emu = FakeEmulator(self.path, sample_rate_hz=FS, tick_samples=B)
        node = self.accept(timeout=10)
        node.tick(None)
        node.tick(ramp(1))
        self.assertTrue(wait_until(lambda: len(snk.data()) >= B, 10))
        self.assertTrue(src.connected())

    def test_004_rejected_then_accepted(self):
        self.emu = FakeEmulator(self.path, sample_rate_hz=FS, tick_samples=B)
        src, _ = self.make(node_id=9)
        self.tb.start()
        self.assertIsNone(self.accept(timeout=10, reject="node 9 is already connected"))
        node = self.accept(timeout=10)
        node.tick(None)
        self.assertTrue(wait_until(src.connected, 5))
        self.assertEqual(src.joins(), 1)

    def test_005_tick_silence_rejoins(self):
        self.emu = FakeEmulator(self.path, sample_rate_hz=FS, tick_samples=B)
        src, _ = self.make(timeout_ms=300)
        self.tb.start()
        node = self.accept(timeout=10)
        node.tick(None)
        t0 = time.monotonic()
        # The fake goes quiet without closing: the block leaves and rejoins.
        node2 = self.accept(timeout=10)
        self.assertGreaterEqual(time.monotonic() - t0, 0.25)
        self.assertEqual(node.sock.recv(64), b"")  # the old connection was closed
        node2.tick(None)
        self.assertTrue(wait_until(lambda: src.joins() == 2, 5))

    def test_006_no_tick_timeout_before_first_tick(self):
        # A run may hold its first tick until every external node has joined.
        self.emu = FakeEmulator(self.path, sample_rate_hz=FS, tick_samples=B)
        src, snk = self.make(timeout_ms=200)
        self.tb.start()
        node = self.accept(timeout=10)
        time.sleep(0.7)
        self.assertTrue(src.connected())
        self.assertEqual(src.joins(), 1)
        node.tick(None)
        node.tick(ramp(1))
        self.assertTrue(wait_until(lambda: len(snk.data()) >= B, 10))

    def test_007_ends_stream_when_emulator_gone(self):
        self.emu = FakeEmulator(self.path, sample_rate_hz=FS, tick_samples=B)
        src, snk = self.make(reconnect_ms=800)
        self.tb.start()
        node = self.accept(timeout=10)
        node.tick(None)
        node.tick(ramp(1))
        self.assertTrue(wait_until(lambda: len(snk.data()) >= B, 10))
        t0 = time.monotonic()
        node.close()
        self.emu.close()
        self.emu = None
        # Reconnecting fails for 0.8 s, then the source returns WORK_DONE and
        # the flowgraph ends by itself.
        self.assertTrue(wait_in_thread(self.tb, 10))
        self.assertGreaterEqual(time.monotonic() - t0, 0.7)
        self.assertTrue(src.finished())
        self.assertFalse(src.connected())
        self.assertEqual(len(snk.data()), B)

    def test_008_rejects_bad_arguments(self):
        with self.assertRaises(ValueError):
            rfsitl.emulator_source(self.path, 0)
        with self.assertRaises(ValueError):
            rfsitl.emulator_source(self.path, 255)
        with self.assertRaises(ValueError):
            rfsitl.emulator_source("", 1)
        keep = rfsitl.emulator_source(self.path, 5)
        with self.assertRaises(RuntimeError):  # one source per node and process
            rfsitl.emulator_source(self.path, 5)
        del keep
        rfsitl.emulator_source(self.path, 5)  # the first one is gone: fine again


if __name__ == "__main__":
    gr_unittest.run(qa_emulator_source)
