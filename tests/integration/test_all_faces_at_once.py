"""Every face of a running emulator busy at the same time, on two engine worker
threads: agents flooding two links, a location feed moving one receiver, two
WebSocket viewers of the dashboard (one watching a node's spectrum and
constellations, one moving a node with --dashboard-control), and /api/stats
and /metrics polled from another thread. It gives ThreadSanitizer
(scripts/test_tsan.sh) every thread of the emulator at once; under any build it
checks that none of this disturbs the frames: every frame reaches its agent
intact and in order, and the books balance.

The two links are 1 km apart (1 -> 2 at x = 0, 3 -> 4 at x = 1000): neither
hears the other above the noise, so no frame is lost to a collision and every
one must arrive."""

import json
import threading
import time
import unittest
import urllib.request

from harness import ARRIVAL_S, Emulator, assert_accounted
from ws_client import WsClient

NODES = {1: (0, 0, 10), 2: (6, 0, 10), 3: (1000, 0, 10), 4: (1006, 0, 10)}
ROUNDS = 10
PER_ROUND = 4


class WebSocketViewer:
    """A dashboard viewer on /ws, reading every message on a thread of its own."""

    def __init__(self, port):
        self.ws = WsClient("127.0.0.1", port, timeout=ARRIVAL_S)
        self.messages = []
        self.lock = threading.Lock()
        self.thread = threading.Thread(target=self._read_all, daemon=True)
        self.thread.start()

    def _read_all(self):
        try:
            while True:
                message = self.ws.read()
                with self.lock:
                    self.messages.append(message)
        except (ConnectionError, OSError):
            pass  # closed (or idle past ARRIVAL_S, which the test's checks notice)

    def send(self, message):
        self.ws.send(message)

    def of_type(self, kind):
        with self.lock:
            return [m for m in self.messages if m.get("type") == kind]

    def close(self):
        self.ws.close()
        self.thread.join(10)


class Poller:
    """Polls /api/stats and /metrics until stopped; keeps every failure."""

    def __init__(self, base_url):
        self.base_url = base_url
        self.polls = 0
        self.failures = []
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        while not self.stop.is_set():
            try:
                with urllib.request.urlopen(self.base_url + "api/stats", timeout=ARRIVAL_S) as r:
                    json.load(r)
                with urllib.request.urlopen(self.base_url + "metrics", timeout=ARRIVAL_S) as r:
                    if b"rfsitl_" not in r.read():
                        self.failures.append("/metrics without rfsitl_ metrics")
                self.polls += 1
            except Exception as e:  # noqa: BLE001 (kept and reported by the test)
                self.failures.append(repr(e))

    def finish(self):
        self.stop.set()
        self.thread.join(ARRIVAL_S)


def node_of(stats, node_id):
    return next(n for n in stats["nodes"] if n["id"] == node_id)


class AllFacesAtOnceTest(unittest.TestCase):
    def test_frames_arrive_intact_while_every_face_is_busy(self):
        with Emulator(NODES, args=["--threads", "2", "--dashboard-control"]) as emu:
            port = emu.dashboard_port()
            watcher, mover = WebSocketViewer(port), WebSocketViewer(port)
            self.addCleanup(watcher.close)
            self.addCleanup(mover.close)
            watcher.send({"type": "watch", "node": 2})
            poller = Poller(f"http://127.0.0.1:{port}/")
            self.addCleanup(poller.finish)
            a1, a2, a3, a4 = (emu.agent(i) for i in (1, 2, 3, 4))
            feed = emu.feed(4)
            sent = {2: [], 4: []}
            for r in range(ROUNDS):
                for k in range(PER_ROUND):
                    for agent, src, dst in ((a1, 1, 2), (a3, 3, 4)):
                        payload = b"%d->%d round %d frame %d " % (src, dst, r, k) + bytes(40)
                        agent.send(src, dst, payload)
                        sent[dst].append((src, dst, payload))
                # Receivers move a little every round, one by its feed, one by a viewer.
                feed.move_local(1006 + r % 3, 0, 10)
                mover.send({"type": "move", "node": 2, "x": 6 + r % 3, "y": 0, "z": 10})
                emu.wait_until(lambda st: node_of(st, 1)["handed_in"] == PER_ROUND * (r + 1)
                               and node_of(st, 3)["handed_in"] == PER_ROUND * (r + 1),
                               what=f"round {r}'s frames handed in")
            emu.wait_settled()
            # Every frame intact and in order at its agent, and nothing more.
            self.assertEqual(a2.receive(len(sent[2])), sent[2])
            self.assertEqual(a4.receive(len(sent[4])), sent[4])
            self.assertEqual(a2.receive(1, timeout=0.3) + a4.receive(1, timeout=0.3), [])
            # The last moves reached the engine (the move is applied at a tick).
            last = 6 + (ROUNDS - 1) % 3
            emu.wait_until(lambda st: abs(node_of(st, 2)["position"]["x"] - last) < 0.01
                           and abs(node_of(st, 4)["position"]["x"] - (1000 + last)) < 0.01,
                           what="the last positions")
            # The watcher saw node 2's spectrum and a constellation of a frame it decoded.
            deadline = time.monotonic() + ARRIVAL_S
            while not (watcher.of_type("constellation") and watcher.of_type("spectrum")):
                self.assertLess(time.monotonic(), deadline, "no spectrum or constellation")
                time.sleep(0.05)
            poller.finish()
            summary = emu.stop()
        self.assertEqual(len(watcher.of_type("hello")), 1)
        self.assertGreaterEqual(len(watcher.of_type("snapshot")), 2)
        self.assertEqual({m["node"] for m in watcher.of_type("constellation")}, {2})
        self.assertEqual({m["node"] for m in watcher.of_type("spectrum")}, {2})
        self.assertTrue(mover.of_type("hello")[0]["control"], mover.of_type("hello"))
        self.assertEqual(mover.of_type("error"), [])
        self.assertEqual(poller.failures, [])
        self.assertGreater(poller.polls, 0)
        for src in (1, 3):
            self.assertEqual(emu.node(src)["delivered"], ROUNDS * PER_ROUND, emu.node(src))
        for dst in (2, 4):
            self.assertEqual(emu.node(dst)["to_agent_dropped"], 0, emu.node(dst))
        assert_accounted(self, summary)


if __name__ == "__main__":
    unittest.main()
