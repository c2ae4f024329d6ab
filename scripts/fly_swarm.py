#!/usr/bin/env python3
"""Flies N virtual UAVs on a slow circle and streams their GPS positions to
rfsitl's location ports, as UB-ANC agents do. Standard library only.

    python3 scripts/fly_swarm.py --nodes 6 --loc-base 15766 --seconds 30
"""

import argparse
import json
import math
import socket
import time

ORIGIN_LAT, ORIGIN_LON = 43.0008, -78.7890  # UB-ANC's default home
EARTH_RADIUS_M = 6371000.0


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nodes", type=int, default=6, help="UAVs 1..N to fly (default 6)")
    ap.add_argument("--loc-base", type=int, default=15766,
                    help="location port base of the emulator: node n is base + 10 n")
    ap.add_argument("--host", default="127.0.0.1", help="emulator address")
    ap.add_argument("--radius", type=float, default=8.0, help="formation radius, metres (8)")
    ap.add_argument("--period", type=float, default=60.0, help="seconds per revolution (60)")
    ap.add_argument("--rate", type=float, default=10.0, help="position updates per second (10)")
    ap.add_argument("--seconds", type=float, default=0.0, help="0: until interrupted")
    args = ap.parse_args()

    feeds = [socket.create_connection((args.host, args.loc_base + 10 * n), timeout=10)
             for n in range(1, args.nodes + 1)]
    start = time.monotonic()
    try:
        while args.seconds <= 0 or time.monotonic() - start < args.seconds:
            t = time.monotonic() - start
            for i, feed in enumerate(feeds):
                angle = 2 * math.pi * (i / args.nodes + t / args.period)
                east, north = args.radius * math.cos(angle), args.radius * math.sin(angle)
                # Small offsets: the feeder may use a local tangent plane; the
                # emulator itself converts every position exactly (WGS84 -> ECEF).
                lat = ORIGIN_LAT + math.degrees(north / EARTH_RADIUS_M)
                lon = ORIGIN_LON + math.degrees(
                    east / (EARTH_RADIUS_M * math.cos(math.radians(ORIGIN_LAT))))
                alt = 20.0 + 2.0 * math.sin(angle)
                feed.sendall((json.dumps({"lat": lat, "lon": lon, "alt": alt}) + "\n").encode())
            time.sleep(1.0 / args.rate)
    except (KeyboardInterrupt, BrokenPipeError, ConnectionResetError):
        pass
    finally:
        for feed in feeds:
            feed.close()


if __name__ == "__main__":
    main()
