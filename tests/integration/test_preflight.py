"""rfsitl run --preflight: a scenario far beyond any machine (64 receivers of
802.11a/g at 20 Msps, every one run every tick) is called unable to hold real
time, exit 1, whatever the machine's load (a busier machine is only slower);
a real-time run of it warns at start; and the answer for a small swarm comes
in the same form. No timing threshold decides a verdict here."""

import re
import subprocess
import unittest

from harness import BIN, pick_port_bases

HUGE = ["--nodes", "64", "--phy", "ofdm", "--sample-rate", "20e6", "--tick", "2000", "--no-skip",
        "--no-dashboard"]


def rfsitl_run(args, timeout=120):
    return subprocess.run([BIN, "run", *args], capture_output=True, text=True, timeout=timeout,
                          stdin=subprocess.DEVNULL)


class PreflightTest(unittest.TestCase):
    def test_a_huge_scenario_will_not_hold_real_time(self):
        r = rfsitl_run(["--preflight", *HUGE])
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertIn("real time will not hold", r.stdout)
        self.assertRegex(r.stdout, r"needs [0-9.]+ cores of \d+")

    def test_a_real_time_run_of_it_warns_at_start(self):
        net, loc = pick_port_bases(range(1, 65))
        r = rfsitl_run([*HUGE, "--duration", "0.002", "--net-base", str(net), "--loc-base",
                        str(loc), "--stats-interval", "0"])
        self.assertEqual(r.returncode, 0, r.stdout[-2000:] + r.stderr[-2000:])
        self.assertRegex(r.stdout, r"warning: real time will not hold.*rfsitl run --preflight")

    def test_a_small_swarm_gets_its_figures(self):
        r = rfsitl_run(["--preflight", "--nodes", "6", "--no-dashboard"])
        self.assertIn(r.returncode, (0, 1), r.stderr)
        m = re.search(r"preflight \(([0-9.]+) virtual s in [0-9.]+ s\): real time "
                      r"(holds|holds with little margin|will not hold)", r.stdout)
        self.assertIsNotNone(m, r.stdout)
        self.assertGreater(float(m.group(1)), 0.0)
        self.assertIn("stand-in load", r.stdout)
        self.assertEqual(r.returncode == 0, m.group(2) != "will not hold")

    def test_preflight_and_no_preflight_exclude_each_other(self):
        r = rfsitl_run(["--preflight", "--no-preflight", "--nodes", "2"])
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--no-preflight", r.stderr + r.stdout)


if __name__ == "__main__":
    unittest.main()
