"""Every registered sample stage keeps outcomes independent of silence
skipping: the determinism test's scenario (links at the edge of decoding, so
the noise decides which frames arrive) with the stage on every transmitter
and every receiver gives the same frames with and without --no-skip (a
receiver run on pure noise may count an extra false header as
rx_crc_failures, as without stages). Each stage also really acts: the
frames differ from the run without it."""

import re
import subprocess
import tempfile
import unittest

import yaml

from harness import BIN, assert_accounted, run_batch, scenario_yaml
from test_determinism import COMPARED, NODES, TRAFFIC

# Settings that make a built-in stage do something (a plugin's own stage runs
# with its defaults).
SETTINGS = {
    "impairments": {"cfo_hz": 400, "cfo_spread_hz": 100, "phase_noise_dbc_hz": -80,
                    "iq_imbalance_db": 0.5, "iq_imbalance_deg": 3, "dc_offset": 0.1},
    "adc": {"bits": 3, "full_scale_db": 6},
}


def sample_stages():
    out = subprocess.run([BIN, "describe", "sample"], capture_output=True, text=True, check=True)
    return re.findall(r"^sample\s+(\S+)\s", out.stdout, re.MULTILINE)


def run(folder, name, stage, args=()):
    doc = yaml.safe_load(scenario_yaml(NODES, TRAFFIC))
    if stage is not None:
        entry = {"type": stage, **SETTINGS.get(stage, {})}
        doc["channel"]["tx_stages"] = [entry]
        doc["channel"]["rx_stages"] = [entry]
    return run_batch(folder, name, yaml.safe_dump(doc), args)


def frames(summary, keys):
    return [{k: n[k] for k in keys} for n in summary["nodes"]]


class SampleStagesTest(unittest.TestCase):
    def test_every_sample_stage_keeps_skipping_exact_and_acts(self):
        stages = sample_stages()
        self.assertIn("impairments", stages)
        self.assertIn("adc", stages)
        same = [k for k in COMPARED if k != "rx_crc_failures"]
        with tempfile.TemporaryDirectory() as d:
            without = run(d, "without", None)
            for stage in stages:
                with self.subTest(stage=stage):
                    skipping = run(d, f"{stage}_skip", stage)
                    every_tick = run(d, f"{stage}_no_skip", stage, ["--no-skip"])
                    assert_accounted(self, skipping)
                    assert_accounted(self, every_tick)
                    self.assertGreater(skipping["receiver_ticks_skipped"], 0)
                    self.assertEqual(every_tick["receiver_ticks_skipped"], 0)
                    self.assertEqual(frames(skipping, same), frames(every_tick, same))
                    if stage in SETTINGS:
                        self.assertNotEqual(frames(skipping, same), frames(without, same),
                                            f"{stage} changed nothing")


if __name__ == "__main__":
    unittest.main()
