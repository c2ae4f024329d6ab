"""The rfsitl Python module against the program and the model: the same
counters as `rfsitl run`, scenario errors that name the key, positions that
move the link table as the path-loss formula says, frames decoded in range and
lost out of range, an I/Q tap with the power the link budget gives, the GIL
released while the engine runs, and a real-time run with its ports.

Run by ctest with PYTHONPATH naming the build's package (tests/CMakeLists.txt);
by hand: PYTHONPATH=build/release/python /usr/bin/python3 tests/python/test_module.py
"""

import json
import math
import os
import socket
import subprocess
import sys
import tempfile
import threading
import unittest

import numpy as np

import rfsitl

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.environ.get("RFSITL_SOURCE_DIR", os.path.join(HERE, "..", ".."))
BIN = os.environ.get("RFSITL_BIN")

# Two nodes on a line, the paper's channel: gain = -20 * 3 * log10(d + 1) dB.
PAIR = {
    "name": "pair",
    "seed": 3,
    "time": {"mode": "virtual", "duration_s": 20},
    "nodes": [{"id": 1, "position": {"x": 0, "y": 0, "z": 10}},
              {"id": 2, "position": {"x": 5, "y": 0, "z": 10}}],
}


def paper_gain_db(d, exponent=3.0):
    return -20.0 * exponent * math.log10(d + 1.0)


def link(table, tx, rx):
    row = table[(table["tx"] == tx) & (table["rx"] == rx)]
    assert len(row) == 1, row
    return row.iloc[0]


class ScenarioTest(unittest.TestCase):
    def test_a_wrong_key_in_a_dict_is_named_with_its_path(self):
        bad = json.loads(json.dumps(PAIR))
        bad["nodes"][1]["phy"] = {"type": "gmsk", "bandwidth_tme": 0.3}
        with self.assertRaises(rfsitl.ScenarioError) as e:
            rfsitl.scenario_from_dict(bad)
        self.assertIn("dict: nodes[1].phy.bandwidth_tme", str(e.exception))

    def test_a_string_is_not_a_number_as_in_a_file(self):
        bad = json.loads(json.dumps(PAIR))
        bad["time"]["duration_s"] = "20"
        with self.assertRaises(rfsitl.ScenarioError) as e:
            rfsitl.scenario_from_dict(bad)
        self.assertIn("time.duration_s", str(e.exception))

    def test_yaml_errors_name_source_line_and_key(self):
        with self.assertRaises(rfsitl.ScenarioError) as e:
            rfsitl.scenario_from_yaml("name: x\nnodes:\n  - {id: 1}\ntime: {tick_sample: 4}\n",
                                      "mine.yaml")
        self.assertIn("mine.yaml:4: time.tick_sample", str(e.exception))

    def test_a_file_loads_as_rfsitl_run_reads_it(self):
        sc = rfsitl.load_scenario(os.path.join(SOURCE, "scenarios", "six_uav_batch.yaml"))
        self.assertEqual(sc.node_ids, [1, 2, 3, 4, 5, 6])
        self.assertEqual(sc.duration_s, 10.0)
        with self.assertRaises(rfsitl.ScenarioError):
            sc.with_setting("channel.noise_power_db", "400")
        self.assertEqual(sc.with_setting("time.duration_s", "2").duration_s, 2.0)

    def test_components_are_the_declared_settings(self):
        phys = {c["name"]: c for c in rfsitl.components("phy")}
        self.assertIn("gmsk", phys)
        bt = [s for s in phys["gmsk"]["settings"] if s["name"] == "bandwidth_time"]
        self.assertEqual(len(bt), 1)
        self.assertEqual(bt[0]["type"], "a number")
        if BIN:  # the same data as `rfsitl describe --json`
            out = subprocess.run([BIN, "describe", "--json"], capture_output=True, text=True,
                                 check=True).stdout
            self.assertEqual(json.loads(out), rfsitl.components())


class EmulatorTest(unittest.TestCase):
    @unittest.skipUnless(BIN, "RFSITL_BIN names the rfsitl program")
    def test_counters_equal_rfsitl_runs_for_the_same_scenario_and_seed(self):
        path = os.path.join(SOURCE, "scenarios", "six_uav_batch.yaml")
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "summary.json")
            # No agent is connected: decoded frames count as to_agent_dropped,
            # as keep_frames=False counts them.
            subprocess.run([BIN, "run", path, "--no-dashboard", "--net-base", "24000",
                            "--loc-base", "25000", "--summary-json", out],
                           check=True, capture_output=True, timeout=600)
            with open(out) as f:
                cli = json.load(f)
        emu = rfsitl.Emulator(path, keep_frames=False)
        # In uneven steps: the outcome must not depend on where the steps end.
        emu.run_for(0.37)
        emu.step(41)
        emu.run_until(lambda e: e.now >= 4.0, step_s=0.25)
        py = emu.run()
        self.assertGreater(sum(n["delivered"] for n in cli["nodes"]), 100)
        # Every counter of every node; "source" says how each node's position
        # was fed, which differs (location ports there, none here).
        def counters(nodes):
            return [{k: v for k, v in n.items() if k != "source"} for n in nodes]
        self.assertEqual(counters(py["nodes"]), counters(cli["nodes"]))
        self.assertGreater(len(counters(py["nodes"])[0]), 10)
        table = emu.counters()
        for n in cli["nodes"]:
            self.assertEqual(int(table.loc[n["id"], "delivered"]), n["delivered"])
            self.assertEqual(int(table.loc[n["id"], "received"]), n["received"])

    def test_positions_move_the_link_table_as_the_path_loss_formula_says(self):
        emu = rfsitl.Emulator(PAIR)
        emu.step()
        self.assertAlmostEqual(link(emu.links(), 1, 2)["gain_db"], paper_gain_db(5.0), places=3)
        for d in (1.0, 12.5, 40.0):
            emu.set_position(2, (0.0, d, 10.0))
            emu.step()
            row = link(emu.links(), 1, 2)
            self.assertAlmostEqual(row["distance_m"], d, places=3)
            self.assertAlmostEqual(row["gain_db"], paper_gain_db(d), places=3)
            noise_db = 10 * math.log10(emu.scenario.noise_variance)
            self.assertAlmostEqual(row["snr_db"], paper_gain_db(d) - noise_db, places=3)
            np.testing.assert_allclose(emu.positions()[1], [0.0, d, 10.0], atol=1e-6)

    def test_a_frame_is_decoded_in_range_and_lost_out_of_range(self):
        emu = rfsitl.Emulator(PAIR)
        payload = bytes(range(60))
        self.assertTrue(emu.send(1, 2, payload))
        emu.run_for(0.5)
        got = emu.received(2)
        self.assertEqual(len(got), 1)
        t, src, receiver, data, snr = got[0]
        self.assertEqual((src, receiver, data), (1, 2, payload))
        self.assertGreater(t, 0.0)
        self.assertAlmostEqual(snr, link(emu.links(), 1, 2)["snr_db"], delta=0.5)

        emu.set_position(2, (0.0, 5000.0, 10.0))  # far below the sensitivity
        emu.step()
        self.assertTrue(emu.send(1, 2, payload))
        emu.run_for(0.5)
        self.assertEqual(emu.received(2), [])
        events = emu.events()
        lost = events[events["kind"] == "lost"]
        self.assertEqual(len(lost), 1)
        self.assertEqual(lost.iloc[0]["reason"], "below_sensitivity")
        counters = emu.counters()
        self.assertEqual(int(counters.loc[1, "delivered"]), 1)
        self.assertEqual(int(counters.loc[1, "lost"]), 1)

    def test_a_payload_too_large_and_an_unknown_node_are_refused(self):
        emu = rfsitl.Emulator(PAIR)
        with self.assertRaises(ValueError):
            emu.send(1, 2, bytes(100000))
        with self.assertRaises(KeyError) as e:
            emu.send(9, 2, b"x")
        self.assertIn("node 9 is not in this run (nodes: 1, 2)", str(e.exception))

    def test_the_iq_tap_has_the_power_of_the_link_budget(self):
        emu = rfsitl.Emulator(PAIR)
        emu.tap(2)
        # Frames back to back: node 2 hears node 1 for most of the step.
        for _ in range(30):
            emu.send(1, 2, bytes(200))
        emu.run_for(1.0)
        first_s, x = emu.iq(2)
        self.assertEqual(x.dtype, np.complex64)
        fs = emu.scenario.sample_rate_hz
        on_air = np.zeros(len(x), bool)
        ev = emu.events()
        for _, e in ev[ev["kind"] == "transmitted"].iterrows():
            a = int(round(e["time_s"] * fs - first_s * fs))
            on_air[max(a, 0):max(a + int(e["length_samples"]), 0)] = True
        self.assertGreater(on_air.sum(), 100_000)
        # Noise has unit power at the front end's scale; the signal adds the SNR.
        p_signal = float(np.mean(np.abs(x[on_air].astype(np.complex128)) ** 2)) - 1.0
        snr_db = link(emu.links(), 1, 2)["snr_db"]
        self.assertAlmostEqual(10 * math.log10(p_signal), snr_db, delta=0.1)
        p_quiet = float(np.mean(np.abs(x[~on_air].astype(np.complex128)) ** 2))
        self.assertAlmostEqual(p_quiet, 1.0, delta=0.05)

    def test_the_gil_is_released_while_the_engine_runs(self):
        emu = rfsitl.Emulator(PAIR)
        for _ in range(20):
            emu.send(1, 2, bytes(200))
        seen = []
        done = threading.Event()

        def watch():
            while not done.is_set():
                seen.append(emu.now)  # a thread-safe view of the clock
                done.wait(0.001)

        t = threading.Thread(target=watch)
        t.start()
        try:
            end = emu.run_for(10.0)
        finally:
            done.set()
            t.join()
        self.assertTrue(any(0.0 < v < end for v in seen),
                        "no reading of the clock while the engine ran")

    def test_same_calls_give_the_same_events(self):
        def play():
            emu = rfsitl.Emulator(PAIR)
            for k in range(5):
                emu.send(1 + k % 2, 2 - k % 2, bytes([k]) * 30)
                emu.run_for(0.05)
            emu.run_for(0.5)
            ev = emu.events()
            snr = [None if math.isnan(v) else v for v in ev["snr_db"]]
            return list(zip(ev["time_s"], ev["kind"].astype(str), ev["node"], snr))
        self.assertEqual(play(), play())

    def test_no_step_after_finish(self):
        emu = rfsitl.Emulator(PAIR)
        emu.run_for(0.1)
        summary = emu.finish()
        self.assertEqual([n["id"] for n in summary["nodes"]], [1, 2])
        with self.assertRaises(Exception):
            emu.run_for(0.1)


class RealTimeRunTest(unittest.TestCase):
    def test_a_real_time_run_serves_its_ports_and_stops_cleanly(self):
        sys.path.insert(0, os.path.join(SOURCE, "tests", "integration"))
        import harness  # noqa: E402  (the integration tests' net client)
        net_base, loc_base = harness.pick_port_bases([1, 2])
        sc = rfsitl.scenario_from_dict({
            "name": "rt", "seed": 1, "time": {"duration_s": 0},
            "ports": {"net_base": net_base, "loc_base": loc_base},
            "nodes": PAIR["nodes"],
        })
        with rfsitl.RealTimeRun(sc) as run:
            self.assertTrue(run.running)
            a = harness.NetClient(run.net_port(1)[1])
            b = harness.NetClient(run.net_port(2)[1])
            try:
                # Resend until it arrives: the agent may be admitted after the first.
                got = None
                for _ in range(60):
                    a.send(1, 2, b"hello over the air")
                    got = b.receive(1, timeout=1.0)
                    if got:
                        break
                self.assertTrue(got, "nothing arrived at node 2 within a minute")
                self.assertEqual(got[0], (1, 2, b"hello over the air"))
            finally:
                a.close()
                b.close()
        self.assertFalse(run.running)
        self.assertGreater(run.summary["nodes"][0]["delivered"], 0)
        # The ports are closed again.
        with socket.socket() as s:
            s.bind(("127.0.0.1", run.net_port(1)[1]))


if __name__ == "__main__":
    unittest.main(verbosity=2)
