"""What a new user meets first, from the command line: --help shows each
flag's type, a repeated flag and a flag that cannot work with the scenario say
which flag (and where the scenario set what conflicts), a broken scenario file
points at a line it has and at the data file really tried, and `rfsitl
mavlink-send` stands in for an autopilot so that --mavlink can be tried
without one. UDP ports for the stand-in vehicles: 44000-44999."""

import os
import re
import subprocess
import tempfile
import unittest

from harness import BIN, Emulator
from test_mavlink_source import free_ports, located, node_of


def cli(*args, timeout=60):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=timeout,
                          stdin=subprocess.DEVNULL)


def write(folder, name, text):
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        f.write(text)
    return path


class HelpTest(unittest.TestCase):
    NUMERIC = {"--net-base": "UINT", "--loc-base": "UINT", "--speed": "FLOAT",
               "--duration": "FLOAT", "--sample-rate": "FLOAT", "--tick": "UINT",
               "--tick-us": "FLOAT", "--seed": "UINT", "--threads": "UINT", "--noise-db": "FLOAT",
               "--stats-interval": "FLOAT", "--external-timeout": "FLOAT"}

    def test_run_help_shows_each_flags_type(self):
        r = cli("run", "--help")
        self.assertEqual(r.returncode, 0, r.stderr)
        for flag, kind in self.NUMERIC.items():
            m = re.search(rf"^\s*{flag} (\S+)", r.stdout, re.M)
            self.assertIsNotNone(m, f"{flag} missing from:\n{r.stdout}")
            self.assertEqual(m.group(1).split("=")[0], kind, m.group(0))
        self.assertRegex(r.stdout, r"--net-base UINT=15763")

    def test_no_command_shows_a_number_as_text(self):
        # Every option whose default is a number has a numeric type.
        for command in ("run", "sweep", "ping", "node", "describe", "mavlink-send"):
            r = cli(command, "--help")
            self.assertEqual(r.returncode, 0, command + ": " + r.stderr)
            for m in re.finditer(r"^\s*(--[\w-]+) TEXT=(-?\d+(?:\.\d+)?(?:e-?\d+)?)\s", r.stdout, re.M):
                self.fail(f"rfsitl {command}: {m.group(1)} shows its number as TEXT")


class FlagErrorTest(unittest.TestCase):
    def test_a_repeated_flag_is_named(self):
        r = cli("run", "--speed", "1", "--speed", "2", "--duration", "0.1")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--speed given 2 times; give it once", r.stderr)
        self.assertNotIn("At Most", r.stderr)

    def test_mavlink_on_a_virtual_time_scenario_names_the_flag_and_the_line(self):
        with tempfile.TemporaryDirectory() as d:
            path = write(d, "mob.yaml",
                         "nodes:\n  - {id: 1, position: {x: 0, y: 0, z: 10}}\n  - {id: 2, position: "
                         "{x: 5, y: 0, z: 10}}\ntime:\n  mode: virtual\n  duration_s: 1\n")
            r = cli("run", path, "--mavlink", "udp:127.0.0.1:40500+1", "--no-dashboard")
            self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
            self.assertIn("rfsitl run: --mavlink: ", r.stderr)
            self.assertIn(f"time.mode virtual at {path}:5", r.stderr)
            # And given on the command line, the flag that set it.
            r = cli("run", "--nodes", "2", "--mode", "virtual", "--mavlink",
                    "udp:127.0.0.1:40500+1", "--no-dashboard")
            self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
            self.assertIn("--mavlink: ", r.stderr)
            self.assertIn("time.mode virtual at --mode", r.stderr)


class ScenarioFileErrorTest(unittest.TestCase):
    def test_a_yaml_syntax_error_points_at_a_line_the_file_has(self):
        with tempfile.TemporaryDirectory() as d:
            path = write(d, "syn.yaml", "nodes:\n  - {id: 1, position: {x: 0, y: 0, z: 10}}\nphy: {type: gmsk\n")
            r = cli("run", path, "--no-dashboard")
            self.assertEqual(r.returncode, 2)
            m = re.search(r"syn\.yaml:(\d+): YAML syntax", r.stderr)
            self.assertIsNotNone(m, r.stderr)
            self.assertLessEqual(int(m.group(1)), 3)

    def test_a_missing_trace_names_the_scenario_line_and_the_path_tried(self):
        with tempfile.TemporaryDirectory() as d:
            path = write(d, "walk.yaml",
                         "nodes:\n  - {id: 1, position: {x: 0, y: 0, z: 10}}\n"
                         "  - id: 2\n    mobility: {type: trace, file: nosuch.csv}\n")
            # Run from elsewhere: the file is looked for beside the scenario.
            r = subprocess.run([BIN, "run", path, "--no-dashboard"], capture_output=True,
                               text=True, timeout=60, cwd="/", stdin=subprocess.DEVNULL)
            self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
            self.assertIn(f"{path}:4: nodes[1].mobility: ", r.stderr)
            self.assertIn(os.path.join(os.path.realpath(d), "nosuch.csv"), r.stderr)


class MavlinkSendTest(unittest.TestCase):
    def test_stand_in_vehicles_move_the_nodes_over_udp(self):
        base = free_ports(2, 1, kind=__import__("socket").SOCK_DGRAM)
        endpoint = f"udp:127.0.0.1:{base}+1"
        with Emulator({1: None, 2: None}, args=["--mavlink", endpoint]) as emu:
            sender = subprocess.Popen(
                [BIN, "mavlink-send", endpoint, "--vehicles", "2", "--spacing", "30",
                 "--north", "2", "--rate", "20"],
                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                stdin=subprocess.DEVNULL)
            try:
                # Vehicle 2 starts 30 m east of vehicle 1; both fly north at 2 m/s.
                st = emu.wait_until(
                    lambda s: located(1, 4.0, tol=100)(s) and located(2, 4.0, tol=100)(s)
                    and node_of(s, 1)["position"]["y"] > 4.0,
                    timeout=30, what="both nodes placed and moving north")
                p1, p2 = node_of(st, 1)["position"], node_of(st, 2)["position"]
                self.assertAlmostEqual(p2["x"] - p1["x"], 30.0, delta=1.0)
                self.assertEqual(node_of(st, 1)["source"]["type"], "mavlink")
                self.assertEqual(node_of(st, 1)["source"]["detail"]["bad_crc"], 0)
                later = emu.wait_until(
                    lambda s: node_of(s, 1)["position"]["y"] > p1["y"] + 2.0,
                    timeout=30, what="node 1 moved on")
                self.assertGreater(node_of(later, 1)["position"]["y"], p1["y"])
            finally:
                sender.terminate()
                out, _ = sender.communicate(timeout=30)
            self.assertIn("sending to udp:127.0.0.1:", out)
            self.assertIn("stopped after", out)
            emu.stop()


if __name__ == "__main__":
    unittest.main()
