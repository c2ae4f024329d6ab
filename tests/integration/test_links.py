"""`rfsitl links` against the real emulator: the live link table agrees with
the dashboard's own numbers (/api/stats) and with the frames the agents saw
delivered, its bounds work, and /metrics carries the same per-link counts."""

import json
import re
import socket
import subprocess
import unittest
import urllib.request

from harness import BIN, Emulator

ROW = re.compile(r"^\s*(\d+) ->\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\d+)\s+(\d+)$")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class LinksTest(unittest.TestCase):
    def links(self, emu, *args):
        return subprocess.run([BIN, "links", "--dashboard-port", str(emu.dashboard_port()), *args],
                              capture_output=True, text=True, timeout=60)

    def test_link_table_matches_the_dashboard_and_the_delivered_frames(self):
        # Node 3 is far: its links exist but decode nothing.
        with Emulator({1: (0, 0, 10), 2: (30, 40, 10), 3: (30000, 0, 10)}) as emu:
            sender, receiver = emu.agent(1), emu.agent(2)
            for i in range(5):
                sender.send(1, 2, b"frame %d" % i)
            self.assertEqual(len(receiver.receive(5)), 5)
            emu.wait_settled()
            r = self.links(emu, "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            doc = json.loads(r.stdout)
            text = self.links(emu)
            stats = emu.stats()
            metrics = urllib.request.urlopen(
                f"http://127.0.0.1:{emu.dashboard_port()}/metrics", timeout=10).read().decode()
            emu.stop()
        self.assertEqual(text.returncode, 0, text.stderr)
        self.assertEqual(doc["nodes"], 3)
        self.assertEqual(doc["links_total"], 6)
        self.assertEqual(len(doc["links"]), 6)
        by_pair = {(l["tx"], l["rx"]): l for l in doc["links"]}
        ids = [n["id"] for n in stats["nodes"]]
        n = len(ids)
        for (tx, rx), l in by_pair.items():
            k = ids.index(tx) * n + ids.index(rx)
            self.assertEqual(l["snr_db"], stats["links"]["snr_db"][k], (tx, rx))
            self.assertEqual(l["gain_db"], stats["links"]["gain_db"][k], (tx, rx))
        one_two = by_pair[(1, 2)]
        self.assertAlmostEqual(one_two["distance_m"], 50.0, delta=0.1)
        self.assertEqual(one_two["received"], 5)
        self.assertEqual(one_two["lost"], 0)
        # Strong link: nearly nothing lost; 30 km: the estimate says lost.
        self.assertLess(one_two["per"], 0.01)
        self.assertGreater(by_pair[(1, 3)]["per"], 0.99)
        # The text table: one row per link, the same numbers.
        rows = [ROW.match(line) for line in text.stdout.splitlines()[2:]]
        self.assertTrue(all(rows), text.stdout)
        self.assertEqual(len(rows), 6, text.stdout)
        row = next(m for m in rows if (m.group(1), m.group(2)) == ("1", "2"))
        self.assertEqual(float(row.group(5)), one_two["snr_db"])
        self.assertEqual((int(row.group(7)), int(row.group(8))), (5, 0))
        self.assertIn('rfsitl_link_frames_total{tx="1",rx="2",outcome="received"} 5\n', metrics)
        m = re.search(r'^rfsitl_link_snr_db\{tx="1",rx="2"\} (\S+)$', metrics, re.M)
        self.assertIsNotNone(m, metrics)
        self.assertAlmostEqual(float(m.group(1)), one_two["snr_db"], delta=0.051)

    def test_top_worst_and_the_snr_floor_bound_the_table(self):
        with Emulator({1: (0, 0, 10), 2: (30, 40, 10), 3: (3000, 0, 10)}) as emu:
            top = json.loads(self.links(emu, "--json", "--top", "2").stdout)
            worst = json.loads(self.links(emu, "--json", "--worst", "1").stdout)
            every = json.loads(self.links(emu, "--json").stdout)
            floor = sorted(l["snr_db"] for l in every["links"])[3]
            above = json.loads(self.links(emu, "--json", "--min-snr", str(floor)).stdout)
            both = self.links(emu, "--top", "1", "--worst", "1")
            emu.stop()
        snrs = sorted((l["snr_db"] for l in every["links"]), reverse=True)
        self.assertEqual([l["snr_db"] for l in top["links"]], snrs[:2])
        self.assertEqual([l["snr_db"] for l in worst["links"]], snrs[-1:])
        # Links are symmetric here (1 -> 2 as 2 -> 1): count ties as the floor does.
        self.assertEqual(len(above["links"]), sum(s >= floor for s in snrs))
        self.assertLess(len(above["links"]), len(snrs))
        self.assertTrue(all(l["snr_db"] >= floor for l in above["links"]))
        self.assertNotEqual(both.returncode, 0, both.stdout)
        self.assertIn("excludes", both.stderr)

    def test_no_emulator_there_is_exit_status_1_naming_the_port(self):
        port = free_port()
        r = subprocess.run([BIN, "links", "--dashboard-port", str(port), "--timeout", "5"],
                           capture_output=True, text=True, timeout=60)
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertIn(f"127.0.0.1:{port}", r.stderr)
        self.assertIn("rfsitl run", r.stderr)


if __name__ == "__main__":
    unittest.main()
