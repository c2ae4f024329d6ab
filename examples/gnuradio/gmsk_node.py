#!/usr/bin/python3
"""An rfsitl external node built from stock GNU Radio blocks: a GMSK
transceiver between rfsitl.emulator_source and rfsitl.emulator_sink, with
its own UB-ANC net port.

    /usr/bin/python3 examples/gnuradio/gmsk_node.py --socket /tmp/rfsitl-15763.sock --id 1

Flowgraph:

    agent <-TCP-> socket_pdu(TCP_SERVER, 127.0.0.1:net_base+10*id) <-> ubanc_framing
      ubanc_framing.radio_out -> GmskTx -> emulator_sink            (transmit)
      emulator_source -> GmskRx -> ubanc_framing.radio_in           (receive)

Packet on the air (GmskTx / GmskRx):

    [preamble 0x55 x4][access code 64 bits][len u16][len u16][src][dst][payload][CRC32][pad 2]

len counts src..CRC32. The preamble lets the receiver's clock recovery settle
before the access code; the pad pushes the CRC's last bits through the
modulator's Gaussian filter, whose delay would otherwise hold them until the
next packet. GNU Radio's Python bindings load only with /usr/bin/python3.
"""

import argparse
import signal
import sys
import threading

from gnuradio import blocks, digital, gr, network, pdu
from gnuradio import rfsitl

LEN_KEY = "packet_len"
ACCESS_CODE = digital.packet_utils.default_access_code  # 64 bits
PREAMBLE = [0x55] * 4
PAD = [0x55] * 2


def _fixed_packets(data):
    """An endless tagged stream repeating `data` as one packet each time, for
    tagged_stream_mux: it takes one packet per transmitted frame."""
    tag = gr.tag_utils.python_to_tag((0, gr.pmt.intern(LEN_KEY), gr.pmt.from_long(len(data))))
    return blocks.vector_source_b(data, True, 1, [tag])


class GmskTx(gr.hier_block2):
    """Message input `pdus` (u8vector [src][dst][payload]) -> unit-amplitude
    GMSK bursts, each tagged with its length in samples (LEN_KEY)."""

    def __init__(self, samples_per_symbol=2, bt=0.35):
        gr.hier_block2.__init__(self, "gmsk_tx", gr.io_signature(0, 0, 0),
                                gr.io_signature(1, 1, gr.sizeof_gr_complex))
        self.message_port_register_hier_in("pdus")
        self.to_stream = to_stream = pdu.pdu_to_tagged_stream(gr.types.byte_t, LEN_KEY)
        crc = digital.crc32_bb(False, LEN_KEY)
        header = digital.protocol_formatter_bb(
            digital.header_format_default(ACCESS_CODE, 0), LEN_KEY)
        mux = blocks.tagged_stream_mux(gr.sizeof_char, LEN_KEY)
        mod = digital.gmsk_mod(samples_per_symbol, bt)
        # The mux's length tag counts bytes; after the modulator one byte is
        # 8 * sps samples.
        to_samples = blocks.tagged_stream_multiply_length(gr.sizeof_gr_complex, LEN_KEY,
                                                          8 * samples_per_symbol)
        self.msg_connect(self, "pdus", to_stream, "pdus")
        self.connect(to_stream, crc)
        self.connect(_fixed_packets(PREAMBLE), (mux, 0))
        self.connect(crc, header, (mux, 1))
        self.connect(crc, (mux, 2))
        self.connect(_fixed_packets(PAD), (mux, 3))
        self.connect(mux, mod, to_samples, self)


class GmskRx(gr.hier_block2):
    """Received samples -> message output `pdus` (u8vector [src][dst][payload])
    for every packet whose CRC checks."""

    def __init__(self, samples_per_symbol=2, access_code_threshold=2):
        gr.hier_block2.__init__(self, "gmsk_rx", gr.io_signature(1, 1, gr.sizeof_gr_complex),
                                gr.io_signature(0, 0, 0))
        self.message_port_register_hier_out("pdus")
        demod = digital.gmsk_demod(samples_per_symbol)
        sync = digital.correlate_access_code_bb_ts(ACCESS_CODE, access_code_threshold, LEN_KEY)
        pack = blocks.repack_bits_bb(1, 8, LEN_KEY, False, gr.GR_MSB_FIRST)
        crc = digital.crc32_bb(True, LEN_KEY)  # drops packets that fail, strips the CRC
        to_pdu = pdu.tagged_stream_to_pdu(gr.types.byte_t, LEN_KEY)
        self.connect(self, demod, sync, pack, crc, to_pdu)
        self.msg_connect(to_pdu, "pdus", self, "pdus")


def wire_gmsk_node(tb, node_id, net_port, bind, samples_per_symbol, bt, max_payload):
    """The node between its radio (tb.source, tb.sink) and its net port: UB-ANC
    framing, a TCP server for the agent, GMSK modulator and demodulator. The
    radio is the caller's: our emulator blocks here, GNU Radio's Soapy blocks in
    gmsk_soapy_node.py."""
    tb.framing = rfsitl.ubanc_framing(node_id, max_payload)
    tb.net = network.socket_pdu("TCP_SERVER", bind, str(net_port), 10000, True)
    tb.tx = GmskTx(samples_per_symbol, bt)
    tb.rx = GmskRx(samples_per_symbol)
    tb.msg_connect(tb.net, "pdus", tb.framing, "net_in")
    tb.msg_connect(tb.framing, "net_out", tb.net, "pdus")
    tb.msg_connect(tb.framing, "radio_out", tb.tx, "pdus")
    tb.msg_connect(tb.rx, "pdus", tb.framing, "radio_in")
    tb.connect(tb.tx, tb.sink)
    tb.connect(tb.source, tb.rx)


class GmskNode(gr.top_block):
    def __init__(self, socket_path, node_id, net_port, bind="127.0.0.1", timeout_ms=2000,
                 reconnect_ms=20000, samples_per_symbol=2, bt=0.35, max_payload=2048):
        gr.top_block.__init__(self, "gmsk_node_%d" % node_id)
        self.source = rfsitl.emulator_source(socket_path, node_id, timeout_ms, reconnect_ms)
        self.sink = rfsitl.emulator_sink(socket_path, node_id, LEN_KEY)
        wire_gmsk_node(self, node_id, net_port, bind, samples_per_symbol, bt, max_payload)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--id", type=int, required=True, help="node id, 1..250")
    ap.add_argument("--net-base", type=int, default=15763,
                    help="net port = NET_BASE + 10 * id (default 15763)")
    ap.add_argument("--socket", default=None,
                    help="emulator socket (default /tmp/rfsitl-NET_BASE.sock)")
    ap.add_argument("--bind", default="127.0.0.1", help="net port address")
    ap.add_argument("--timeout-ms", type=int, default=2000,
                    help="tick silence after which the node rejoins")
    ap.add_argument("--reconnect-ms", type=int, default=20000,
                    help="how long to try to (re)connect before exiting")
    ap.add_argument("--samples-per-symbol", type=int, default=2)
    ap.add_argument("--bt", type=float, default=0.35)
    ap.add_argument("--max-payload", type=int, default=2048)
    ap.add_argument("--log-level", default="info",
                    choices=["trace", "debug", "info", "warn", "error", "critical", "off"],
                    help="GNU Radio log level (Debian's default config says debug)")
    args = ap.parse_args(argv)
    if not 1 <= args.id <= 250:
        ap.error("--id must be 1..250")
    socket_path = args.socket or "/tmp/rfsitl-%d.sock" % args.net_base
    net_port = args.net_base + 10 * args.id
    # Loggers take the default level when they are created: set it first.
    gr.logging().set_default_level(gr.log_levels.__members__[args.log_level])

    try:
        tb = GmskNode(socket_path, args.id, net_port, args.bind, args.timeout_ms,
                      args.reconnect_ms, args.samples_per_symbol, args.bt, args.max_payload)
    except Exception as e:  # e.g. the net port is in use
        print("gmsk_node: node %d: cannot start (net port %s:%d): %s"
              % (args.id, args.bind, net_port, e), file=sys.stderr)
        return 1

    stop = threading.Event()

    def on_signal(signum, _frame):
        stop.set()

    signal.signal(signal.SIGINT, on_signal)
    signal.signal(signal.SIGTERM, on_signal)

    tb.start()
    ready = False
    status = 0
    # The emulator_source ends the stream when the emulator is gone for good;
    # the message-driven half of the flowgraph would run on, so watch it here.
    while not stop.wait(0.05):
        if not ready and tb.source.connected():
            ready = True
            print("gmsk_node: node %d ready, net port %d" % (args.id, net_port), flush=True)
        if tb.source.finished():
            if ready:
                print("gmsk_node: node %d: emulator gone, exiting" % args.id, flush=True)
            else:
                print("gmsk_node: node %d: no emulator at %s within %d ms, exiting"
                      % (args.id, socket_path, args.reconnect_ms), file=sys.stderr, flush=True)
                status = 1
            break
    tb.stop()
    tb.wait()
    f = tb.framing
    print("gmsk_node: node %d stopped: ticks=%d frames_to_radio=%d frames_to_net=%d "
          "framing_errors=%d filtered=%d" % (args.id, tb.source.ticks(), f.frames_to_radio(),
                                             f.frames_to_net(), f.framing_errors(),
                                             f.frames_filtered()), flush=True)
    return status


if __name__ == "__main__":
    sys.exit(main())
