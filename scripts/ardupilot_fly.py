#!/usr/bin/env python3
"""Flies one ArduPilot SITL copter to a point with plain MAVLink: GUIDED mode,
arm, take off, then a SET_POSITION_TARGET_GLOBAL_INT set-point some metres
north/east of where it took off. Standard library only; the few MAVLink v2
messages it needs are packed by hand from the message definitions (field
order by size, CRC over header + payload + the message's CRC_EXTRA byte).

    python3 scripts/ardupilot_fly.py --connect tcp:127.0.0.1:5780 \\
        --north 600 --alt 30 --speed 12

Connect to a port the copter serves that nobody else uses: ArduPilot SITL
instance I serves SERIAL0 on TCP 5760 + 10 I and SERIAL1 on 5762 + 10 I
(rfsitl follows the copter on SERIAL1, so this script takes SERIAL0).
It waits for the copter's heartbeat, retries arming until the pre-arm checks
pass (in SITL about 42 s after start-up, once the EKF uses the GPS),
and exits 0 once the copter is within --tolerance metres of the target,
leaving it hovering there in GUIDED mode (or landing it with --land).
"""

import argparse
import math
import socket
import struct
import sys
import threading
import time

# --- MAVLink v2 framing ------------------------------------------------------

STX_V1, STX_V2 = 0xFE, 0xFD
OUR_SYSID, OUR_COMPID = 250, 190        # a ground station's ids (MAV_COMP_ID_MISSIONPLANNER)

# id: (name, CRC_EXTRA, struct format of the payload in wire order)
MESSAGES = {
    0: ("HEARTBEAT", 50, "<IBBBBB"),
    23: ("PARAM_SET", 168, "<fBB16sB"),
    24: ("GPS_RAW_INT", 24, "<QiiiHHHHBB"),        # the v2 extension fields are not read
    33: ("GLOBAL_POSITION_INT", 104, "<IiiiihhhH"),
    76: ("COMMAND_LONG", 152, "<fffffffHBBB"),
    77: ("COMMAND_ACK", 143, "<HB"),                # progress etc. are extensions
    86: ("SET_POSITION_TARGET_GLOBAL_INT", 5, "<IiifffffffffHBBB"),
    253: ("STATUSTEXT", 83, "<B50s"),
}
BY_NAME = {name: (msgid, extra, fmt) for msgid, (name, extra, fmt) in MESSAGES.items()}

MAV_CMD_DO_SET_MODE = 176
MAV_CMD_DO_CHANGE_SPEED = 178
MAV_CMD_COMPONENT_ARM_DISARM = 400
MAV_CMD_NAV_TAKEOFF = 22
MAV_CMD_SET_MESSAGE_INTERVAL = 511
MAV_RESULT = {0: "ACCEPTED", 1: "TEMPORARILY_REJECTED", 2: "DENIED", 3: "UNSUPPORTED",
              4: "FAILED", 5: "IN_PROGRESS", 6: "CANCELLED"}
COPTER_MODE = {"STABILIZE": 0, "GUIDED": 4, "LOITER": 5, "RTL": 6, "LAND": 9}
MAV_FRAME_GLOBAL_RELATIVE_ALT_INT = 6
# SET_POSITION_TARGET type_mask: use x/y/z only (ignore velocity, acceleration, yaw, yaw rate)
POSITION_ONLY = 0b0000_1101_1111_1000
MAV_PARAM_TYPE_REAL32 = 9
EARTH_RADIUS_M = 6378137.0


def x25(data, crc=0xFFFF):
    """CRC-16/MCRF4XX, the checksum MAVLink calls X.25."""
    for byte in data:
        tmp = (byte ^ crc) & 0xFF
        tmp = (tmp ^ (tmp << 4)) & 0xFF
        crc = ((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4)) & 0xFFFF
    return crc


class Link:
    """One MAVLink v2 stream over TCP: pack, send, and read decoded messages."""

    def __init__(self, endpoint, timeout=60.0):
        kind, host, port = endpoint.split(":")
        if kind != "tcp":
            raise SystemExit(f"{endpoint}: only tcp:HOST:PORT is supported")
        deadline = time.monotonic() + timeout
        while True:
            try:
                self.sock = socket.create_connection((host, int(port)), timeout=2)
                break
            except OSError as err:
                if time.monotonic() > deadline:
                    raise SystemExit(f"{endpoint}: cannot connect: {err}")
                time.sleep(0.5)
        self.sock.settimeout(0.2)
        self.buf = bytearray()
        self.seq = 0
        self.lock = threading.Lock()

    def send(self, name, *fields):
        msgid, extra, fmt = BY_NAME[name]
        payload = struct.pack(fmt, *fields).rstrip(b"\0") or b"\0"   # v2 trims trailing zeros
        header = struct.pack("<BBBBBBBHB", STX_V2, len(payload), 0, 0, self.seq,
                             OUR_SYSID, OUR_COMPID, msgid & 0xFFFF, msgid >> 16)
        crc = x25(bytes([extra]), x25(header[1:] + payload))
        with self.lock:
            self.seq = (self.seq + 1) & 0xFF
            self.sock.sendall(header + payload + struct.pack("<H", crc))

    def recv(self):
        """Returns (name, sysid, compid, fields) of the next known message, or None
        after 0.2 s without one."""
        while True:
            msg = self._parse_one()
            if msg is not None:
                return msg
            try:
                chunk = self.sock.recv(4096)
            except socket.timeout:
                return None
            if not chunk:
                raise SystemExit("autopilot closed the connection")
            self.buf += chunk

    def _parse_one(self):
        buf = self.buf
        while buf:
            if buf[0] not in (STX_V1, STX_V2):
                del buf[0]
                continue
            v2 = buf[0] == STX_V2
            hlen = 10 if v2 else 6
            if len(buf) < hlen:
                return None
            plen = buf[1]
            signed = v2 and (buf[2] & 0x01)
            total = hlen + plen + 2 + (13 if signed else 0)
            if len(buf) < total:
                return None
            frame = bytes(buf[:total])
            if v2:
                sysid, compid = frame[5], frame[6]
                msgid = frame[7] | frame[8] << 8 | frame[9] << 16
            else:
                sysid, compid, msgid = frame[3], frame[4], frame[5]
            known = MESSAGES.get(msgid)
            crc_ok = known is not None and struct.unpack_from("<H", frame, hlen + plen)[0] == \
                x25(bytes([known[1]]), x25(frame[1:hlen + plen]))
            if known is None or not crc_ok:
                # Unknown or corrupt: drop only the start byte when corrupt, so a
                # false start inside real data cannot swallow the next frame.
                del buf[:total if known is None else 1]
                continue
            del buf[:total]
            name, _, fmt = known
            size = struct.calcsize(fmt)
            payload = frame[hlen:hlen + plen][:size].ljust(size, b"\0")
            return name, sysid, compid, struct.unpack(fmt, payload)
        return None


# --- the flight ----------------------------------------------------------------

class Copter:
    def __init__(self, link, verbose=True):
        self.link = link
        self.verbose = verbose
        self.sysid = self.compid = None
        self.position = None          # (lat deg, lon deg, relative alt m)
        self.fix_type = 0
        self.mode = None
        self.armed = False
        self.acks = {}
        self._stop = threading.Event()

    def log(self, text):
        if self.verbose:
            print(f"ardupilot_fly: {text}", flush=True)

    def pump(self, seconds):
        """Reads and tracks messages for this many seconds."""
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            msg = self.link.recv()
            if msg is None:
                continue
            name, sysid, compid, f = msg
            # The autopilot forwards what other programs on its other ports send
            # (a ground station, rfsitl): take the first heartbeat of a real
            # autopilot (not MAV_AUTOPILOT_INVALID, not a MAV_TYPE_GCS) and
            # listen to that system and component only.
            if name == "HEARTBEAT" and self.sysid is None and f[2] != 8 and f[1] != 6:
                self.sysid, self.compid = sysid, compid
                self.log(f"autopilot sysid {sysid} compid {compid}")
            if (sysid, compid) != (self.sysid, self.compid):
                continue
            if name == "HEARTBEAT":
                self.mode, self.armed = f[0], bool(f[3] & 0x80)
            elif name == "GLOBAL_POSITION_INT":
                self.position = (f[1] / 1e7, f[2] / 1e7, f[4] / 1000.0)
            elif name == "GPS_RAW_INT":
                self.fix_type = f[8]
            elif name == "COMMAND_ACK":
                self.acks[f[0]] = f[1]
            elif name == "STATUSTEXT":
                self.log("autopilot says: " + f[1].split(b"\0")[0].decode(errors="replace"))

    def heartbeats(self):
        while not self._stop.wait(1.0):
            try:
                self.link.send("HEARTBEAT", 0, 6, 8, 0, 0, 3)   # GCS, no autopilot, active
            except OSError:
                return

    def command(self, cmd, *params, wait=5.0):
        """COMMAND_LONG; returns the MAV_RESULT of its COMMAND_ACK, or None."""
        p = list(params) + [0.0] * (7 - len(params))
        self.acks.pop(cmd, None)
        self.link.send("COMMAND_LONG", *p, cmd, self.sysid, self.compid, 0)
        end = time.monotonic() + wait
        while cmd not in self.acks and time.monotonic() < end:
            self.pump(0.1)
        return self.acks.get(cmd)

    def set_param(self, name, value):
        self.link.send("PARAM_SET", float(value), self.sysid, self.compid,
                       name.encode(), MAV_PARAM_TYPE_REAL32)

    def stream(self, msgid, hz):
        return self.command(MAV_CMD_SET_MESSAGE_INTERVAL, msgid, 1e6 / hz)


def offset(lat, lon, north_m, east_m):
    """The point north_m/east_m metres from lat/lon (flat earth; fine for a few km)."""
    dlat = math.degrees(north_m / EARTH_RADIUS_M)
    dlon = math.degrees(east_m / (EARTH_RADIUS_M * math.cos(math.radians(lat))))
    return lat + dlat, lon + dlon


def distance_m(a, b):
    north = math.radians(b[0] - a[0]) * EARTH_RADIUS_M
    east = math.radians(b[1] - a[1]) * EARTH_RADIUS_M * math.cos(math.radians(a[0]))
    return math.hypot(north, east)


def result_name(result):
    return "no answer" if result is None else MAV_RESULT.get(result, str(result))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--connect", default="tcp:127.0.0.1:5760",
                    help="the copter's MAVLink port (default tcp:127.0.0.1:5760, SERIAL0 of instance 0)")
    ap.add_argument("--north", type=float, default=0.0, help="target, metres north of take-off")
    ap.add_argument("--east", type=float, default=0.0, help="target, metres east of take-off")
    ap.add_argument("--alt", type=float, default=30.0, help="altitude above home, metres (30)")
    ap.add_argument("--speed", type=float, default=0.0,
                    help="horizontal speed, m/s (default: the copter's WPNAV_SPEED)")
    ap.add_argument("--tolerance", type=float, default=5.0, help="arrived within this, metres (5)")
    ap.add_argument("--no-arming-checks", action="store_true",
                    help="set ARMING_CHECK 0 first (SITL only: skips the pre-arm checks)")
    ap.add_argument("--land", action="store_true", help="land at the target instead of hovering")
    ap.add_argument("--timeout", type=float, default=600.0, help="give up after this many seconds")
    args = ap.parse_args()

    start = time.monotonic()

    def time_left():
        if time.monotonic() - start > args.timeout:
            raise SystemExit(f"ardupilot_fly: gave up after {args.timeout:.0f} s")
        return True

    copter = Copter(Link(args.connect))
    threading.Thread(target=copter.heartbeats, daemon=True).start()
    while copter.sysid is None and time_left():
        copter.pump(0.5)
    for msgid in (33, 24):                     # GLOBAL_POSITION_INT, GPS_RAW_INT at 4 Hz
        copter.stream(msgid, 4)
    if args.no_arming_checks:
        copter.set_param("ARMING_CHECK", 0)
        copter.log("ARMING_CHECK set to 0")

    copter.log("waiting for a 3D GPS fix")
    while (copter.fix_type < 3 or not copter.position or copter.position[0] == 0) and time_left():
        copter.pump(0.5)
    result = copter.command(MAV_CMD_DO_SET_MODE, 1, COPTER_MODE["GUIDED"])
    copter.log(f"GUIDED mode: {result_name(result)}")

    # Pre-arm checks fail until the EKF has a good position; the ack says DENIED
    # or FAILED until then, and the autopilot explains why in a STATUSTEXT.
    while time_left():
        result = copter.command(MAV_CMD_COMPONENT_ARM_DISARM, 1)
        if result == 0:
            break
        copter.log(f"arming: {result_name(result)}, retrying")
        copter.pump(3.0)
    copter.log("armed")
    home = copter.position
    result = copter.command(MAV_CMD_NAV_TAKEOFF, 0, 0, 0, 0, 0, 0, args.alt)
    copter.log(f"take-off to {args.alt:.0f} m: {result_name(result)}")
    if result != 0:
        raise SystemExit(1)
    while copter.position[2] < 0.9 * args.alt and time_left():
        copter.pump(0.5)

    if args.speed > 0:
        result = copter.command(MAV_CMD_DO_CHANGE_SPEED, 1, args.speed, -1)
        copter.log(f"speed {args.speed:g} m/s: {result_name(result)}")
    target = offset(home[0], home[1], args.north, args.east)
    copter.log(f"flying to {target[0]:.6f}, {target[1]:.6f} at {args.alt:.0f} m "
               f"({args.north:g} m north, {args.east:g} m east of take-off)")
    last_report = 0.0
    while time_left():
        copter.link.send("SET_POSITION_TARGET_GLOBAL_INT", 0, round(target[0] * 1e7),
                         round(target[1] * 1e7), args.alt, 0, 0, 0, 0, 0, 0, 0, 0,
                         POSITION_ONLY, copter.sysid, copter.compid,
                         MAV_FRAME_GLOBAL_RELATIVE_ALT_INT)
        copter.pump(1.0)
        left = distance_m(copter.position, target)
        if time.monotonic() - last_report >= 5:
            last_report = time.monotonic()
            copter.log(f"{distance_m(home, copter.position):6.0f} m from take-off, "
                       f"{left:6.0f} m to go, {copter.position[2]:.0f} m up")
        if left <= args.tolerance:
            break
    copter.log("arrived")
    if args.land:
        copter.log(f"LAND mode: {result_name(copter.command(MAV_CMD_DO_SET_MODE, 1, COPTER_MODE['LAND']))}")
    copter._stop.set()
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:
        sys.exit(130)
