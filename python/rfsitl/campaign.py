"""Campaigns from Python: `rfsitl sweep` driven from a dict or a campaign file,
its table back as a pandas DataFrame.

    from rfsitl.campaign import Campaign
    c = Campaign.from_dict({
        "scenario": "scenarios/six_uav_batch.yaml",
        "settings": {"time.duration_s": 10},
        "parameters": {"channel.noise_power_db": [-80, -60]},
        "seeds": 10,
        "output": "noise.results",
    })
    df = c.run(jobs=2)          # resumable: rows already in the table are not run again
    df.groupby("channel.noise_power_db")["delivery_ratio"].mean()

The campaign runs in the `rfsitl` program (its sweep command), one process per
run; nothing here needs the native module. The program is `binary=`, else
$RFSITL_BIN, else `rfsitl` on the PATH.
"""

import os
import subprocess

import pandas
import yaml

__all__ = ["Campaign", "CampaignError", "load"]


class CampaignError(RuntimeError):
    """A campaign `rfsitl sweep` refused (its message names file:line:key)."""


def load(folder):
    """The table a campaign wrote into `folder` (its results.csv) as a
    DataFrame: numbers as numbers, empty cells as NaN, texts such as "none"
    kept as texts."""
    return pandas.read_csv(os.path.join(folder, "results.csv"), keep_default_na=False,
                           na_values=[""])


def _program(binary):
    return binary or os.environ.get("RFSITL_BIN") or "rfsitl"


class Campaign:
    """A campaign file (see the README's "Campaigns" section), run by `rfsitl sweep`."""

    def __init__(self, path, binary=None):
        """`path`: an existing campaign file."""
        self.path = os.path.abspath(path)
        self.binary = _program(binary)
        with open(self.path) as f:
            spec = yaml.safe_load(f)
        folder = os.path.dirname(self.path)
        stem = os.path.splitext(os.path.basename(self.path))[0]
        self.output = os.path.join(folder, spec.get("output", stem + ".results"))

    @classmethod
    def from_file(cls, path, binary=None):
        return cls(path, binary)

    @classmethod
    def from_dict(cls, spec, folder=".", binary=None):
        """A campaign from a dict in the campaign file's form. Relative paths
        (scenario, output) start at `folder`; the file is written into the
        output folder as campaign.yaml (default output: folder/campaign.results)."""
        spec = dict(spec)
        spec["scenario"] = os.path.abspath(os.path.join(folder, spec["scenario"]))
        spec["output"] = os.path.abspath(os.path.join(folder, spec.get("output",
                                                                       "campaign.results")))
        os.makedirs(spec["output"], exist_ok=True)
        path = os.path.join(spec["output"], "campaign.yaml")
        with open(path, "w") as f:
            yaml.safe_dump(spec, f, sort_keys=False)
        return cls(path, binary)

    def check(self):
        """Validates every grid point's scenario without running anything;
        returns the number of runs. Raises CampaignError."""
        out = self._sweep(["--dry-run"], capture=True)
        return int(out.split(": ")[-1].split(" runs")[0])

    def run(self, jobs=None, retry_failed=False, quiet=False):
        """Runs the rows not yet in the table (`jobs` at once; default one per
        core) and returns the whole table. Failed runs are rows with status
        "failed"; a bad campaign raises CampaignError before any run."""
        args = []
        if jobs:
            args += ["--jobs", str(jobs)]
        if retry_failed:
            args.append("--retry-failed")
        self._sweep(args, capture=quiet, failed_rows_ok=True)
        return self.table()

    def table(self):
        """The table as it stands (after run() or an earlier campaign)."""
        return load(self.output)

    def plot(self, metric, by, out=None):
        """`rfsitl sweep --plot`: an SVG of `metric` against parameter `by`
        (means over seeds with 95 % intervals); returns its path."""
        out = os.path.abspath(out or os.path.join(self.output, f"{metric}_by_{by}.svg"))
        self._sweep(["--plot", metric, "--by", by, "--out", out], capture=True)
        return out

    def _sweep(self, args, capture, failed_rows_ok=False):
        r = subprocess.run([self.binary, "sweep", self.path, *args], text=True,
                           stdout=subprocess.PIPE if capture else None, stderr=subprocess.PIPE)
        if r.returncode == 2 or (r.returncode != 0 and not failed_rows_ok):
            raise CampaignError(r.stderr.strip() or f"rfsitl sweep: exit code {r.returncode}")
        return r.stdout or ""
