"""PHY "gfsk" (the SiK-like telemetry radio) from a scenario, in the split
architecture, and named in the run's summary."""

import json
import os
import subprocess
import tempfile
import unittest

from harness import BIN, pick_port_bases

SCENARIO = ("time: {mode: virtual, duration_s: 0.2}\n"
            "phy: {type: gfsk, samples_per_symbol: 4, receiver: energy}\n"
            "nodes:\n  - {id: 1, position: {x: 0, y: 0, z: 10}}\n"
            "  - {id: 2, position: {x: 10, y: 0, z: 10}}\n"
            "traffic:\n  - {at_s: 0.01, src: 1, dst: 2, size_bytes: 80, repeat: 5,"
            " interval_s: 0.03}\n")


class GfskTest(unittest.TestCase):
    def run_scenario(self, *args):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "gfsk.yaml")
            with open(path, "w") as f:
                f.write(SCENARIO)
            net_base, loc_base = pick_port_bases([1, 2])
            r = subprocess.run([BIN, "run", path, "--no-dashboard", "--net-base", str(net_base),
                                "--loc-base", str(loc_base), "--stats-interval", "0",
                                "--summary-json", os.path.join(d, "s.json"), *args],
                               capture_output=True, text=True, timeout=120)
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            with open(os.path.join(d, "s.json")) as f:
                return json.load(f)

    def test_gfsk_nodes_deliver_in_process_and_split(self):
        for arch in ("threads", "split"):
            summary = self.run_scenario("--arch", arch)
            node1 = next(n for n in summary["nodes"] if n["id"] == 1)
            self.assertEqual(node1["phy"], "gfsk")
            self.assertEqual(node1["delivered"], 5, (arch, node1))
            if arch == "split":  # the transceivers ran in `rfsitl node` children
                roles = {n["id"]: n["role"] for n in summary["external"]["nodes"]}
                self.assertEqual(roles, {1: "transceiver", 2: "transceiver"})


if __name__ == "__main__":
    unittest.main()
