"""Campaigns from Python (rfsitl.campaign, rfsitl.plotting): a Campaign built
from a dict writes the very table `rfsitl sweep` writes for the same campaign
file, and plot_metric's lines are that table's means over the seeds."""

import csv
import os
import subprocess
import sys
import tempfile
import unittest
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")

from rfsitl.campaign import Campaign, load  # noqa: E402
from rfsitl.plotting import mean_ci95, plot_metric  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.environ.get("RFSITL_SOURCE_DIR", os.path.join(HERE, "..", ".."))
BIN = os.environ.get("RFSITL_BIN")
# The campaign of the CLI's own test (tests/integration/test_sweep.py).
sys.path.insert(0, os.path.join(SOURCE, "tests", "integration"))
from test_sweep import CAMPAIGN, ROWS, SCENARIO  # noqa: E402


def table_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@unittest.skipUnless(BIN, "RFSITL_BIN names the rfsitl program")
class CampaignTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="rfsitl-campaign-")
        campaign = os.path.join(cls.tmp.name, "noise.yaml")
        with open(campaign, "w") as f:
            f.write(CAMPAIGN.format(timeout=300))
        r = subprocess.run([BIN, "sweep", campaign, "--jobs", "2"], capture_output=True,
                           text=True, timeout=600)
        if r.returncode != 0:
            raise AssertionError(f"exit {r.returncode}\n{r.stdout}\n{r.stderr}")
        cls.results = os.path.join(cls.tmp.name, "noise.results")
        with open(os.path.join(cls.results, "results.csv"), "rb") as f:
            cls.table = f.read()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_a_campaign_from_a_dict_writes_the_cli_table(self):
        folder = tempfile.mkdtemp(dir=self.tmp.name)
        c = Campaign.from_dict({
            "scenario": SCENARIO,
            "settings": {"time.duration_s": 2},
            "parameters": {"channel.noise_power_db": [-80, -60]},
            "seeds": 3,
        }, folder=folder, binary=BIN)
        self.assertEqual(c.check(), ROWS)
        df = c.run(jobs=2, quiet=True)
        with open(os.path.join(folder, "campaign.results", "results.csv"), "rb") as f:
            self.assertEqual(f.read(), self.table)
        self.assertEqual(len(df), ROWS)
        self.assertEqual(list(df["seed"]), [1, 2, 3, 1, 2, 3])
        self.assertEqual(int(df["delivered"].sum()),
                         sum(int(r["delivered"]) for r in table_rows(
                             os.path.join(self.results, "results.csv"))))

    def test_plot_lines_are_the_tables_means(self):
        df = load(self.results)
        ax = plot_metric(df, "delivered", "channel.noise_power_db")
        xs, ys = ax.lines[0].get_data()
        by_noise = defaultdict(list)
        for row in table_rows(os.path.join(self.results, "results.csv")):
            by_noise[int(row["channel.noise_power_db"])].append(int(row["delivered"]))
        self.assertEqual(list(xs), sorted(by_noise))
        for x, y in zip(xs, ys):
            self.assertAlmostEqual(y, sum(by_noise[x]) / len(by_noise[x]))
        ax.figure.savefig(os.path.join(self.tmp.name, "delivered.png"))

    def test_the_interval_is_students(self):
        # n = 3, values 1, 2, 3: s = 1, t(0.975, 2) = 4.302652729911275.
        mean, half, n = mean_ci95([1.0, 2.0, 3.0])
        self.assertEqual((mean, n), (2.0, 3))
        self.assertAlmostEqual(half, 4.302652729911275 / 3 ** 0.5, places=9)


if __name__ == "__main__":
    unittest.main(verbosity=2)
