"""scenarios/soapy_pair.yaml (two built-in GMSK nodes that talk, nodes 3 and 4
served to SoapySDR programs) run as shipped, with python3-soapysdr programs on
its external nodes: SoapySDRUtil labels a device alike in --find and --probe;
a device's first getHardwareTime() is already the emulator's time; CS16 at
the default RX gain carries the noise in its low bits and a 10 m link below
full scale; and the README's SoapySDR snippet, run as written (on this test's
socket), finds its burst at the time it scheduled it.

Needs soapysdr-tools and python3-soapysdr (scripts/setup.sh); skipped with a
message without them. Helpers and the module's folder as in test_soapy.py."""

import os
import re
import shutil
import unittest

from harness import LOAD_TOLERANT, SOURCE_DIR, Emulator
from test_soapy import require_module, run_program, soapy_util

SCENARIO = os.path.join(SOURCE_DIR, "scenarios", "soapy_pair.yaml")
README = os.path.join(SOURCE_DIR, "README.md")

# Node 3 receives CS16 at the device's default gain while node 4, 10 m away,
# sends a full-scale burst (the loudest a Soapy node can send); prints the
# first hardware time, then the levels of 0.3 virtual seconds.
LEVELS = r"""
import json, sys, time
import numpy as np
import SoapySDR
from SoapySDR import (SOAPY_SDR_RX, SOAPY_SDR_TX, SOAPY_SDR_CS16, SOAPY_SDR_CF32,
                      SOAPY_SDR_HAS_TIME, SOAPY_SDR_END_BURST)
def say(**kw):
    print(json.dumps(kw), flush=True)
rx_dev = SoapySDR.Device(dict(driver="rfsitl", socket=sys.argv[1], node="3"))
say(step="time", first_ns=rx_dev.getHardwareTime())
tx_dev = SoapySDR.Device(dict(driver="rfsitl", socket=sys.argv[1], node="4"))
fs = rx_dev.getSampleRate(SOAPY_SDR_RX, 0)
rx = rx_dev.setupStream(SOAPY_SDR_RX, SOAPY_SDR_CS16)
tx = tx_dev.setupStream(SOAPY_SDR_TX, SOAPY_SDR_CF32)
rx_dev.activateStream(rx)
tx_dev.activateStream(tx)
mtu = rx_dev.getStreamMTU(rx)
when = tx_dev.getHardwareTime() + 100_000_000
burst = np.ones(5000, np.complex64)
tx_dev.writeStream(tx, [burst], len(burst), SOAPY_SDR_HAS_TIME | SOAPY_SDR_END_BURST, when)
buf = np.zeros(2 * mtu, np.int16)
chunks, start_ns, got = [], None, 0
deadline = time.monotonic() + 120
while got < 0.3 * fs and time.monotonic() < deadline:
    r = rx_dev.readStream(rx, [buf], mtu, timeoutUs=200000)
    if r.ret > 0:
        start_ns = r.timeNs if start_ns is None else start_ns
        chunks.append(buf[:2 * r.ret].astype(float))
        got += r.ret
x = np.abs(np.concatenate(chunks))
gain = rx_dev.getGainRange(SOAPY_SDR_RX, 0)
say(step="levels", first_read_ns=start_ns, when=when, tick_ns=mtu * 1e9 / fs,
    # Bursts fill a few per cent of the time: the median is the noise's.
    # For Gaussian noise the median of |I| is 0.6745 sigma.
    noise_rms=float(np.median(x) / 0.6745), peak=float(x.max()),
    clipped=float(np.mean(x >= 32767)), gain=rx_dev.getGain(SOAPY_SDR_RX, 0),
    gain_range=[gain.minimum(), gain.maximum()])
"""


def readme_snippet():
    """The ```python block of the README's SoapySDR section."""
    with open(README) as f:
        text = f.read()
    section = text[text.index("\n## SoapySDR\n"):]
    m = re.search(r"```python\n(.*?)```", section, re.S)
    return m.group(1)


class SoapyPairScenarioTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        require_module()

    def start(self):
        """The shipped scenario on free ports (the harness's node ids pick
        them; its file is replaced by the shipped one), load-tolerant timing."""
        emu = Emulator({n: None for n in (1, 2, 3, 4)},
                       args=["--external-timeout", "5", *LOAD_TOLERANT])
        shutil.copyfile(SCENARIO, emu.scenario)
        emu.__enter__()
        self.addCleanup(emu.__exit__, None, None, None)
        return emu, f"/tmp/rfsitl-{emu.net_base}.sock"

    def test_find_and_probe_give_a_device_one_label(self):
        emu, sock = self.start()
        found = soapy_util(f"--find=driver=rfsitl,socket={sock}")
        devices = [dict(re.findall(r"^\s*(\w+) = (.*)$", block, re.M))
                   for block in found.split("Found device")[1:]]
        labels = {d["node"]: d["label"] for d in devices}
        self.assertEqual(sorted(labels), ["3", "4"], found)
        self.assertIn("soapy-pair node 3", labels["3"])
        probe = soapy_util(f"--probe=driver=rfsitl,socket={sock},node=3")
        m = re.search(r"^\s*label=(.*)$", probe, re.M)
        self.assertIsNotNone(m, probe)
        self.assertEqual(m.group(1).strip(), labels["3"].strip(), probe)

    def levels(self):
        """Runs LEVELS on a fresh emulator that has run a while (0.2 virtual
        s) before the program makes its devices; returns (the emulator's time
        before, the first hardware time, the levels step)."""
        emu, sock = self.start()
        before = emu.wait_until(lambda st: st["virtual_s"] >= 0.2, what="0.2 s")["virtual_s"]
        until = run_program(self, LEVELS, sock, context=lambda: "".join(emu.output[-30:]))
        first = until("time")["first_ns"]
        lv = until("levels")
        self.assertEqual(until.proc.wait(60), 0, "".join(until.lines))
        return before, first, lv

    def test_first_hardware_time_is_already_the_emulators(self):
        before, first, lv = self.levels()
        # Not 0: at least where the emulator was before the device was made...
        self.assertGreaterEqual(first, before * 1e9 - lv["tick_ns"], lv)
        # ...and no later than the RX stream activated after it.
        self.assertLessEqual(first, lv["first_read_ns"] + lv["tick_ns"], (first, lv))

    def test_cs16_at_the_default_gain_is_usable(self):
        _, _, lv = self.levels()
        # A real SDR's noise floor, and the loudest 10 m link (node 4 at full
        # scale) far above it but below full scale.
        self.assertGreaterEqual(lv["noise_rms"], 8, lv)
        self.assertLessEqual(lv["noise_rms"], 64, lv)
        self.assertEqual(lv["clipped"], 0.0, lv)
        self.assertGreater(lv["peak"], 100 * lv["noise_rms"], lv)
        self.assertLess(lv["peak"], 32767, lv)
        self.assertLessEqual(lv["gain_range"][0], lv["gain"])
        self.assertLessEqual(lv["gain"], lv["gain_range"][1])

    def test_readme_snippet_receives_its_burst_at_the_time_it_scheduled(self):
        snippet = readme_snippet()
        self.assertIn("/usr/bin/python3", snippet, "the snippet names the python to run it with")
        emu, sock = self.start()
        st = emu.wait_until(lambda st: st["virtual_s"] >= 0.2, what="0.2 s")
        before, tick_s = st["virtual_s"], st["tick_samples"] / st["sample_rate_hz"]
        # As written, on this emulator's socket (the default scans /tmp).
        code = snippet.replace('driver="rfsitl"', f'driver="rfsitl", socket="{sock}"')
        until = run_program(self, code + 'print(\'{"step": "done"}\')\n',
                            context=lambda: "".join(emu.output[-30:]))
        until("done")
        said = "".join(until.lines)
        m = re.search(r"sent for (\d+\.\d+) s, received at (\d+\.\d+) s", said)
        self.assertIsNotNone(m, said)
        sent, received = float(m.group(1)), float(m.group(2))
        self.assertGreater(sent, before, "scheduled in the emulator's time, not from 0")
        self.assertLessEqual(abs(received - sent), tick_s, said)

if __name__ == "__main__":
    unittest.main(verbosity=2)
