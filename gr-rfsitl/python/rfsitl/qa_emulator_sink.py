#!/usr/bin/python3
"""QA for rfsitl.emulator_sink with its emulator_source against a fake
emulator: transmitted samples come back in the kTx replies unchanged, at
most one tick each, zero-length when idle; a tagged burst is held until it
is complete; a full buffer stalls the transmitter instead of dropping; the
transmit stream ends when the source has ended. Every wait is bounded."""

import os
import shutil
import tempfile
import threading
import time

import numpy as np
import pmt
from gnuradio import blocks, gr, gr_unittest, pdu
from gnuradio import rfsitl
from gnuradio.rfsitl.fake_emulator import FakeEmulator, wait_until

B = 250
FS = 1e6


def samples(n, seed):
    rng = np.random.default_rng(seed)
    return (rng.standard_normal(n) + 1j * rng.standard_normal(n)).astype(np.complex64)


def collect(node, n, max_ticks):
    """Ticks until n transmit samples arrived; returns them and the per-tick counts."""
    got, counts = [], []
    deadline = time.monotonic() + 10
    while sum(counts) < n and len(counts) < max_ticks and time.monotonic() < deadline:
        tx = node.tick(np.zeros(B, np.complex64))
        counts.append(len(tx))
        got.append(tx)
        if len(tx) == 0:
            time.sleep(0.002)  # the transmitter chain has not delivered yet
    return (np.concatenate(got) if got else np.zeros(0, np.complex64)), counts


class qa_emulator_sink(gr_unittest.TestCase):

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="rfsitl_qa_")
        self.path = os.path.join(self.dir, "emu.sock")
        self.emu = FakeEmulator(self.path, sample_rate_hz=FS, tick_samples=B)
        self.tb = gr.top_block()
        self.nodes = []

    def tearDown(self):
        self.tb.stop()
        self.tb.wait()
        for node in self.nodes:
            node.close()
        self.emu.close()
        shutil.rmtree(self.dir, ignore_errors=True)

    def start(self, node_id=1, **sink_args):
        """emulator_source -> null_sink and a sink of the same node; returns the sink."""
        src = rfsitl.emulator_source(self.path, node_id, 2000, 5000)
        self.tb.connect(src, blocks.null_sink(gr.sizeof_gr_complex))
        self.src = src
        return rfsitl.emulator_sink(self.path, node_id, **sink_args)

    def accept(self):
        node = self.emu.accept(timeout=10)
        self.nodes.append(node)
        return node

    def test_001_tx_comes_back_in_ticks(self):
        data = samples(3 * B + 17, 1)
        snk = self.start(node_id=4)
        self.tb.connect(blocks.vector_source_c(data.tolist()), snk)
        self.tb.start()
        node = self.accept()
        got, counts = collect(node, len(data), 200)
        np.testing.assert_array_equal(got, data)
        self.assertTrue(all(c <= B for c in counts))
        # Whole ticks while the buffer holds enough; the rest in the last one.
        nonzero = [c for c in counts if c]
        self.assertEqual(nonzero[-1], 17)
        # Idle: the source answers every tick with zero samples.
        for _ in range(5):
            self.assertEqual(len(node.tick(np.zeros(B, np.complex64))), 0)
        self.assertEqual(self.src.tx_samples_sent(), len(data))
        self.assertEqual(snk.samples_in(), len(data))
        self.assertEqual(snk.buffered(), 0)

    def test_002_burst_held_until_complete(self):
        snk = self.start(len_tag_key="packet_len")
        p2s = pdu.pdu_to_tagged_stream(gr.types.complex_t, "packet_len")
        # The length tag claims twice the samples a PDU carries: every burst
        # stays incomplete until the next tag ends it early.
        dbl = blocks.tagged_stream_multiply_length(gr.sizeof_gr_complex, "packet_len", 2.0)
        self.tb.connect(p2s, dbl, snk)
        self.tb.start()
        node = self.accept()
        a, b = samples(300, 2), samples(300, 3)
        port = pmt.intern("pdus")
        p2s.to_basic_block()._post(port, pmt.cons(pmt.make_dict(), pmt.init_c32vector(300, a)))
        self.assertTrue(wait_until(lambda: snk.samples_in() == 300, 5))
        for _ in range(4):  # burst a is incomplete: nothing goes on the air
            self.assertEqual(len(node.tick(None)), 0)
        self.assertEqual(snk.buffered(), 300)
        p2s.to_basic_block()._post(port, pmt.cons(pmt.make_dict(), pmt.init_c32vector(300, b)))
        self.assertTrue(wait_until(lambda: snk.samples_in() == 600, 5))
        tx = [node.tick(None) for _ in range(4)]
        self.assertEqual([len(t) for t in tx], [250, 50, 0, 0])  # a, contiguous; b held
        np.testing.assert_array_equal(np.concatenate(tx), a)
        self.assertEqual(snk.buffered(), 300)

    def test_003_complete_bursts_flow(self):
        snk = self.start(len_tag_key="packet_len")
        p2s = pdu.pdu_to_tagged_stream(gr.types.complex_t, "packet_len")
        self.tb.connect(p2s, snk)
        self.tb.start()
        node = self.accept()
        bursts = [samples(n, 10 + n) for n in (600, 1, 250)]
        for x in bursts:
            p2s.to_basic_block()._post(pmt.intern("pdus"),
                                       pmt.cons(pmt.make_dict(), pmt.init_c32vector(len(x), x)))
        total = sum(len(x) for x in bursts)
        self.assertTrue(wait_until(lambda: snk.samples_in() == total, 5))
        got, counts = collect(node, total, 50)
        np.testing.assert_array_equal(got, np.concatenate(bursts))
        self.assertEqual([c for c in counts if c], [250, 250, 250, 101])

    def test_004_backpressure_without_loss(self):
        # Bound: max(0.002 s * 1 Msps, 4 ticks, 1024) = 2000 samples.
        data = samples(10000, 4)
        snk = self.start(max_buffer_s=0.002)
        self.tb.connect(blocks.vector_source_c(data.tolist()), snk)
        self.tb.start()
        node = self.accept()  # joined, but no tick drains the buffer yet
        self.assertTrue(wait_until(lambda: snk.samples_in() >= 2000, 5))
        time.sleep(0.3)
        # The transmitter chain is stalled at the bound, nothing dropped.
        self.assertEqual(snk.samples_in(), 2000)
        self.assertEqual(snk.buffered(), 2000)
        got, counts = collect(node, len(data), 200)
        np.testing.assert_array_equal(got, data)
        self.assertTrue(all(c <= B for c in counts))

    def test_005_tx_stream_ends_with_source(self):
        snk = rfsitl.emulator_sink(self.path, 2, max_buffer_s=0.002)
        src = rfsitl.emulator_source(self.path, 2, 2000, 600)
        self.tb.connect(src, blocks.null_sink(gr.sizeof_gr_complex))
        self.tb.connect(blocks.vector_source_c([1j] * 1000, repeat=True), snk)
        self.tb.start()
        node = self.accept()
        node.tick(None)
        node.tick(None)
        node.close()
        self.nodes.remove(node)
        self.emu.close()
        # The source gives up after 0.6 s; the sink, blocked on a full buffer,
        # must then end too, and with it the endless transmitter.
        done = threading.Thread(target=self.tb.wait, daemon=True)
        done.start()
        done.join(10)
        self.assertFalse(done.is_alive())
        self.assertTrue(src.finished())


    def test_006_one_sink_per_node(self):
        keep = rfsitl.emulator_sink(self.path, 3)
        with self.assertRaises(RuntimeError):  # two would interleave their samples
            rfsitl.emulator_sink(self.path, 3)
        rfsitl.emulator_sink(self.path, 4)  # another node is fine
        del keep
        rfsitl.emulator_sink(self.path, 3)  # the first one is gone: fine again
        with self.assertRaises(ValueError):
            rfsitl.emulator_sink(self.path, 3, max_buffer_s=0.0)


if __name__ == "__main__":
    gr_unittest.run(qa_emulator_sink)
