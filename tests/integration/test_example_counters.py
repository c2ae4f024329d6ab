"""Refactors change no outcome: every example scenario (scenarios/*.yaml) and a
few probes of the channel's corners (the determinism test's noise-decided
links, with front-end impairments, shared noise, fading and multipath) run in
virtual time and give the same counters, bit for bit, as the golden file
tests/vectors/example_counters.json records.

The golden file was recorded by this script (`--record`) at the commit its
"recorded_at" names; re-record only for a change that is meant to move
outcomes, and say why in the commit. Noise is counter-based and every SIMD
kernel spells out the same IEEE operations, so the counters do not depend on
the machine (x86-64) or the number of threads.

An example scenario runs as written, except: virtual time, at most
MAX_DURATION_S; external nodes become built-in (nothing would attach in a
test); a live position source (MAVLink) is left out; and a scenario without
traffic gets the same ring of frames between its nodes."""

import copy
import glob
import json
import os
import subprocess
import sys
import tempfile
import unittest

import yaml

from harness import run_batch, scenario_yaml
from test_determinism import NODES as DET_NODES, TRAFFIC as DET_TRAFFIC

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.path.dirname(os.path.dirname(HERE))
SCENARIOS = os.path.join(SOURCE_DIR, "scenarios")
GOLDEN = os.path.join(SOURCE_DIR, "tests", "vectors", "example_counters.json")
MAX_DURATION_S = 2.0

# Run-time measurements, not outcomes.
NODE_KEYS_LEFT_OUT = ("source", "pending", "queue_depth")
TOP_KEYS = ("receiver_ticks_blanked", "receiver_ticks_run", "receiver_ticks_skipped", "links",
            "virtual_s")


def ring_traffic(ids):
    """Each node sends 60-byte frames to the next every 50 ms; the first also
    broadcasts every 300 ms."""
    items = []
    for k, src in enumerate(ids):
        dst = ids[(k + 1) % len(ids)]
        items.append({"at_s": round(0.01 + 0.007 * k, 3), "src": src, "dst": dst,
                      "size_bytes": 60, "repeat": 1000, "interval_s": 0.05})
    items.append({"at_s": 0.02, "src": ids[0], "dst": 255, "size_bytes": 40, "repeat": 100,
                  "interval_s": 0.3})
    return items


def batch_version(doc):
    """The example as a bounded virtual-time batch run (see the module's doc)."""
    doc = copy.deepcopy(doc)
    time = doc.setdefault("time", {})
    time["mode"] = "virtual"
    own = float(time.get("duration_s", 0) or 0)
    time["duration_s"] = min(own, MAX_DURATION_S) if own > 0 else MAX_DURATION_S
    doc.pop("external", None)
    if doc.get("position", {}).get("source") == "mavlink":
        doc.pop("position")
    for node in doc.get("nodes", []):
        if isinstance(node.get("phy"), dict) and node["phy"].get("type") == "external":
            del node["phy"]
    if not doc.get("traffic"):
        doc["traffic"] = ring_traffic([n["id"] for n in doc["nodes"]])
    return doc


# Each probe: the determinism scenario with these keys merged in (channel's
# keys into its channel section).
PROBES = {
    "probe_noise_decided": {},
    "probe_impairments": {"channel": {"impairments": {
        "tx": {"cfo_hz": 300, "cfo_spread_hz": 100, "phase_noise_dbc_hz": -80,
               "iq_imbalance_db": 0.5, "iq_imbalance_deg": 2, "dc_offset": 0.05},
        "rx": {"cfo_hz": -150, "phase_noise_dbc_hz": -85, "iq_imbalance_db": -0.3,
               "dc_offset": 0.1}}}},
    "probe_shared_noise": {"channel": {"shared_noise": True}},
    "probe_fading_multipath": {"channel": {"stages": [
        {"type": "path_loss"}, {"type": "multipath", "profile": "tdl_a", "delay_spread_ns": 300},
        {"type": "fading", "model": "rician", "k_db": 3}]}},
    # GFSK (no example scenario uses it) at 250 kbit/s, the noise 4 dB lower
    # than the determinism test's, where it still decides which frames arrive.
    "probe_gfsk": {"phy": {"type": "gfsk", "samples_per_symbol": 4},
                   "channel": {"noise_power_db": -95}},
}


def probe_yaml(overlay):
    """The determinism scenario with `overlay` merged in."""
    doc = yaml.safe_load(scenario_yaml(DET_NODES, DET_TRAFFIC))
    for key, value in overlay.items():
        if key == "channel":
            doc.setdefault("channel", {}).update(value)
        else:
            doc[key] = value
    return yaml.safe_dump(doc, sort_keys=False)


def outcome(summary):
    nodes = [{k: v for k, v in n.items() if k not in NODE_KEYS_LEFT_OUT}
             for n in summary["nodes"]]
    return {"nodes": nodes, **{k: summary[k] for k in TOP_KEYS}}


def run_yaml(text, folder, name):
    """Runs a scenario given as text, written into `folder` (where the
    example's data folders are linked), and returns its outcome."""
    return outcome(run_batch(folder, name, text, timeout=600))


def all_cases(folder):
    """(name, scenario text) of every case, with the examples' data folders
    linked into `folder` so that their relative paths resolve."""
    for entry in os.listdir(SCENARIOS):
        if os.path.isdir(os.path.join(SCENARIOS, entry)):
            os.symlink(os.path.join(SCENARIOS, entry), os.path.join(folder, entry))
    cases = []
    for path in sorted(glob.glob(os.path.join(SCENARIOS, "*.yaml"))):
        with open(path) as f:
            doc = yaml.safe_load(f)
        name = os.path.splitext(os.path.basename(path))[0]
        cases.append((name, yaml.safe_dump(batch_version(doc), sort_keys=False)))
    for name, spec in PROBES.items():
        cases.append((name, probe_yaml(spec)))
    return cases


def git_head():
    r = subprocess.run(["git", "-C", SOURCE_DIR, "rev-parse", "--short", "HEAD"],
                       capture_output=True, text=True)
    return r.stdout.strip() or "unknown"


class ExampleCountersTest(unittest.TestCase):
    def test_every_example_and_probe_gives_the_recorded_counters(self):
        with open(GOLDEN) as f:
            golden = json.load(f)
        with tempfile.TemporaryDirectory() as d:
            cases = all_cases(d)
            self.assertEqual(sorted(golden["cases"]), sorted(name for name, _ in cases),
                             "a scenario was added or removed: record the golden file again")
            for name, text in cases:
                with self.subTest(case=name):
                    got = run_yaml(text, d, name)
                    want = golden["cases"][name]
                    delivered = sum(n["delivered"] for n in got["nodes"])
                    self.assertGreater(delivered, 0, f"{name}: nothing delivered, a vacuous case")
                    for a, b in zip(want["nodes"], got["nodes"]):
                        self.assertEqual(a, b, f"{name}: node {a['id']} differs")
                    self.assertEqual(want, got, f"{name}: outcome differs")


def record():
    with tempfile.TemporaryDirectory() as d:
        cases = {name: run_yaml(text, d, name) for name, text in all_cases(d)}
    with open(GOLDEN, "w") as f:
        json.dump({"recorded_at": git_head(), "command": "tests/integration/test_example_counters.py --record",
                   "cases": cases}, f, indent=1, sort_keys=True)
        f.write("\n")
    print(f"recorded {len(cases)} cases into {GOLDEN}")


if __name__ == "__main__":
    if "--record" in sys.argv:
        record()
    else:
        unittest.main()
