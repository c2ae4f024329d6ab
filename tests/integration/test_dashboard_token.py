"""The dashboard's control token (issue 15, item 7): with --dashboard-control on
an address beyond loopback, moving nodes needs a token the emulator draws and
prints once as a URL; without it or with a wrong one a move is refused (401 or
a WebSocket error) and counted, while viewing works. On loopback nothing
changes unless the user gives a token (--dashboard-token-file).

The non-loopback address is one of our own: as root the test makes a network
namespace (rfsitl-tok-PID) with a veth pair holding 10.213.0.1/24, runs the
emulator in it with `ip netns exec`, and talks to it from this thread moved
into the namespace with setns(2); the namespace is deleted in every case.
"""

import ctypes
import json
import os
import re
import shutil
import subprocess
import tempfile
import time
import unittest
import urllib.error
import urllib.request

from harness import BIN, Emulator, assert_accounted, pick_port_bases
from ws_client import WsClient

ADDR = "10.213.0.1"
NS = f"rfsitl-tok-{os.getpid()}"
CLONE_NEWNET = 0x40000000
NODES = {1: (0, 0, 10), 2: (20, 0, 10)}


def ip(*args, check=True):
    return subprocess.run(["ip", *args], capture_output=True, text=True, check=check, timeout=30)


class NetNamespace:
    """A network namespace with ADDR on a veth pair (or, where veth is
    unavailable, on its loopback interface: still an address the emulator must
    treat as reachable from elsewhere). `inside()` moves this thread into it."""

    def __enter__(self):
        ip("netns", "add", NS)
        try:
            ip("-n", NS, "link", "set", "lo", "up")
            if ip("-n", NS, "link", "add", "v0", "type", "veth", "peer", "name", "v1",
                  check=False).returncode == 0:
                ip("-n", NS, "addr", "add", f"{ADDR}/24", "dev", "v0")
                ip("-n", NS, "link", "set", "v0", "up")
                ip("-n", NS, "link", "set", "v1", "up")
            else:
                ip("-n", NS, "addr", "add", f"{ADDR}/32", "dev", "lo")
            self._libc = ctypes.CDLL(None, use_errno=True)
            self._home = os.open("/proc/thread-self/ns/net", os.O_RDONLY)
            self._ns = os.open(f"/var/run/netns/{NS}", os.O_RDONLY)
        except BaseException:
            ip("netns", "del", NS, check=False)
            raise
        return self

    def _setns(self, fd):
        if self._libc.setns(fd, CLONE_NEWNET) != 0:
            err = ctypes.get_errno()
            raise OSError(err, f"setns: {os.strerror(err)}")

    def enter(self):
        self._setns(self._ns)

    def leave(self):
        self._setns(self._home)

    def __exit__(self, *exc):
        try:
            self.leave()
        finally:
            os.close(self._ns)
            os.close(self._home)
            ip("netns", "del", NS, check=False)
        return False


def http(url, method="GET", body=None, headers=None):
    """(status, parsed JSON or text, headers); errors are answers too."""
    req = urllib.request.Request(url, data=body.encode() if body else None, method=method,
                                 headers=headers or {})
    try:
        with urllib.request.urlopen(req, timeout=10) as r:
            status, text, hdrs = r.status, r.read().decode(), r.headers
    except urllib.error.HTTPError as e:
        status, text, hdrs = e.code, e.read().decode(), e.headers
    try:
        return status, json.loads(text), hdrs
    except ValueError:
        return status, text, hdrs


class Viewer(WsClient):
    """A dashboard viewer on /ws that can wait for a message of one type."""

    def next_of(self, kind, timeout=20.0):
        """The next message of type `kind`, skipping the periodic ones."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            m = self.read()
            if m.get("type") == kind:
                return m
        raise AssertionError(f"no {kind} message within {timeout} s")


def position_x(base, node_id):
    """Node `node_id`'s local x now; None before the engine's first tick."""
    _, snap, _ = http(base + "api/snapshot")
    for n in snap["nodes"]:
        if n["id"] == node_id:
            return n["position"]["x"] if n["position"] else None
    raise KeyError(node_id)


def near(base, node_id, x):
    p = position_x(base, node_id)
    return p is not None and abs(p - x) < 1e-3


def wait_for(predicate, what, timeout=30.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


def virtual_s(base):
    return http(base + "api/stats")[1]["virtual_s"]


def refused_total(base):
    _, text, _ = http(base + "metrics")
    m = re.search(r"^rfsitl_dashboard_control_refused_total (\d+)$", text, re.M)
    assert m, "no rfsitl_dashboard_control_refused_total in /metrics"
    return int(m.group(1))


def ticks_pass(base, seconds=0.2):
    """Waits until the engine has run `seconds` of virtual time more: a move it
    had accepted would have been applied by then."""
    start = virtual_s(base)
    wait_for(lambda: virtual_s(base) >= start + seconds, "the engine to run on")


@unittest.skipUnless(os.geteuid() == 0 and shutil.which("ip"),
                     "needs root and iproute2 to make a network namespace")
class BeyondLoopbackTest(unittest.TestCase):
    def test_moves_need_the_printed_token_viewing_does_not(self):
        with NetNamespace() as ns:
            emu = Emulator(NODES, args=["--bind", ADDR, "--dashboard-control"])
            emu.args = ["ip", "netns", "exec", NS] + emu.args
            with emu:
                ns.enter()
                try:
                    self.check_token_run(emu)
                finally:
                    ns.leave()
                summary = emu.stop()
            assert_accounted(self, summary)

    def check_token_run(self, emu):
        out = "".join(emu.output)
        m = re.search(rf"rfsitl: dashboard control URL .*: (http://{re.escape(ADDR)}:(\d+)/)"
                      r"\?token=([0-9a-f]+)\n", out)
        self.assertIsNotNone(m, "no control URL with a token in the banner:\n" + out)
        base, port, token = m.group(1), int(m.group(2)), m.group(3)
        self.assertEqual(len(token), 32, "128 bits in hex")
        self.assertIn(f"rfsitl: dashboard {base} (moving nodes only with the control token",
                      out)
        wait_for(lambda: position_x(base, 2) is not None, "the engine's first tick")
        x0 = position_x(base, 2)

        # Viewing needs no token: the page, the API, a WebSocket viewer.
        status, page, _ = http(base)
        self.assertEqual(status, 200)
        self.assertIn("<html", page.lower())
        # The page hands the token of its URL to the WebSocket upgrade.
        _, js, _ = http(base + "connection.js")
        self.assertIn("get('token')", js)
        self.assertIn("/ws${query}", js)
        self.assertEqual(http(base + "api/stats")[0], 200)
        viewer = Viewer(ADDR, port)
        hello = viewer.next_of("hello")
        self.assertIs(hello["control"], False)
        self.assertIn("control token", hello["control_refused"])
        self.assertIn("nodes", viewer.next_of("snapshot"))

        # Refused: POST without a token, with a wrong one (header, query); WebSocket
        # moves without a token and with a wrong one.
        wrong = "0" * 32
        body = json.dumps({"x": 30, "y": 0, "z": 10})
        url = base + "api/nodes/2/position"
        for extra, headers in (("", {}), ("", {"Authorization": f"Bearer {wrong}"}),
                               (f"?token={wrong}", {})):
            status, answer, hdrs = http(url + extra, "POST", body, headers)
            self.assertEqual(status, 401, answer)
            self.assertIn("Bearer", hdrs.get("WWW-Authenticate", ""))
            self.assertIn("token", answer["error"])
        viewer.send({"type": "move", "node": 2, "x": 30, "y": 0, "z": 10})
        self.assertIn("needs the dashboard's control token", viewer.next_of("error")["message"])
        impostor = Viewer(ADDR, port, f"/ws?token={wrong}")
        self.assertIs(impostor.next_of("hello")["control"], False)
        impostor.send({"type": "move", "node": 2, "x": 30, "y": 0, "z": 10})
        self.assertIn("wrong control token", impostor.next_of("error")["message"])
        self.assertEqual(refused_total(base), 5)
        ticks_pass(base)
        self.assertAlmostEqual(position_x(base, 2), x0, places=3)

        # Accepted: the token as a Bearer header, then as the page sends it.
        status, answer, _ = http(url, "POST", body, {"Authorization": f"Bearer {token}"})
        self.assertEqual(status, 200, answer)
        wait_for(lambda: near(base, 2, 30), "node 2 at x = 30")
        owner = Viewer(ADDR, port, f"/ws?token={token}")
        hello = owner.next_of("hello")
        self.assertIs(hello["control"], True)
        self.assertNotIn("control_refused", hello)
        owner.send({"type": "move", "node": 2, "x": 40, "y": 0, "z": 10})
        wait_for(lambda: near(base, 2, 40), "node 2 at x = 40")
        self.assertEqual(refused_total(base), 5)
        for v in (viewer, impostor, owner):
            v.close()
        # Refusals are logged (naming the request), the token is printed once,
        # and no token a client sent reaches the log.
        wait_for(lambda: "dashboard: a move from viewer" in "".join(emu.output)
                 and "dashboard: a move from POST /api/nodes/2/position refused"
                 in "".join(emu.output), "the refusals in the log")
        out = "".join(emu.output)
        self.assertEqual(out.count(token), 1, out)
        self.assertNotIn(wrong, out)


class LoopbackTest(unittest.TestCase):
    def test_loopback_control_needs_no_token(self):
        with Emulator(NODES, args=["--dashboard-control"]) as emu:
            out = "".join(emu.output)
            self.assertNotIn("token", out)
            base = f"http://127.0.0.1:{emu.dashboard_port()}/"
            status, answer, _ = http(base + "api/nodes/2/position", "POST",
                                     json.dumps({"x": 30, "y": 0, "z": 10}))
            self.assertEqual(status, 200, answer)
            wait_for(lambda: near(base, 2, 30), "node 2 at x = 30")
            summary = emu.stop()
        assert_accounted(self, summary)

    def test_a_token_file_makes_loopback_control_need_it_and_stays_out_of_the_output(self):
        token = "file-token_" + os.urandom(12).hex()
        with tempfile.TemporaryDirectory(prefix="rfsitl-tok-") as d:
            path = os.path.join(d, "token")
            with open(path, "w") as f:
                f.write(token + "\n")
            with Emulator(NODES, args=["--dashboard-control", "--dashboard-token-file",
                                       path]) as emu:
                base = f"http://127.0.0.1:{emu.dashboard_port()}/"
                self.assertIn("moving nodes only with the control token you gave",
                              "".join(emu.output))
                url = base + "api/nodes/2/position"
                body = json.dumps({"x": 25, "y": 0, "z": 10})
                self.assertEqual(http(url, "POST", body)[0], 401)
                self.assertEqual(http(url, "POST", body,
                                      {"Authorization": f"Bearer {token}x"})[0], 401)
                self.assertEqual(http(url + f"?token={token}", "POST", body)[0], 200)
                wait_for(lambda: near(base, 2, 25), "node 2 at x = 25")
                self.assertEqual(refused_total(base), 2)
                summary = emu.stop()
                self.assertNotIn(token, "".join(emu.output))
            assert_accounted(self, summary)

    def test_unusable_tokens_are_refused_before_the_run(self):
        with tempfile.TemporaryDirectory(prefix="rfsitl-tok-") as d:
            short = os.path.join(d, "short")
            with open(short, "w") as f:
                f.write("abc\n")
            cases = [
                (["--dashboard-control", "--dashboard-token-file", short],
                 "--dashboard-token-file " + short + ": the token must be 16 to 256"),
                (["--dashboard-control", "--dashboard-token-file", os.path.join(d, "missing")],
                 "cannot read"),
                (["--dashboard-control", "--dashboard-token", "has spaces in it, see?"],
                 "--dashboard-token: the token may contain only"),
                (["--dashboard-token", "a" * 20], "--dashboard-control"),
            ]
            for args, text in cases:
                net_base, loc_base = pick_port_bases([1, 2])
                r = subprocess.run([BIN, "run", "--nodes", "2", "--net-base", str(net_base),
                                    "--loc-base", str(loc_base), "--dashboard-port", "0",
                                    "--stats-interval", "0", *args],
                                   capture_output=True, text=True, timeout=60)
                self.assertNotEqual(r.returncode, 0, args)
                self.assertIn(text, r.stdout + r.stderr, args)


if __name__ == "__main__":
    unittest.main(verbosity=2)
