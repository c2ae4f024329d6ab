#!/usr/bin/python3
"""QA for rfsitl.ubanc_framing: frames are reassembled from arbitrary byte
chunks, garbage and oversized frames are counted and the stream resyncs,
decoded packets get their terminator and the node filter applies."""

import pmt
from gnuradio import blocks, gr, gr_unittest
from gnuradio import rfsitl
from gnuradio.rfsitl.fake_emulator import wait_until

TERM = b"\r\r\n\n"


def pdu(data):
    return pmt.cons(pmt.make_dict(), pmt.init_u8vector(len(data), list(data)))


def pdu_bytes(msg):
    return bytes(pmt.u8vector_elements(pmt.cdr(msg)))


class qa_ubanc_framing(gr_unittest.TestCase):

    def setUp(self):
        self.tb = gr.top_block()

    def tearDown(self):
        self.tb.stop()
        self.tb.wait()

    def start(self, node_id=0, max_payload=2048):
        self.fr = rfsitl.ubanc_framing(node_id, max_payload)
        self.to_radio = blocks.message_debug()
        self.to_net = blocks.message_debug()
        self.tb.msg_connect(self.fr, "radio_out", self.to_radio, "store")
        self.tb.msg_connect(self.fr, "net_out", self.to_net, "store")
        self.tb.start()

    def net(self, chunk):
        self.fr.to_basic_block()._post(pmt.intern("net_in"), pdu(chunk))

    def radio(self, packet):
        self.fr.to_basic_block()._post(pmt.intern("radio_in"), pdu(packet))

    def radio_frames(self, n):
        self.assertTrue(wait_until(lambda: self.to_radio.num_messages() >= n, 5))
        return [pdu_bytes(self.to_radio.get_message(i)) for i in range(self.to_radio.num_messages())]

    def test_001_reassembles_split_frames(self):
        self.start()
        f1 = bytes([1, 2]) + bytes(range(80))
        f2 = bytes([1, 255]) + b"hello"
        f3 = bytes([3, 4])  # empty payload is a valid frame
        stream = f1 + TERM + f2 + TERM + f3 + TERM
        # Chunks of 7 bytes split headers, payloads and terminators alike.
        for i in range(0, len(stream), 7):
            self.net(stream[i:i + 7])
        self.assertEqual(self.radio_frames(3), [f1, f2, f3])
        # Two frames and the start of a third in one chunk; terminator split 2+2.
        f4, f5, f6 = bytes([5, 6]) + b"a", bytes([5, 6]) + b"bb", bytes([5, 6]) + b"ccc"
        self.net(f4 + TERM + f5 + TERM + f6 + b"\r\r")
        self.net(b"\n\n")
        self.assertEqual(self.radio_frames(6)[3:], [f4, f5, f6])
        self.assertEqual(self.fr.frames_to_radio(), 6)
        self.assertEqual(self.fr.framing_errors(), 0)

    def test_002_oversized_and_short_frames(self):
        self.start(max_payload=100)
        # Endless garbage without a terminator, in chunks: one error, bounded
        # memory, then the stream resyncs at the next terminator.
        for _ in range(30):
            self.net(b"x" * 100)
        self.net(b"tail of garbage" + TERM)
        ok1 = bytes([1, 2]) + b"y" * 100  # exactly the limit
        self.net(ok1 + TERM)
        # An oversized frame that arrives whole, and one too short for a header.
        self.net(bytes([1, 2]) + b"z" * 101 + TERM + b"\x01" + TERM)
        ok2 = bytes([7, 8]) + b"after"
        self.net(ok2 + TERM)
        self.assertEqual(self.radio_frames(2), [ok1, ok2])
        self.assertTrue(wait_until(lambda: self.fr.framing_errors() == 3, 5))
        self.assertEqual(self.fr.frames_to_radio(), 2)

    def test_003_radio_to_net_with_filter(self):
        self.start(node_id=2)
        self.radio(bytes([1, 2]) + b"for me")
        self.radio(bytes([1, 3]) + b"for node 3")
        self.radio(bytes([1, 255]) + b"for all")
        self.radio(bytes([2, 255]) + b"own broadcast, heard back")
        self.assertTrue(wait_until(lambda: self.to_net.num_messages() >= 2, 5))
        self.assertTrue(wait_until(lambda: self.fr.frames_filtered() == 2, 5))
        got = [pdu_bytes(self.to_net.get_message(i)) for i in range(self.to_net.num_messages())]
        self.assertEqual(got, [bytes([1, 2]) + b"for me" + TERM,
                               bytes([1, 255]) + b"for all" + TERM])
        self.assertEqual(self.fr.frames_to_net(), 2)

    def test_004_no_filter_passes_all(self):
        self.start(node_id=0)
        self.radio(bytes([1, 3]) + b"p")
        self.assertTrue(wait_until(lambda: self.to_net.num_messages() == 1, 5))
        self.assertEqual(pdu_bytes(self.to_net.get_message(0)), bytes([1, 3]) + b"p" + TERM)
        self.assertEqual(self.fr.frames_filtered(), 0)

    def test_005_rejects_bad_arguments(self):
        for args in ((-1, 100), (255, 100), (1, 0), (1, 65536)):
            with self.assertRaises(ValueError):
                rfsitl.ubanc_framing(*args)


if __name__ == "__main__":
    gr_unittest.run(qa_ubanc_framing)
