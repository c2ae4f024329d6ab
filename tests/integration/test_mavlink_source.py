"""The MAVLink position source end to end: `rfsitl run --mavlink` follows three
vehicles (mavlink_vehicle.py, written from the specification and sharing no
code with the emulator) and the links follow them: a vehicle that flies out of
range stops receiving and gets its frames back when it returns; a vehicle that
disconnects is reconnected to and asked for its stream again; garbage, corrupt
frames and another system's flood are counted while the run and the last good
position stay. Ports: 44000-44999 for the vehicles."""

import math
import os
import random
import socket
import subprocess
import tempfile
import unittest

import mavlink_vehicle as mv
from harness import BIN, Emulator, assert_accounted, scenario_yaml

ORIGIN = (43.0008, -78.7890)  # the scenario default
METRES_PER_DEG_LAT = 111_000.0  # close enough to place vehicles; the test reads x/y back


def free_ports(count, step=1, kind=socket.SOCK_STREAM):
    """A base port in 44000-44999 with base + step * k free (TCP or UDP) for k < count."""
    for _ in range(200):
        base = random.randrange(44000, 45000 - step * count)
        held = []
        try:
            for k in range(count):
                s = socket.socket(socket.AF_INET, kind)
                held.append(s)
                s.bind(("127.0.0.1", base + step * k))
            return base
        except OSError:
            continue
        finally:
            for s in held:
                s.close()
    raise RuntimeError("no free ports in 44000-44999")


def at(north_m, east_m=0.0, alt=10.0):
    lat = ORIGIN[0] + north_m / METRES_PER_DEG_LAT
    lon = ORIGIN[1] + east_m / (METRES_PER_DEG_LAT * math.cos(math.radians(ORIGIN[0])))
    return lat, lon, alt


def node_of(stats, node_id):
    return next(n for n in stats["nodes"] if n["id"] == node_id)


def located(node_id, north_m, tol=2.0):
    def check(stats):
        p = node_of(stats, node_id)["position"]
        return p is not None and abs(p["y"] - north_m) < tol
    return check


class MavlinkSourceTest(unittest.TestCase):
    STEP = 10

    def start_vehicles(self, base, extra=None):
        vehicles = []
        for k, north in enumerate((0.0, 8.0, 0.0)):
            east = 8.0 if k == 2 else 0.0
            lat, lon, alt = at(north, east)
            v = mv.MavlinkVehicle(sysid=k + 1, rate_hz=1.0, lat=lat, lon=lon, alt_m=alt,
                                  **(extra or {}).get(k, {}))
            v.serve_tcp(base + self.STEP * k)
            vehicles.append(v)
        self.addCleanup(lambda: [v.stop() for v in vehicles])
        return vehicles

    def exchange(self, a_src, a_dst, src, dst, tag, expected=True):
        """Sends tag src -> dst; what arrives (waiting long for an expected
        frame, briefly for one that should not arrive)."""
        a_src.send(src, dst, tag)
        return a_dst.receive(1) if expected else a_dst.receive(1, timeout=1.0)

    def test_three_vehicles_links_follow_them_out_of_range_and_back_and_through_a_reconnect(self):
        base = free_ports(3, self.STEP)
        # Vehicle 3 has no fix until the test gives it one, as ArduPilot SITL at start.
        v1, v2, v3 = self.start_vehicles(base, extra={2: {"zero_fix_reports": 10**9}})
        endpoint = f"tcp:127.0.0.1:{base}+{self.STEP}"
        with Emulator({1: None, 2: None, 3: None}, args=["--mavlink", endpoint]) as emu:
            banner = "".join(emu.output)
            self.assertIn(f"follows mavlink tcp:127.0.0.1:{base + self.STEP}", banner)
            # Each vehicle is asked for its stream at 10 Hz with SET_MESSAGE_INTERVAL.
            for v in (v1, v2, v3):
                asks = v.wait_for(76, timeout=20, count=2)
                self.assertGreaterEqual(len(asks), 2)
                self.assertEqual({round(a["fields"]["param1"]) for a in asks}, {33, 30})
                self.assertEqual(asks[0]["fields"]["param2"], 100000.0)
                heartbeats = v.wait_for(0, timeout=5)
                self.assertEqual(heartbeats[0]["fields"]["type"], 18)  # onboard controller
            # Without a fix node 3 stays unknown (not at 0 N 0 E).
            st = emu.wait_until(lambda s: node_of(s, 3)["source"]["detail"]["no_fix"] >= 3,
                                timeout=20, what="zero-fix reports")
            self.assertIsNone(node_of(st, 3)["position"])
            self.assertEqual(node_of(st, 3)["source"]["updates"], 0)
            with v3.lock:
                v3.zero_fix_left = 0
            st = emu.wait_until(lambda s: all(located(i, n)(s) for i, n in
                                              ((1, 0.0), (2, 8.0), (3, 0.0))),
                                timeout=30, what="three positions")
            n3 = node_of(st, 3)
            self.assertAlmostEqual(n3["position"]["x"], 8.0, delta=2.0)
            self.assertEqual(n3["source"]["type"], "mavlink")
            self.assertTrue(n3["source"]["connected"])

            # Velocity (NED from the vehicle, shown east/north/up) and attitude.
            v1.set_velocity(3.0, -1.5, -0.5)
            v1.set_attitude(0.1, -0.05, 1.2)
            st = emu.wait_until(lambda s: node_of(s, 1).get("velocity", {}).get("north_mps") == 3.0,
                                timeout=20, what="node 1's velocity")
            n1 = node_of(st, 1)
            self.assertEqual(n1["velocity"], {"east_mps": -1.5, "north_mps": 3.0, "up_mps": 0.5})
            st = emu.wait_until(lambda s: "attitude" in node_of(s, 1)
                                and abs(node_of(s, 1)["attitude"]["yaw_rad"] - 1.2) < 1e-3,
                                timeout=20, what="node 1's attitude")
            self.assertAlmostEqual(node_of(st, 1)["attitude"]["roll_rad"], 0.1, places=3)
            v1.set_velocity(0.0, 0.0, 0.0)

            a1, a2, a3 = emu.agent(1), emu.agent(2), emu.agent(3)
            self.assertEqual(self.exchange(a1, a2, 1, 2, b"near"), [(1, 2, b"near")])
            self.assertEqual(self.exchange(a1, a3, 1, 3, b"three"), [(1, 3, b"three")])

            # Vehicle 2 flies 1 km north: out of range.
            v2.set_position(*at(1000.0))
            emu.wait_until(located(2, 1000.0, tol=5.0), timeout=20, what="node 2 at 1 km")
            for i in range(3):
                self.assertEqual(self.exchange(a1, a2, 1, 2, b"far %d" % i, expected=False), [])
            # All three lost before it comes back (a lagging run may still hold them).
            emu.wait_until(lambda s: node_of(s, 1)["lost"]["below_sensitivity"] == 3,
                           what="the far frames' outcome")
            # And back.
            v2.set_position(*at(8.0))
            emu.wait_until(located(2, 8.0), timeout=20, what="node 2 back")
            self.assertEqual(self.exchange(a1, a2, 1, 2, b"back"), [(1, 2, b"back")])

            # Vehicle 2 goes away (its link drops) and a new one serves its port.
            v2.stop()
            emu.wait_until(lambda s: not node_of(s, 2)["source"]["connected"], timeout=20,
                           what="node 2 disconnected")
            # Silent past stale_after_s (3 s): shown stale, at its last position.
            st = emu.wait_until(lambda s: node_of(s, 2)["source"]["stale"], timeout=20,
                                what="node 2 stale")
            self.assertTrue(located(2, 8.0)(st))
            lat, lon, alt = at(16.0)
            v2b = mv.MavlinkVehicle(sysid=2, rate_hz=1.0, lat=lat, lon=lon, alt_m=alt)
            self.addCleanup(v2b.stop)
            v2b.serve_tcp(base + self.STEP)
            self.assertGreaterEqual(len(v2b.wait_for(76, timeout=20, count=2)), 2)  # asked again
            st = emu.wait_until(located(2, 16.0), timeout=20, what="node 2 after the reconnect")
            self.assertGreaterEqual(node_of(st, 2)["source"]["reconnects"], 1)
            self.assertEqual(self.exchange(a1, a2, 1, 2, b"again"), [(1, 2, b"again")])

            # Hostile input on vehicle 1's link: garbage, corrupt frames, a flood
            # from another system that claims to be far away.
            before = node_of(emu.stats(), 1)["source"]
            for i in range(5):
                self.assertTrue(v1.inject_garbage(64, seed=i))
                self.assertTrue(v1.inject_corrupt_frame())
            far = {"time_boot_ms": 0, "lat": round(at(5000.0)[0] * 1e7), "lon": round(ORIGIN[1] * 1e7),
                   "alt": 10000, "relative_alt": 0, "vx": 0, "vy": 0, "vz": 0, "hdg": 0}
            self.assertTrue(v1.inject(b"".join(
                mv.encode(mv.GLOBAL_POSITION_INT, far, seq=i, sysid=99) for i in range(200))))
            # Each garbage run and its corrupt frame cost at least one counted
            # rejection: the corrupt frame's CRC failure, or, when the garbage
            # holds a magic byte whose would-be frame names a message id the
            # parser does not know, that unknown id: the parser then steps
            # over the would-be frame's whole length, which may swallow the
            # corrupt frame (or the vehicle's next frame, whichever of them
            # the scheduler let in first: why the CRC count alone varies).
            def rejected(src):
                d = src["detail"]
                return d["bad_crc"] + d["unknown_id"] + d["bad_length"] + d["bad_incompat_flags"]

            st = emu.wait_until(
                lambda s: node_of(s, 1)["source"]["detail"]["other_system"] >= 200
                and rejected(node_of(s, 1)["source"]) >= rejected(before) + 5,
                timeout=20, what="hostile input counted")
            src = node_of(st, 1)["source"]
            # A magic byte in the garbage makes a candidate whose dropped bytes
            # count as rejected, not garbage: together they cover the runs.
            self.assertGreaterEqual(
                src["detail"]["garbage_bytes"] + src["detail"]["rejected_bytes"], 5 * 64)
            self.assertTrue(src["connected"])
            self.assertTrue(located(1, 0.0)(st))  # the flood did not move it
            self.assertEqual(self.exchange(a2, a1, 2, 1, b"still"), [(2, 1, b"still")])
            summary = emu.stop()
        out = "".join(emu.output)
        self.assertIn("bad checksum", out)
        self.assertIn("message from system 99 ignored", out)
        self.assertIn("no position fix yet", out)
        # The summary has each node's final position both ways, and its source.
        n2 = emu.node(2)
        self.assertAlmostEqual(n2["position"]["y"], 16.0, delta=2.0)
        self.assertAlmostEqual(n2["position"]["lat"], at(16.0)[0], delta=2e-5)
        self.assertEqual(n2["source"]["where"], f"tcp:127.0.0.1:{base + self.STEP}, system 2")
        self.assertGreaterEqual(n2["source"]["updates"], 3)
        self.assertEqual(emu.node(1)["delivered"], 4)  # near, three, back, again
        self.assertEqual(emu.node(1)["lost"]["below_sensitivity"], 3)
        assert_accounted(self, summary)

    def test_udp_endpoint_listens_and_answers_the_vehicle(self):
        base = free_ports(2, kind=socket.SOCK_DGRAM)
        lat, lon, alt = at(5.0)
        yaml = f"position: {{source: mavlink, endpoint: \"udp:127.0.0.1:{base}+1\", rate_hz: 5}}\n"
        with Emulator({1: (0, 0, 10), 2: None}, extra_yaml=yaml) as emu:
            v = mv.MavlinkVehicle(sysid=42, rate_hz=1.0, lat=lat, lon=lon, alt_m=alt, version=1)
            self.addCleanup(v.stop)
            v.send_udp(base + 1)  # node 2's port: base + 1 * (2 - 1)
            asks = v.wait_for(76, timeout=20, count=2)
            self.assertGreaterEqual(len(asks), 2)
            self.assertEqual(asks[0]["fields"]["param2"], 200000.0)  # 5 Hz
            self.assertEqual(asks[0]["version"], 1)  # answered in the vehicle's version
            st = emu.wait_until(located(2, 5.0), timeout=20, what="node 2 from UDP")
            self.assertEqual(node_of(st, 2)["source"]["where"],
                             f"udp:127.0.0.1:{base + 1}, system 42")
            # Node 1's vehicle never speaks: it keeps its scenario start position.
            n1 = node_of(st, 1)
            self.assertEqual(n1["source"]["type"], "mavlink")
            self.assertFalse(n1["source"]["connected"])
            self.assertAlmostEqual(n1["position"]["z"], 10.0, delta=0.01)
            self.assertEqual(n1["source"]["overrides"], {"updates": 0, "errors": 0})
            # Its location port still moves it (an override, until the vehicle's
            # next report), counted apart from the MAVLink counts.
            feed = emu.feed(1)
            feed.move_local(0, 3, 10)
            feed.send_line("not a position")
            # (Counted when the line is read; the engine applies it at a later tick.)
            st = emu.wait_until(
                lambda s: node_of(s, 1)["source"]["overrides"] == {"updates": 1, "errors": 1}
                and located(1, 3.0, tol=0.01)(s), what="node 1's override counted and applied")
            self.assertEqual(node_of(st, 1)["source"]["updates"], 0)
            emu.stop()

    def test_a_location_feed_without_velocity_gets_one_by_differencing(self):
        with Emulator({1: (0, 0, 10), 2: (5, 0, 10)}) as emu:
            feed = emu.feed(2)
            x = 5.0

            def moving_east(stats):
                nonlocal x
                x += 1.0  # one metre per poll, east: a few tens of m/s
                feed.move_local(x, 0, 10)
                v = node_of(stats, 2).get("velocity")
                return v is not None and v["east_mps"] > 5.0
            st = emu.wait_until(moving_east, timeout=30, what="an eastward velocity")
            v = node_of(st, 2)["velocity"]
            self.assertLess(abs(v["north_mps"]), 0.2 * v["east_mps"])
            self.assertLess(abs(v["up_mps"]), 0.2 * v["east_mps"])
            src = node_of(st, 2)["source"]
            self.assertEqual(src["type"], "location_port")
            self.assertEqual(src["where"], f"127.0.0.1:{emu.loc_port(2)}")
            self.assertGreaterEqual(src["updates"], 2)
            self.assertEqual(src["errors"], 0)
            self.assertTrue(src["connected"])
            self.assertNotIn("overrides", src)
            emu.stop()

    def run_refused(self, args, yaml_extra=""):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "s.yaml")
            with open(path, "w") as f:
                f.write(scenario_yaml({1: (0, 0, 10), 2: None}, yaml_extra))
            r = subprocess.run([BIN, "run", path, "--no-dashboard", *args], capture_output=True,
                               text=True, timeout=60)
        return r.returncode, r.stdout + r.stderr, path

    def test_virtual_time_and_bad_endpoints_are_refused_before_anything_starts(self):
        rc, out, _ = self.run_refused(["--mavlink", "tcp:127.0.0.1:5762+10", "--mode", "virtual"])
        self.assertEqual(rc, 2, out)
        self.assertIn("wall clock", out)
        rc, out, _ = self.run_refused(["--mavlink", "tcp:5762"])
        self.assertEqual(rc, 2, out)
        self.assertIn("--mavlink: expected tcp:HOST:PORT", out)
        rc, out, path = self.run_refused(
            [], "position: {source: mavlink, endpoint: \"tcp:127.0.0.1:5762\", rate_hz: 0}\n")
        self.assertEqual(rc, 2, out)
        self.assertRegex(out, r"s\.yaml:\d+: position\.rate_hz: ")
        rc, out, _ = self.run_refused(
            [], "position: {source: mavlink, endpoint: \"tcp:127.0.0.1:65530+10\"}\n")
        self.assertEqual(rc, 2, out)
        self.assertIn("node 2: mavlink endpoint tcp:127.0.0.1:65530+10 gives a port above 65535", out)


if __name__ == "__main__":
    unittest.main()
