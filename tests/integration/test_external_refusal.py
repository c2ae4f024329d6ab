"""A process the emulator refuses keeps trying to join: `rfsitl node` pointed
at a node that runs the "samples" role (`--phy external`). The emulator counts
every refusal but logs only the first few in full and the rest as a count; the
process backs off instead of retrying 20-40 times a second, and tells its user
why it is refused, once."""

import re
import subprocess
import time
import unittest

from harness import BIN, Emulator


class ExternalRefusalTest(unittest.TestCase):
    def test_wrong_role_process_backs_off_says_why_once_and_the_log_stays_short(self):
        nodes = {1: (0, 0, 10), 2: (10, 0, 10)}
        # The run starts at once without its samples-role nodes (they may join later).
        with Emulator(nodes, extra_yaml="external: {start_timeout_s: 0}\n",
                      args=["--phy", "external"]) as emu:
            socket_path = f"/tmp/rfsitl-{emu.net_base}.sock"
            started = time.monotonic()
            node = subprocess.run([BIN, "node", "--socket", socket_path, "--id", "1",
                                   "--connect-timeout", "3"],
                                  capture_output=True, text=True, timeout=60)
            took = time.monotonic() - started
            summary = emu.stop()
        self.assertEqual(node.returncode, 1, node.stderr)
        self.assertGreaterEqual(took, 2.9)
        reason = "node 1 expects role 'samples', the program connected as 'transceiver'"
        # Once as soon as it is refused, once more in the final error it exits with.
        notices = [l for l in node.stderr.splitlines() if "refused this node" in l]
        self.assertEqual(len(notices), 1, node.stderr)
        self.assertIn(reason, notices[0])
        self.assertIn(socket_path, notices[0])
        self.assertIn("rejected: " + reason, node.stderr.splitlines()[-1])

        # Backoff from 50 ms: about 7 attempts in 3 s (a fixed 50 ms pause made 60).
        refused = summary["external"]["rejected_connections"]
        self.assertGreaterEqual(refused, 4)
        self.assertLessEqual(refused, 10)

        # The emulator's log: the first three in full, the rest as a count (the
        # last one when the run ends), adding up to every refusal.
        output = "".join(emu.output)
        full = re.findall(r"refused a connection: " + re.escape(reason), output)
        self.assertEqual(len(full), 3, output)
        more = [int(n) for n in re.findall(r"refused (\d+) more connection", output)]
        self.assertEqual(len(full) + sum(more), refused, output)
        self.assertEqual([n["joins"] for n in summary["external"]["nodes"]], [0, 0])


if __name__ == "__main__":
    unittest.main()
