"""`rfsitl describe` and the settings every component declares: listed, printed,
enforced at load time with file and line, and the same text as scenarios/README.md."""

import json
import os
import re
import socket
import subprocess
import tempfile
import unittest

from harness import BIN, SOURCE_DIR, pick_port_bases

BEGIN = "<!-- BEGIN rfsitl describe --markdown -->\n"
END = "<!-- END rfsitl describe --markdown -->"


def cli(*args, timeout=60):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=timeout)


class DescribeTest(unittest.TestCase):
    def test_lists_every_registered_phy(self):
        r = cli("describe")
        self.assertEqual(r.returncode, 0, r.stderr)
        listed = re.findall(r"^phy\s+(\S+)\s", r.stdout, re.M)
        self.assertEqual(listed, sorted(listed))
        for builtin in ("dsss", "external", "gmsk", "gmsk-liquid", "ofdm"):
            self.assertIn(builtin, listed)

    def test_one_phy_prints_its_settings_with_units_defaults_and_limits(self):
        r = cli("describe", "phy", "gmsk")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("| `samples_per_symbol` | integer | samples | `2` | 2..8 |", r.stdout)
        self.assertIn("| `bandwidth_time` | real |  | `0.5` | [0.2, 1] |", r.stdout)
        r = cli("describe", "phy", "ofdm")
        self.assertIn("| `rate_mbps` | integer | Mbit/s | `6` | 6, 9, 12, 18, 24, 36, 48, 54 |",
                      r.stdout)

    def test_a_list_setting_prints_the_fields_of_its_items(self):
        r = cli("describe", "mobility", "waypoints")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("| `points` | list |  | `[]` | 1..100000 items |", r.stdout)
        items = r.stdout.split("Each item of `points`:\n\n", 1)[1]
        self.assertIn("| `t` | s |  | >= 0 |", items)
        self.assertIn("| `speed_mps` | m/s |  | (0, 10000] |", items)

    def test_unknown_kind_or_name_is_an_error_listing_the_known_ones(self):
        r = cli("describe", "phy", "lora")
        self.assertEqual(r.returncode, 2)
        self.assertRegex(r.stderr, r"no phy named 'lora' \(known: dsss, external, .*gmsk.*\)")
        r = cli("describe", "antenna")
        self.assertEqual(r.returncode, 2)
        self.assertIn("unknown kind 'antenna' (known: position, mobility, phy, mac, channel, sample, radio, spectrum)",
                      r.stderr)

    def test_lists_every_registered_mac_and_the_readme_shows_their_tables(self):
        r = cli("describe", "mac")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(re.findall(r"^mac\s+(\S+)\s", r.stdout, re.M), ["csma", "none", "tdma"])
        with open(os.path.join(SOURCE_DIR, "README.md"), encoding="utf-8") as f:
            readme = f.read()
        for name in ("csma", "tdma"):
            table = cli("describe", "mac", name).stdout.split("\n\n", 1)[1].strip()
            self.assertTrue(table in readme, f"README.md's table of mac {name} is stale: paste "
                            f"the output of `rfsitl describe mac {name}`")

    def test_scenario_readme_tables_are_the_generated_ones(self):
        with open(os.path.join(SOURCE_DIR, "scenarios", "README.md"), encoding="utf-8") as f:
            readme = f.read()
        self.assertIn(BEGIN, readme)
        section = readme.split(BEGIN, 1)[1].split(END, 1)[0]
        generated = cli("describe", "--markdown").stdout
        self.assertEqual(section, generated,
                         "scenarios/README.md is stale: replace the section between the markers "
                         "with the output of `rfsitl describe --markdown`")

    def test_a_setting_outside_the_phys_limits_is_refused_at_load_and_nothing_starts(self):
        net_base, loc_base = pick_port_bases([1])
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "k12.yaml")
            with open(path, "w") as f:
                f.write(f"ports: {{net_base: {net_base}, loc_base: {loc_base}}}\n"
                        "nodes:\n  - id: 1\nphy:\n  type: gmsk\n  samples_per_symbol: 12\n")
            r = cli("run", path, "--no-dashboard")
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn(f"{path}:6: phy.samples_per_symbol: must be in 2..8, got 12", r.stderr)
        self.assertNotIn("listening", r.stdout + r.stderr)
        # Nothing was bound: the node's port is still free.
        s = socket.socket()
        try:
            s.bind(("127.0.0.1", net_base + 10))
        finally:
            s.close()


if __name__ == "__main__":
    unittest.main()
