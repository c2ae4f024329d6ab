"""`rfsitl sweep`: campaigns of virtual-time runs into one table.

Two campaigns with the same seeds write byte-identical tables; one interrupted
with SIGINT and resumed writes the same table as one that was not; a row's
manifest command re-runs it to the same counters; a wrong key fails before any
run naming file:line:key; failed runs are rows, retried only when asked;
--plot's points are the table's means. (The Python Campaign against this
table: tests/python/test_campaign.py.)
"""

import csv
import json
import os
import re
import signal
import subprocess
import tempfile
import time
import unittest
from collections import defaultdict

from harness import BIN, SOURCE_DIR

SCENARIO = os.path.join(SOURCE_DIR, "scenarios", "six_uav_batch.yaml")
# Two noise levels: at -60 dB the longest links are below GMSK's sensitivity.
CAMPAIGN = f"""scenario: {SCENARIO}
settings:
  time.duration_s: 2
parameters:
  channel.noise_power_db: [-80, -60]
seeds: 3
timeout_s: {{timeout}}
"""
ROWS = 2 * 3


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return path


def read(path):
    with open(path, "rb") as f:
        return f.read()


def sweep(campaign, *args, timeout=300):
    return subprocess.run([BIN, "sweep", campaign, *args], capture_output=True, text=True,
                          timeout=timeout)


def table_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


class SweepTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="rfsitl-sweep-")
        cls.campaign = write(os.path.join(cls.tmp.name, "noise.yaml"),
                             CAMPAIGN.format(timeout=300))
        r = sweep(cls.campaign, "--jobs", "2")
        if r.returncode != 0:
            raise AssertionError(f"exit {r.returncode}\n{r.stdout}\n{r.stderr}")
        cls.results = os.path.join(cls.tmp.name, "noise.results")
        cls.table = read(os.path.join(cls.results, "results.csv"))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def other_campaign(self, name, timeout=300):
        """The same campaign in a folder of its own (its own results)."""
        folder = tempfile.mkdtemp(dir=self.tmp.name)
        return write(os.path.join(folder, name), CAMPAIGN.format(timeout=timeout))

    def test_table_has_every_row_in_grid_order_with_counters(self):
        rows = table_rows(os.path.join(self.results, "results.csv"))
        self.assertEqual([(r["channel.noise_power_db"], r["seed"]) for r in rows],
                         [(n, s) for n in ("-80", "-60") for s in ("1", "2", "3")])
        for r in rows:
            self.assertEqual(r["status"], "ok", r["error"])
            self.assertEqual(float(r["virtual_s"]), 2.0)
            self.assertAlmostEqual(float(r["delivery_ratio"]),
                                   int(r["delivered"]) / int(r["handed_in"]))
        # The noise is what differs: the loud floor loses frames the quiet one delivers.
        quiet = [int(r["delivered"]) for r in rows if r["channel.noise_power_db"] == "-80"]
        loud = [int(r["delivered"]) for r in rows if r["channel.noise_power_db"] == "-60"]
        self.assertGreater(min(quiet), max(loud))

    def test_same_seeds_give_byte_identical_tables(self):
        again = self.other_campaign("noise.yaml")
        r = sweep(again, "--jobs", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(read(os.path.join(os.path.dirname(again), "noise.results",
                                           "results.csv")), self.table)

    def test_interrupted_and_resumed_gives_the_same_table(self):
        campaign = self.other_campaign("noise.yaml")
        table = os.path.join(os.path.dirname(campaign), "noise.results", "results.csv")
        p = subprocess.Popen([BIN, "sweep", campaign, "--jobs", "1"], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and p.poll() is None:
            if os.path.exists(table) and len(table_rows(table)) >= 2:
                break
            time.sleep(0.02)
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=60)
        self.assertEqual(p.returncode, 1, out + err)
        self.assertIn("SIGINT: stopped", out)
        partial = table_rows(table)
        self.assertLess(len(partial), ROWS, "the campaign ended before the interruption")
        self.assertGreaterEqual(len(partial), 2)
        for row in partial:  # only complete rows
            self.assertEqual(row["status"], "ok")
            self.assertNotEqual(row["delivered"], "")
        r = sweep(campaign, "--jobs", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn(f"{len(partial)} reused", r.stdout)
        self.assertEqual(read(table), self.table)

    def test_a_changed_grid_reuses_its_rows_and_says_what_it_left_out(self):
        campaign = self.other_campaign("noise.yaml")
        self.assertEqual(sweep(campaign, "--jobs", "2").returncode, 0)
        write(campaign, CAMPAIGN.format(timeout=300).replace("[-80, -60]", "[-80, -70]"))
        r = sweep(campaign, "--jobs", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("(3 run now, 0 failed, 3 reused)", r.stdout)
        self.assertIn("3 row(s) of the earlier table are not in this campaign's grid", r.stdout)
        rows = table_rows(os.path.join(os.path.dirname(campaign), "noise.results",
                                       "results.csv"))
        self.assertEqual([r["channel.noise_power_db"] for r in rows], ["-80"] * 3 + ["-70"] * 3)

    def test_a_manifest_command_reproduces_its_row(self):
        with open(os.path.join(self.results, "manifest.json")) as f:
            manifest = json.load(f)
        self.assertEqual(len(manifest["rows"]), ROWS)
        row = manifest["rows"][4]
        args = row["arguments"]
        self.assertEqual(args[args.index("--seed") + 1], str(row["seed"]))
        recorded = os.path.join(self.results, "runs", row["key"], "summary.json")
        self.assertEqual(args[-1], recorded)
        again = os.path.join(self.tmp.name, "again.json")
        r = subprocess.run([*args[:-1], again], capture_output=True, text=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(recorded) as f:
            first = json.load(f)
        with open(again) as f:
            second = json.load(f)
        self.assertEqual(second["nodes"], first["nodes"])
        self.assertEqual(second["links"], first["links"])
        self.assertEqual(manifest["rfsitl_version"], first["rfsitl_version"])

    def test_a_wrong_key_fails_before_any_run_naming_file_line_key(self):
        folder = tempfile.mkdtemp(dir=self.tmp.name)
        bad = write(os.path.join(folder, "bad.yaml"), CAMPAIGN.format(timeout=300).replace(
            "seeds: 3", "  channel.nosie_db: [1, 2]\nseeds: 3"))
        r = sweep(bad)
        self.assertEqual(r.returncode, 2)
        self.assertIn(f"{bad}:6: channel.nosie_db: unknown key", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(folder, "bad.results")))

    def test_failed_runs_are_rows_retried_only_when_asked(self):
        # A timeout no run can meet: every run is killed and its row says so.
        campaign = self.other_campaign("noise.yaml", timeout=0.001)
        table = os.path.join(os.path.dirname(campaign), "noise.results", "results.csv")
        r = sweep(campaign, "--jobs", "2")
        self.assertEqual(r.returncode, 1)
        rows = table_rows(table)
        self.assertEqual(len(rows), ROWS)
        for row in rows:
            self.assertEqual(row["status"], "failed")
            self.assertTrue(row["error"].startswith("timed out after"), row["error"])
            self.assertEqual(row["delivery_ratio"], "")  # no figures: the table's columns only
        self.assertIn("0 run now", sweep(campaign).stdout)  # kept, not retried
        write(campaign, CAMPAIGN.format(timeout=300))
        r = sweep(campaign, "--jobs", "2", "--retry-failed")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(read(table), self.table)

    def test_plot_points_are_the_tables_means(self):
        svg_path = os.path.join(self.tmp.name, "ratio.svg")
        r = sweep(self.campaign, "--plot", "delivered", "--by", "channel.noise_power_db",
                  "--out", svg_path)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(svg_path) as f:
            svg = f.read()
        self.assertTrue(svg.startswith("<?xml"))
        points = {m.group(1): (float(m.group(2)), float(m.group(3)), int(m.group(4)))
                  for m in re.finditer(r'data-x="([^"]+)" data-mean="([^"]+)" '
                                       r'data-ci="([^"]+)" data-n="(\d+)"', svg)}
        by_noise = defaultdict(list)
        for row in table_rows(os.path.join(self.results, "results.csv")):
            by_noise[row["channel.noise_power_db"]].append(int(row["delivered"]))
        self.assertEqual(set(points), set(by_noise))
        for noise, values in by_noise.items():
            mean, ci, n = points[noise]
            self.assertAlmostEqual(mean, sum(values) / len(values))
            self.assertEqual(n, len(values))
            self.assertGreaterEqual(ci, 0.0)
        r = sweep(self.campaign, "--plot", "delivered", "--by", "mac.type")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--by mac.type: not a parameter of this campaign", r.stderr)


if __name__ == "__main__":
    unittest.main()
