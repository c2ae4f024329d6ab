#!/usr/bin/python3
"""gmsk_node.py's GMSK transceiver with GNU Radio's own SoapySDR blocks as its
radio: `soapy.source` and `soapy.sink` on the device `driver=rfsitl` (the
module in src/soapy/), not the emulator source and sink of gr-rfsitl. The same
flowgraph would drive any SoapySDR radio; here it is a node of the emulator.

    export SOAPY_SDR_PLUGIN_PATH=$PWD/build/release/src/soapy
    /usr/bin/python3 examples/gnuradio/gmsk_soapy_node.py --socket /tmp/rfsitl-15763.sock --id 1

Flowgraph (GmskTx, GmskRx and the framing as in gmsk_node.py):

    agent <-TCP-> socket_pdu <-> ubanc_framing
      ubanc_framing.radio_out -> GmskTx -> soapy.sink   (untimed writes)
      soapy.source -> GmskRx -> ubanc_framing.radio_in

The sink writes the packets' samples untimed; the module puts each packet on
the air at the next tick (see GmskSoapyNode for why not in burst mode). Both
blocks make the device with the same arguments, so SoapySDR gives them one device (one claim of the node).
Unlike gr-rfsitl's source, GNU Radio's does not end the flowgraph when the
device fails (it logs and retries), so this script watches the device's
`connected` sensor (through python3-soapysdr) and exits when the emulator is
gone.
"""

import argparse
import os
import signal
import sys
import threading

import SoapySDR
from gnuradio import gr, soapy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gmsk_node import wire_gmsk_node  # noqa: E402  (the example beside this one)


class GmskSoapyNode(gr.top_block):
    def __init__(self, device_args, node_id, net_port, bind="127.0.0.1", frequency_hz=None,
                 samples_per_symbol=2, bt=0.35, max_payload=2048):
        gr.top_block.__init__(self, "gmsk_soapy_node_%d" % node_id)
        # One RX and one TX channel; CF32 ("fc32") is the module's native format.
        self.source = soapy.source("driver=rfsitl", "fc32", 1, device_args, "", [""], [""])
        # No length tag: GNU Radio 3.10's soapy.sink reads its burst counter
        # uninitialized in burst mode (sink_impl.h: `long d_burst_remaining;`)
        # and can pass a negative count to writeStream. Untimed writes without
        # END_BURST work as well: the module starts each packet at the next
        # tick and sends nothing between packets.
        self.sink = soapy.sink("driver=rfsitl", "fc32", 1, device_args, "", [""], [""])
        if frequency_hz is not None:  # default: the scenario's carrier
            self.source.set_frequency(0, frequency_hz)
            self.sink.set_frequency(0, frequency_hz)
        wire_gmsk_node(self, node_id, net_port, bind, samples_per_symbol, bt, max_payload)

        # The same device once more, for the `connected` sensor: SoapySDR hands
        # out the one the blocks hold. (The source block's read_sensor waits for
        # the block's own lock, which its reading thread hardly ever releases
        # while the device fails.)
        self.device = SoapySDR.Device(SoapySDR.KwargsFromString("driver=rfsitl," + device_args))
        # The top of the RX gain range passes the emulator's samples unchanged:
        # GmskRx then sees what it sees behind gr-rfsitl's source in
        # gmsk_node.py (its demodulator does not mind the level; a squelch or
        # an SNR estimate beside it would).
        self.device.setGain(SoapySDR.SOAPY_SDR_RX, 0,
                            self.device.getGainRange(SoapySDR.SOAPY_SDR_RX, 0).maximum())

    def connected(self):
        return self.device.readSensor("connected") == "true"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--id", type=int, required=True, help="node id, 1..250")
    ap.add_argument("--net-base", type=int, default=15763,
                    help="net port = NET_BASE + 10 * id (default 15763)")
    ap.add_argument("--socket", default=None,
                    help="emulator socket (default /tmp/rfsitl-NET_BASE.sock)")
    ap.add_argument("--device-args", default="",
                    help="more driver=rfsitl arguments, e.g. takeover=1,buffer_ms=2000")
    ap.add_argument("--frequency", type=float, default=None,
                    help="tune RX and TX here (Hz; default: the scenario's carrier)")
    ap.add_argument("--bind", default="127.0.0.1", help="net port address")
    ap.add_argument("--samples-per-symbol", type=int, default=2)
    ap.add_argument("--bt", type=float, default=0.35)
    ap.add_argument("--max-payload", type=int, default=2048)
    ap.add_argument("--log-level", default="info",
                    choices=["trace", "debug", "info", "warn", "error", "critical", "off"])
    args = ap.parse_args(argv)
    if not 1 <= args.id <= 250:
        ap.error("--id must be 1..250")
    socket_path = args.socket or "/tmp/rfsitl-%d.sock" % args.net_base
    device_args = ",".join(a for a in ("socket=" + socket_path, "node=%d" % args.id,
                                       args.device_args) if a)
    net_port = args.net_base + 10 * args.id
    gr.logging().set_default_level(gr.log_levels.__members__[args.log_level])

    try:
        tb = GmskSoapyNode(device_args, args.id, net_port, args.bind, args.frequency,
                           args.samples_per_symbol, args.bt, args.max_payload)
    except Exception as e:  # no such node, claimed, net port in use
        print("gmsk_soapy_node: node %d: cannot start: %s" % (args.id, e), file=sys.stderr)
        return 1

    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    tb.start()
    print("gmsk_soapy_node: node %d ready, net port %d" % (args.id, net_port), flush=True)
    while not stop.wait(0.05):
        if not tb.connected():
            print("gmsk_soapy_node: node %d: emulator gone, exiting" % args.id, flush=True)
            break
    tb.stop()
    tb.wait()
    tb.device = None  # the last reference: the device is released
    f = tb.framing
    print("gmsk_soapy_node: node %d stopped: frames_to_radio=%d frames_to_net=%d "
          "framing_errors=%d" % (args.id, f.frames_to_radio(), f.frames_to_net(),
                                 f.framing_errors()), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
