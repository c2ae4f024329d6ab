"""GNU Radio's stock SoapySDR blocks as a node: examples/gnuradio/
gmsk_soapy_node.py (the GMSK flowgraph of gmsk_node.py on `soapy.source` and
`soapy.sink`, device driver=rfsitl) exchanges frames with gmsk_node.py on our
emulator blocks, while native nodes share the channel; and it exits when the
emulator stops under it. Its GRC twin, gmsk_soapy_node.grc, compiles with
grcc and exchanges frames the same way.

Needs gr-rfsitl (scripts/build_gr.sh: the example's framing block), GNU
Radio's soapy module, python3-soapysdr and the built SoapySDR module; skipped
with a message without the SoapySDR parts."""

import os
import shutil
import subprocess
import tempfile
import threading
import unittest

from harness import ARRIVAL_S, LOAD_TOLERANT, Emulator, GnuRadioNode, NetClient, wait_for_output
from test_gnuradio import exchange, gr_available
from test_soapy import MODULE_DIR, PYTHON, soapy_env, soapy_missing

SOAPY_NODE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples",
                          "gnuradio", "gmsk_soapy_node.py")
SOAPY_NODE_GRC = os.path.join(os.path.dirname(SOAPY_NODE), "gmsk_soapy_node.grc")
FRAMES = 100
GRC_FRAMES = 40


class SoapyFlowgraph:
    """gmsk_soapy_node.py as node `node_id` of `emu` (or `command`, another
    flowgraph script with its arguments): started, and stopped by the test's
    cleanup."""

    def __init__(self, emu, node_id, command=None):
        sock = f"/tmp/rfsitl-{emu.net_base}.sock"
        self.output = []
        self.proc = subprocess.Popen(
            command or [PYTHON, "-u", SOAPY_NODE, "--socket", sock, "--id", str(node_id),
                        "--net-base", str(emu.net_base), "--log-level", "warn"],
            env=soapy_env(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.ready = threading.Event()
        self.ended = threading.Event()
        threading.Thread(target=self._pump, daemon=True).start()

    def _pump(self):
        for line in self.proc.stdout:
            self.output.append(line)
            if "ready, net port" in line:
                self.ready.set()
        self.ready.set()
        self.ended.set()

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(15)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(10)
        self.ended.wait(10)
        self.proc.stdout.close()


class GnuRadioSoapyNodeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        why = soapy_missing()
        if why:
            raise unittest.SkipTest(why)
        r = subprocess.run([PYTHON, "-c", "from gnuradio import soapy"], capture_output=True,
                           text=True)
        if r.returncode != 0:
            raise unittest.SkipTest("GNU Radio's soapy module is missing: " + r.stderr.strip())
        ok, err = gr_available()
        if not ok:
            raise AssertionError("gr-rfsitl is not installed (bash scripts/build_gr.sh): " + err)
        if not os.path.exists(os.path.join(MODULE_DIR, "libSoapyRfsitl.so")):
            raise AssertionError("the SoapySDR module was not built in " + MODULE_DIR)

    def start(self, nodes):
        """An emulator of `nodes` whose 3 and 4 are external, waiting for both,
        with gmsk_node.py on our blocks as node 3."""
        emu = Emulator(nodes, node_phy={3: {"type": "external"}, 4: {"type": "external"}},
                       ready_marker="waiting up to",
                       args=["--external-timeout", "5", *LOAD_TOLERANT])
        emu.__enter__()
        self.addCleanup(emu.__exit__, None, None, None)
        gr3 = GnuRadioNode(emu, 3).start()
        self.addCleanup(gr3.stop)
        return emu

    def test_soapy_flowgraph_exchanges_frames_with_the_emulator_block_flowgraph(self):
        # Native pair 1 -> 2 beside the GNU Radio pair 3 (our blocks) <-> 4
        # (stock Soapy blocks), 10 m apart each, all on one channel.
        emu = self.start({1: (0, 30, 10), 2: (10, 30, 10), 3: (0, 0, 10), 4: (10, 0, 10)})
        soapy4 = SoapyFlowgraph(emu, 4)
        self.addCleanup(soapy4.stop)
        self.assertTrue(soapy4.ready.wait(60) and soapy4.proc.poll() is None,
                        "".join(soapy4.output))
        self.assertTrue(wait_for_output(emu, "rfsitl: ready"),
                        "".join(emu.output) + "".join(soapy4.output))
        a1, a2 = emu.agent(1), emu.agent(2)
        a3, a4 = NetClient(emu.net_port(3)), NetClient(emu.net_port(4))
        self.addCleanup(a3.close)
        self.addCleanup(a4.close)
        self.assertGreaterEqual(exchange(a1, a2, 1, 2, 10), 9)
        half = FRAMES // 2
        got = exchange(a3, a4, 3, 4, half) + exchange(a4, a3, 4, 3, half)
        self.assertGreaterEqual(got, 95, "".join(soapy4.output[-20:]))
        self.assertGreaterEqual(exchange(a2, a1, 2, 1, 10), 9)
        summary = emu.stop()
        ext = {n["id"]: n for n in summary["external"]["nodes"]}
        self.assertEqual((ext[4]["role"], ext[4]["joins"], ext[4]["drops"]), ("samples", 1, 0))
        # The emulator stopped: the Soapy flowgraph notices and exits by itself.
        self.assertTrue(soapy4.ended.wait(ARRIVAL_S), "".join(soapy4.output))
        self.assertEqual(soapy4.proc.wait(10), 0, "".join(soapy4.output))
        self.assertTrue(any("emulator gone" in line for line in soapy4.output),
                        "".join(soapy4.output))

    def test_grc_twin_compiles_and_exchanges_frames(self):
        # examples/gnuradio/gmsk_soapy_node.grc, compiled by grcc, is the same
        # node as gmsk_soapy_node.py (without its ready line and exit).
        if shutil.which("grcc") is None:
            self.skipTest("grcc not installed (apt-get install gnuradio)")
        out = tempfile.TemporaryDirectory(prefix="rfsitl-grc-")
        self.addCleanup(out.cleanup)
        r = subprocess.run(["grcc", "-o", out.name, SOAPY_NODE_GRC], capture_output=True,
                           text=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        script = os.path.join(out.name, "gmsk_soapy_node_grc.py")
        emu = self.start({3: (0, 0, 10), 4: (10, 0, 10)})
        grc4 = SoapyFlowgraph(emu, 4, [PYTHON, "-u", script,
                                       "--socket-path", f"/tmp/rfsitl-{emu.net_base}.sock",
                                       "--node-id", "4", "--net-base", str(emu.net_base)])
        self.addCleanup(grc4.stop)
        # The emulator runs once both nodes have joined.
        self.assertTrue(wait_for_output(emu, "rfsitl: ready"),
                        "".join(emu.output) + "".join(grc4.output))
        a3, a4 = NetClient(emu.net_port(3)), NetClient(emu.net_port(4))
        self.addCleanup(a3.close)
        self.addCleanup(a4.close)
        half = GRC_FRAMES // 2
        got = exchange(a3, a4, 3, 4, half) + exchange(a4, a3, 4, 3, half)
        self.assertGreaterEqual(got, GRC_FRAMES * 95 // 100, "".join(grc4.output[-20:]))
        summary = emu.stop()
        ext = {n["id"]: n for n in summary["external"]["nodes"]}
        self.assertEqual((ext[4]["joins"], ext[4]["drops"]), (1, 0))


if __name__ == "__main__":
    unittest.main(verbosity=2)
