#!/usr/bin/env python3
"""A MAVLink vehicle for integration tests: streams HEARTBEAT, GLOBAL_POSITION_INT
and ATTITUDE like an autopilot, and answers the requests a ground station or
companion sends for message rates.

Written from the MAVLink specification (https://mavlink.io/en/guide/serialization.html
and common.xml) with the Python standard library only; it shares no code with
the emulator's C++ codec, so each checks the other. test_mavlink_vehicle.py
checks this file against frames captured from real autopilots.

Transports, as the two autopilots' SITL offer them:
  - TCP server (ArduPilot SITL's SERIALn ports): listens on 127.0.0.1, the
    emulator connects as the client; one client at a time, the next accepted
    when it leaves.
  - UDP (PX4 SITL): sends to 127.0.0.1:<port> from its own socket and takes
    whatever comes back to that socket.

    with MavlinkVehicle(sysid=3, rate_hz=2) as v:
        v.serve_tcp(43010)
        v.set_position(43.0008, -78.789, 250.0)
        v.wait_for(76, timeout=5)       # a COMMAND_LONG arrived
        print(v.received_ids())

Command line: python3 mavlink_vehicle.py --tcp 43010 [--v1] [--signed] ...
"""

import argparse
import math
import random
import socket
import struct
import threading
import time

MAGIC_V1 = 0xFE
MAGIC_V2 = 0xFD
INCOMPAT_SIGNED = 0x01
SIGNATURE_BYTES = 13

MAV_TYPE_QUADROTOR = 2
MAV_AUTOPILOT_ARDUPILOTMEGA = 3
MAV_MODE_FLAG_CUSTOM_MODE_ENABLED = 1
MAV_STATE_STANDBY = 3
MAV_CMD_SET_MESSAGE_INTERVAL = 511
MAV_RESULT_ACCEPTED = 0
MAV_RESULT_UNSUPPORTED = 3
MAV_DATA_STREAM_ALL = 0
MAV_DATA_STREAM_POSITION = 6
MAV_DATA_STREAM_EXTRA1 = 10
GARBAGE_BYTES = bytes(b for b in range(256) if b not in (0xFD, 0xFE))  # no magic byte


def x25_crc(data, crc=0xFFFF):
    """CRC-16/MCRF4XX ("X.25" in the MAVLink docs), bit by bit: reflected
    polynomial 0x8408, initial value 0xFFFF, no final XOR."""
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0x8408 if crc & 1 else crc >> 1
    return crc


# Field types of the XML: (struct code, size).
TYPES = {
    'uint8_t': ('B', 1), 'int8_t': ('b', 1), 'uint16_t': ('H', 2), 'int16_t': ('h', 2),
    'uint32_t': ('I', 4), 'int32_t': ('i', 4), 'uint64_t': ('Q', 8), 'float': ('f', 4),
    'uint8_t_mavlink_version': ('B', 1),
}


class MessageDef:
    """One message of common.xml: fields in XML order, split at <extensions>."""

    def __init__(self, msg_id, name, fields, extensions=()):
        self.id = msg_id
        self.name = name
        # Wire order: the base fields stably sorted by size, largest first, then
        # the extensions as declared.
        base = sorted(fields, key=lambda f: -TYPES[f[0]][1])
        self.wire = base + list(extensions)
        self.field_names = [name for _, name in self.wire]
        self.base_length = sum(TYPES[t][1] for t, _ in base)
        self.format = '<' + ''.join(TYPES[t][0] for t, _ in self.wire)
        self.max_length = struct.calcsize(self.format)
        # CRC_EXTRA: the checksum of "NAME " and "type name " for each base field
        # in wire order (no arrays here), folded to one byte.
        crc = x25_crc((name + ' ').encode())
        for t, field in base:
            crc = x25_crc(f"{'uint8_t' if t == 'uint8_t_mavlink_version' else t} {field} ".encode(),
                          crc)
        self.crc_extra = (crc & 0xFF) ^ (crc >> 8)

    def pack(self, values):
        return struct.pack(self.format, *(values.get(n, 0) for n in self.field_names))

    def unpack(self, payload):
        payload = payload[:self.max_length].ljust(self.max_length, b'\0')
        return dict(zip(self.field_names, struct.unpack(self.format, payload)))


MESSAGES = {m.id: m for m in [
    MessageDef(0, 'HEARTBEAT', [
        ('uint8_t', 'type'), ('uint8_t', 'autopilot'), ('uint8_t', 'base_mode'),
        ('uint32_t', 'custom_mode'), ('uint8_t', 'system_status'),
        ('uint8_t_mavlink_version', 'mavlink_version')]),
    MessageDef(30, 'ATTITUDE', [
        ('uint32_t', 'time_boot_ms'), ('float', 'roll'), ('float', 'pitch'), ('float', 'yaw'),
        ('float', 'rollspeed'), ('float', 'pitchspeed'), ('float', 'yawspeed')]),
    MessageDef(33, 'GLOBAL_POSITION_INT', [
        ('uint32_t', 'time_boot_ms'), ('int32_t', 'lat'), ('int32_t', 'lon'), ('int32_t', 'alt'),
        ('int32_t', 'relative_alt'), ('int16_t', 'vx'), ('int16_t', 'vy'), ('int16_t', 'vz'),
        ('uint16_t', 'hdg')]),
    MessageDef(66, 'REQUEST_DATA_STREAM', [
        ('uint8_t', 'target_system'), ('uint8_t', 'target_component'),
        ('uint8_t', 'req_stream_id'), ('uint16_t', 'req_message_rate'), ('uint8_t', 'start_stop')]),
    MessageDef(76, 'COMMAND_LONG', [
        ('uint8_t', 'target_system'), ('uint8_t', 'target_component'), ('uint16_t', 'command'),
        ('uint8_t', 'confirmation')] + [('float', f'param{i}') for i in range(1, 8)]),
    MessageDef(77, 'COMMAND_ACK', [('uint16_t', 'command'), ('uint8_t', 'result')], [
        ('uint8_t', 'progress'), ('int32_t', 'result_param2'), ('uint8_t', 'target_system'),
        ('uint8_t', 'target_component')]),
]}
BY_NAME = {m.name: m for m in MESSAGES.values()}
HEARTBEAT, ATTITUDE, GLOBAL_POSITION_INT = 0, 30, 33


def encode(msg_id, values, seq=0, sysid=1, compid=1, version=2, signed=False):
    """One frame. v2 drops the payload's trailing zeros (keeping one byte) and,
    when `signed`, sets incompat bit 0 and appends a 13-byte signature block
    (link id 0, a timestamp, a zero hash: well-formed, never valid)."""
    m = MESSAGES[msg_id]
    payload = m.pack(values)
    if version == 1:
        payload = payload[:m.base_length]
        header = bytes([MAGIC_V1, len(payload), seq & 0xFF, sysid, compid, msg_id])
    else:
        payload = payload.rstrip(b'\0') or b'\0'
        header = bytes([MAGIC_V2, len(payload), INCOMPAT_SIGNED if signed else 0, 0, seq & 0xFF,
                        sysid, compid]) + struct.pack('<I', msg_id)[:3]
    crc = x25_crc(header[1:] + payload + bytes([m.crc_extra]))
    frame = header + payload + struct.pack('<H', crc)
    if version == 2 and signed:
        # Timestamp: 10 us units since 2015-01-01, 48 bits.
        stamp = int((time.time() - 1420070400) * 1e5) & 0xFFFFFFFFFFFF
        frame += bytes([0]) + stamp.to_bytes(6, 'little') + bytes(6)
    return frame


class Decoder:
    """Streaming frame reader for what the vehicle receives. Known ids are
    checked and decoded; unknown ids cannot be checked and are returned as
    {'msgid': id, 'fields': None}. Bad checksums and bytes outside frames are
    counted; after a bad frame, scanning resumes after its magic byte. Made for
    the clean stream a peer sends (a stray magic byte whose frame has an id not
    listed here swallows the bytes its length claims)."""

    def __init__(self):
        self.buf = bytearray()
        self.garbage_bytes = 0
        self.bad_crc = 0

    def feed(self, data):
        self.buf += data
        out = []
        while True:
            start = next((i for i, b in enumerate(self.buf) if b in (MAGIC_V1, MAGIC_V2)), None)
            if start is None:
                self.garbage_bytes += len(self.buf)
                self.buf.clear()
                return out
            self.garbage_bytes += start
            del self.buf[:start]
            v2 = self.buf[0] == MAGIC_V2
            header_len = 10 if v2 else 6
            if len(self.buf) < header_len:
                return out
            if v2 and self.buf[2] & ~INCOMPAT_SIGNED:
                self.garbage_bytes += 1  # a flag we do not understand: not a frame for us
                del self.buf[:1]
                continue
            length = self.buf[1]
            signed = v2 and self.buf[2] & INCOMPAT_SIGNED
            total = header_len + length + 2 + (SIGNATURE_BYTES if signed else 0)
            if len(self.buf) < total:
                return out
            msg_id = int.from_bytes(self.buf[7:10], 'little') if v2 else self.buf[5]
            seq, sysid, compid = self.buf[4:7] if v2 else self.buf[2:5]
            payload = bytes(self.buf[header_len:header_len + length])
            m = MESSAGES.get(msg_id)
            if m is not None:
                crc = x25_crc(bytes(self.buf[1:header_len + length]) + bytes([m.crc_extra]))
                if struct.unpack_from('<H', self.buf, header_len + length)[0] != crc:
                    self.bad_crc += 1
                    self.garbage_bytes += 1
                    del self.buf[:1]
                    continue
            out.append({'msgid': msg_id, 'version': 2 if v2 else 1, 'seq': seq, 'sysid': sysid,
                        'compid': compid, 'signed': bool(signed),
                        'fields': m.unpack(payload) if m else None})
            del self.buf[:total]


class MavlinkVehicle:
    """A quadrotor on ArduPilot, as far as its position stream goes.

    Streams HEARTBEAT at 1 Hz and GLOBAL_POSITION_INT and ATTITUDE at `rate_hz`
    until asked otherwise by COMMAND_LONG MAV_CMD_SET_MESSAGE_INTERVAL (answered
    with COMMAND_ACK) or REQUEST_DATA_STREAM (POSITION: GLOBAL_POSITION_INT,
    EXTRA1: ATTITUDE, ALL: both). `zero_fix_reports`: that many first position
    reports carry lat = lon = alt = 0, as ArduPilot 4.6 sends before its GPS has
    a fix. Setters and accessors are thread-safe; `received` holds every
    decoded frame that came in, in order."""

    def __init__(self, sysid=1, compid=1, version=2, signed=False, rate_hz=2.0,
                 zero_fix_reports=0, lat=43.0008, lon=-78.7890, alt_m=250.0, home_alt_m=None,
                 integrate_velocity=False):
        self.sysid, self.compid, self.version, self.signed = sysid, compid, version, signed
        self.zero_fix_left = zero_fix_reports
        self.integrate_velocity = integrate_velocity
        self.lock = threading.Lock()
        self.state = {'lat': lat, 'lon': lon, 'alt': alt_m,
                      'home_alt': alt_m if home_alt_m is None else home_alt_m,
                      'vn': 0.0, 've': 0.0, 'vd': 0.0, 'roll': 0.0, 'pitch': 0.0, 'yaw': 0.0,
                      'rollspeed': 0.0, 'pitchspeed': 0.0, 'yawspeed': 0.0}
        self.default_interval = 1.0 / rate_hz if rate_hz > 0 else None
        self.intervals = {HEARTBEAT: 1.0, GLOBAL_POSITION_INT: self.default_interval,
                          ATTITUDE: self.default_interval}
        self.next_due = {}
        self.sent_counts = {HEARTBEAT: 0, GLOBAL_POSITION_INT: 0, ATTITUDE: 0}
        self.received = []
        self.received_cv = threading.Condition(self.lock)
        self.decoder = Decoder()
        self.seq = 0
        self.boot = time.monotonic()
        self.stop_event = threading.Event()
        self.threads = []
        self.peer = None       # callable(bytes) that sends to the current peer, or None
        self.send_lock = threading.Lock()

    # ----- transports -----

    def serve_tcp(self, port, host='127.0.0.1'):
        """Listens on host:port; the connected client gets the stream."""
        server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        server.bind((host, port))
        server.listen(1)
        server.settimeout(0.1)
        self._start(self._tcp_loop, server)
        self._start(self._stream_loop)
        return server.getsockname()[1]

    def send_udp(self, port, host='127.0.0.1', local_port=0):
        """Sends to host:port from a socket bound to 127.0.0.1:local_port and
        reads what comes back to it. Returns the local port."""
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        sock.bind(('127.0.0.1', local_port))
        sock.settimeout(0.1)
        with self.send_lock:
            self.peer = lambda data: sock.sendto(data, (host, port))
        self._start(self._udp_loop, sock)
        self._start(self._stream_loop)
        return sock.getsockname()[1]

    def _start(self, target, *args):
        t = threading.Thread(target=target, args=args, daemon=True)
        t.start()
        self.threads.append(t)

    def _tcp_loop(self, server):
        with server:
            while not self.stop_event.is_set():
                try:
                    conn, _ = server.accept()
                except socket.timeout:
                    continue
                conn.settimeout(0.1)
                with self.send_lock:
                    self.peer = conn.sendall
                with conn:
                    while not self.stop_event.is_set():
                        try:
                            data = conn.recv(4096)
                        except socket.timeout:
                            continue
                        except OSError:
                            break
                        if not data:
                            break
                        self._on_bytes(data)
                with self.send_lock:
                    self.peer = None

    def _udp_loop(self, sock):
        with sock:
            while not self.stop_event.is_set():
                try:
                    data = sock.recv(65535)
                except (socket.timeout, ConnectionRefusedError):
                    continue  # nobody listening yet at the other end
                self._on_bytes(data)

    def _send(self, data):
        with self.send_lock:
            if self.peer is None:
                return False
            try:
                self.peer(data)
                return True
            except OSError:
                return False

    # ----- what it sends -----

    def _frame(self, msg_id, values):
        with self.lock:
            seq = self.seq
            self.seq = (self.seq + 1) & 0xFF
        return encode(msg_id, values, seq, self.sysid, self.compid, self.version, self.signed)

    def _time_boot_ms(self):
        return int((time.monotonic() - self.boot) * 1000) & 0xFFFFFFFF

    def _values(self, msg_id, dt, report=True):
        """Field values of msg_id now; `report` False leaves the count of
        zero-fix reports alone (for injected copies)."""
        with self.lock:
            s = self.state
            if msg_id == HEARTBEAT:
                return {'type': MAV_TYPE_QUADROTOR, 'autopilot': MAV_AUTOPILOT_ARDUPILOTMEGA,
                        'base_mode': MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, 'custom_mode': 0,
                        'system_status': MAV_STATE_STANDBY, 'mavlink_version': 3}
            if msg_id == ATTITUDE:
                return {'time_boot_ms': self._time_boot_ms(), **{k: s[k] for k in (
                    'roll', 'pitch', 'yaw', 'rollspeed', 'pitchspeed', 'yawspeed')}}
            if self.integrate_velocity and dt > 0:
                s['lat'] += s['vn'] * dt / 111319.49
                s['lon'] += s['ve'] * dt / (111319.49 * max(math.cos(math.radians(s['lat'])), 1e-6))
                s['alt'] -= s['vd'] * dt
            no_fix = self.zero_fix_left > 0
            if no_fix and report:
                self.zero_fix_left -= 1
            return {'time_boot_ms': self._time_boot_ms(),
                    'lat': 0 if no_fix else round(s['lat'] * 1e7),
                    'lon': 0 if no_fix else round(s['lon'] * 1e7),
                    'alt': 0 if no_fix else round(s['alt'] * 1000),
                    'relative_alt': 0 if no_fix else round((s['alt'] - s['home_alt']) * 1000),
                    'vx': round(s['vn'] * 100), 'vy': round(s['ve'] * 100),
                    'vz': round(s['vd'] * 100),
                    'hdg': round(math.degrees(s['yaw']) * 100) % 36000}

    def _stream_loop(self):
        last_position = time.monotonic()
        while not self.stop_event.wait(0.005):
            # Nothing is due while no peer listens: a report sent to nobody
            # would use up a zero-fix report before the client connects (a
            # race a loaded machine loses).
            with self.send_lock:
                if self.peer is None:
                    continue
            now = time.monotonic()
            with self.lock:
                due = []
                for msg_id, interval in self.intervals.items():
                    if interval is None:
                        self.next_due.pop(msg_id, None)
                        continue
                    if now >= self.next_due.get(msg_id, 0.0):
                        due.append(msg_id)
                        self.next_due[msg_id] = now + interval
            for msg_id in due:
                dt = 0.0
                if msg_id == GLOBAL_POSITION_INT:
                    dt, last_position = now - last_position, now
                if self._send(self._frame(msg_id, self._values(msg_id, dt))):
                    with self.lock:
                        self.sent_counts[msg_id] += 1

    # ----- what it receives -----

    def _on_bytes(self, data):
        for msg in self.decoder.feed(data):
            self._handle(msg)  # first, so that whoever waits for it sees its effect
            with self.lock:
                self.received.append(msg)
                self.received_cv.notify_all()

    def _for_me(self, fields):
        return fields['target_system'] in (0, self.sysid)

    def _handle(self, msg):
        f = msg['fields']
        if msg['msgid'] == 76 and self._for_me(f):
            result = MAV_RESULT_UNSUPPORTED
            if f['command'] == MAV_CMD_SET_MESSAGE_INTERVAL and int(f['param1']) in self.intervals:
                self._set_interval(int(f['param1']), f['param2'])
                result = MAV_RESULT_ACCEPTED
            self._send(self._frame(77, {'command': f['command'], 'result': result,
                                        'target_system': msg['sysid'],
                                        'target_component': msg['compid']}))
        elif msg['msgid'] == 66 and self._for_me(f):
            ids = {MAV_DATA_STREAM_ALL: (GLOBAL_POSITION_INT, ATTITUDE),
                   MAV_DATA_STREAM_POSITION: (GLOBAL_POSITION_INT,),
                   MAV_DATA_STREAM_EXTRA1: (ATTITUDE,)}.get(f['req_stream_id'], ())
            rate = f['req_message_rate']
            for msg_id in ids:
                self._set_interval(msg_id, 1e6 / rate if f['start_stop'] and rate > 0 else -1)

    def _set_interval(self, msg_id, interval_us):
        with self.lock:
            if interval_us < 0:
                self.intervals[msg_id] = None
            elif interval_us == 0:
                self.intervals[msg_id] = self.default_interval
            else:
                self.intervals[msg_id] = interval_us / 1e6
            self.next_due.pop(msg_id, None)  # the new rate starts now

    # ----- the test's handles -----

    def set_position(self, lat_deg, lon_deg, alt_m, home_alt_m=None):
        with self.lock:
            self.state.update(lat=lat_deg, lon=lon_deg, alt=alt_m)
            if home_alt_m is not None:
                self.state['home_alt'] = home_alt_m

    def set_velocity(self, vn_mps, ve_mps, vd_mps):
        with self.lock:
            self.state.update(vn=vn_mps, ve=ve_mps, vd=vd_mps)

    def set_attitude(self, roll_rad, pitch_rad, yaw_rad, rollspeed=0.0, pitchspeed=0.0,
                     yawspeed=0.0):
        with self.lock:
            self.state.update(roll=roll_rad, pitch=pitch_rad, yaw=yaw_rad, rollspeed=rollspeed,
                              pitchspeed=pitchspeed, yawspeed=yawspeed)

    def interval_s(self, msg_id):
        """The current interval of msg_id in seconds, None when stopped."""
        with self.lock:
            return self.intervals.get(msg_id)

    def sent(self, msg_id):
        with self.lock:
            return self.sent_counts.get(msg_id, 0)

    def inject(self, data):
        """Sends raw bytes to the peer as they are; True if there was one."""
        return self._send(bytes(data))

    def inject_garbage(self, n=32, seed=None):
        """n random bytes that contain no magic byte (pure garbage)."""
        rng = random.Random(seed)
        return self.inject(bytes(rng.choice(GARBAGE_BYTES) for _ in range(n)))

    def inject_corrupt_frame(self, msg_id=GLOBAL_POSITION_INT):
        """A frame of msg_id with its checksum inverted."""
        frame = bytearray(self._frame(msg_id, self._values(msg_id, 0.0, report=False)))
        end = len(frame) - (SIGNATURE_BYTES if self.version == 2 and self.signed else 0)
        frame[end - 2] ^= 0xFF
        frame[end - 1] ^= 0xFF
        return self.inject(frame)

    def received_ids(self):
        with self.lock:
            return [m['msgid'] for m in self.received]

    def received_messages(self, msg_id):
        with self.lock:
            return [m for m in self.received if m['msgid'] == msg_id]

    def wait_for(self, msg_id, timeout=5.0, count=1):
        """Waits until `count` frames of msg_id have arrived; returns them
        (fewer on timeout)."""
        deadline = time.monotonic() + timeout
        with self.received_cv:
            while True:
                got = [m for m in self.received if m['msgid'] == msg_id]
                left = deadline - time.monotonic()
                if len(got) >= count or left <= 0:
                    return got
                self.received_cv.wait(left)

    def stop(self):
        self.stop_event.set()
        for t in self.threads:
            t.join(timeout=2)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    where = ap.add_mutually_exclusive_group(required=True)
    where.add_argument('--tcp', type=int, metavar='PORT', help='listen on 127.0.0.1:PORT')
    where.add_argument('--udp', type=int, metavar='PORT', help='send to 127.0.0.1:PORT')
    ap.add_argument('--udp-local', type=int, default=0, metavar='PORT')
    ap.add_argument('--sysid', type=int, default=1)
    ap.add_argument('--v1', action='store_true', help='MAVLink 1 framing')
    ap.add_argument('--signed', action='store_true', help='append (unverifiable) signatures')
    ap.add_argument('--rate', type=float, default=2.0, help='default position/attitude rate, Hz')
    ap.add_argument('--zero-fix', type=int, default=0, metavar='N',
                    help='first N position reports at lat=lon=alt=0')
    ap.add_argument('--lat', type=float, default=43.0008)
    ap.add_argument('--lon', type=float, default=-78.7890)
    ap.add_argument('--alt', type=float, default=250.0, help='metres MSL')
    ap.add_argument('--velocity', type=float, nargs=3, default=None, metavar=('VN', 'VE', 'VD'),
                    help='m/s NED; the position moves with it')
    ap.add_argument('--duration', type=float, default=0, help='seconds (0: until Ctrl-C)')
    a = ap.parse_args()
    v = MavlinkVehicle(sysid=a.sysid, version=1 if a.v1 else 2, signed=a.signed, rate_hz=a.rate,
                       zero_fix_reports=a.zero_fix, lat=a.lat, lon=a.lon, alt_m=a.alt,
                       integrate_velocity=a.velocity is not None)
    if a.velocity:
        v.set_velocity(*a.velocity)
    if a.tcp is not None:
        print(f'mavlink_vehicle: listening on 127.0.0.1:{v.serve_tcp(a.tcp)}', flush=True)
    else:
        local = v.send_udp(a.udp, local_port=a.udp_local)
        print(f'mavlink_vehicle: sending to 127.0.0.1:{a.udp} from {local}', flush=True)
    try:
        time.sleep(a.duration) if a.duration > 0 else threading.Event().wait()
    except KeyboardInterrupt:
        pass
    v.stop()
    names = {i: m.name for i, m in MESSAGES.items()}
    ids = v.received_ids()
    print('mavlink_vehicle: received', {names.get(i, i): ids.count(i) for i in sorted(set(ids))},
          f'garbage {v.decoder.garbage_bytes} B, bad crc {v.decoder.bad_crc}')


if __name__ == '__main__':
    main()
