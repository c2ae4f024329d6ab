"""The MAVLink vehicle simulator (mavlink_vehicle.py) checked on its own, before
it is trusted to test the emulator: its checksum and CRC_EXTRA against the
published values, its frames byte for byte against frames captured from real
autopilots and frames worked out by hand from the spec, and its behaviour over
loopback TCP and UDP (ports 43000-43999)."""

import random
import socket
import struct
import time
import unittest

import mavlink_vehicle as mv

# Captured from real autopilots (public hex dumps), with what they decode to.
# Header | custom_mode | type autopilot base_mode system_status version | CRC.
ARDUPILOT_V1_HEARTBEAT = bytes.fromhex('fe094e010100' '00000000' '0203510403' '1c7f')
GCS_V1_HEARTBEAT = bytes.fromhex('fe0966ffbe00' '00000000' '0603000003' '79ed')
PIXHAWK_V2_HEARTBEAT = bytes.fromhex('fd090000ef0101000000' '00000000' '0203510303' '7389')

# Worked out by hand (see tests/unit/mavlink_known_frames_test.cpp for the
# byte-by-byte derivation): GLOBAL_POSITION_INT v2 seq 7 from 1/1, and
# SET_MESSAGE_INTERVAL(33, 200000 us) v2 seq 1 from 1/191 to 1/1, its
# trailing zero confirmation byte truncated.
HAND_POSITION = bytes.fromhex(
    'fd1c0000070101210000' '40e20100' 'c066a119' 'b0c009d1' '90d00300' '10270000'
    '9600' 'ecff' '0500' '2823' '319e')
HAND_SET_INTERVAL = bytes.fromhex(
    'fd20000001' '01bf4c0000' '00000442' '00504348' + '00' * 20 + 'ff01' '0101' 'b974')


def free_port():
    for _ in range(100):
        port = random.randrange(43000, 44000)
        with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s, \
                socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as u:
            try:
                s.bind(('127.0.0.1', port))
                u.bind(('127.0.0.1', port))
                return port
            except OSError:
                continue
    raise RuntimeError('no free port in 43000-43999')


class Codec(unittest.TestCase):
    def test_checksum_is_crc16_mcrf4xx(self):
        self.assertEqual(mv.x25_crc(b'123456789'), 0x6F91)

    def test_crc_extra_matches_the_published_values(self):
        published = {0: 50, 30: 39, 33: 104, 66: 148, 76: 152, 77: 143}
        self.assertEqual({i: m.crc_extra for i, m in mv.MESSAGES.items()}, published)
        self.assertEqual(mv.MESSAGES[77].base_length, 3)
        self.assertEqual(mv.MESSAGES[77].max_length, 10)

    def test_reproduces_captured_ardupilot_v1_heartbeats(self):
        hb = {'type': 2, 'autopilot': 3, 'base_mode': 0x51, 'custom_mode': 0,
              'system_status': 4, 'mavlink_version': 3}
        self.assertEqual(mv.encode(0, hb, seq=0x4E, version=1), ARDUPILOT_V1_HEARTBEAT)
        gcs = {'type': 6, 'autopilot': 3, 'mavlink_version': 3}
        self.assertEqual(mv.encode(0, gcs, seq=0x66, sysid=255, compid=190, version=1),
                         GCS_V1_HEARTBEAT)

    def test_reproduces_captured_pixhawk_v2_heartbeat(self):
        hb = {'type': 2, 'autopilot': 3, 'base_mode': 0x51, 'system_status': 3,
              'mavlink_version': 3}
        self.assertEqual(mv.encode(0, hb, seq=0xEF), PIXHAWK_V2_HEARTBEAT)

    def test_reproduces_hand_derived_frames(self):
        pos = {'time_boot_ms': 123456, 'lat': 430008000, 'lon': -787890000, 'alt': 250000,
               'relative_alt': 10000, 'vx': 150, 'vy': -20, 'vz': 5, 'hdg': 9000}
        self.assertEqual(mv.encode(33, pos, seq=7), HAND_POSITION)
        cmd = {'target_system': 1, 'target_component': 1, 'command': 511, 'param1': 33.0,
               'param2': 200000.0}
        self.assertEqual(mv.encode(76, cmd, seq=1, sysid=1, compid=191), HAND_SET_INTERVAL)

    def test_decoder_reads_every_known_frame_and_zero_extends(self):
        d = mv.Decoder()
        out = d.feed(ARDUPILOT_V1_HEARTBEAT + b'\x00\x01' + HAND_SET_INTERVAL + HAND_POSITION)
        self.assertEqual([m['msgid'] for m in out], [0, 76, 33])
        self.assertEqual(d.garbage_bytes, 2)
        self.assertEqual(out[1]['fields']['confirmation'], 0)
        self.assertEqual(out[1]['fields']['param2'], 200000.0)
        self.assertEqual(out[2]['fields']['lon'], -787890000)

    def test_signed_frame_has_flag_and_13_byte_block(self):
        plain = mv.encode(0, {'type': 2}, version=2)
        signed = mv.encode(0, {'type': 2}, version=2, signed=True)
        self.assertEqual(len(signed), len(plain) + 13)
        self.assertEqual(signed[2], 0x01)
        out = mv.Decoder().feed(signed)
        self.assertTrue(out[0]['signed'])

    def test_corrupt_checksum_is_rejected_and_the_next_frame_found(self):
        bad = bytearray(HAND_POSITION)
        bad[-1] ^= 0xFF
        d = mv.Decoder()
        self.assertEqual([m['msgid'] for m in d.feed(bytes(bad) + PIXHAWK_V2_HEARTBEAT)], [0])
        self.assertEqual(d.bad_crc, 1)


class Client:
    """What the emulator would be: reads the vehicle's frames, sends requests."""

    def __init__(self, sock, udp_peer=None):
        self.sock, self.udp_peer = sock, udp_peer
        self.decoder = mv.Decoder()
        self.messages = []

    def send(self, frame):
        if self.udp_peer:
            self.sock.sendto(frame, self.udp_peer)
        else:
            self.sock.sendall(frame)

    def read_for(self, seconds):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.sock.settimeout(max(end - time.monotonic(), 0.01))
            try:
                data, addr = self.sock.recvfrom(65535)
            except socket.timeout:
                break
            if self.udp_peer is None and self.sock.type == socket.SOCK_DGRAM:
                self.udp_peer = addr
            self.messages += self.decoder.feed(data)

    def read_until(self, done, timeout=30.0):
        """Reads until done(self) holds or `timeout` s passed; whether it holds.
        A loaded machine may delay the vehicle's frames: the wait is generous
        and ends as soon as they are there."""
        end = time.monotonic() + timeout
        while not done(self) and time.monotonic() < end:
            self.read_for(min(0.1, end - time.monotonic()))
        return done(self)

    def ids(self):
        return [m['msgid'] for m in self.messages]

    def positions(self):
        return [m['fields'] for m in self.messages if m['msgid'] == 33]


def median_interval_s(positions):
    """The median spacing of GLOBAL_POSITION_INT reports by the vehicle's own
    clock (time_boot_ms): its sending rate, whatever delays the machine adds
    on the way to the reader. (Counting reports in a second of wall time
    instead fails when the machine is busy.)"""
    gaps = sorted(b['time_boot_ms'] - a['time_boot_ms'] for a, b in zip(positions, positions[1:]))
    return gaps[len(gaps) // 2] / 1000.0


class OverTcp(unittest.TestCase):
    def test_streams_answers_interval_requests_and_records_what_it_got(self):
        port = free_port()
        with mv.MavlinkVehicle(sysid=3, rate_hz=2, zero_fix_reports=2) as v:
            v.serve_tcp(port)
            v.set_position(43.0010, -78.7900, 260.0, home_alt_m=250.0)
            v.set_attitude(0.1, -0.2, 1.5)
            with socket.create_connection(('127.0.0.1', port), timeout=2) as s:
                c = Client(s)
                c.read_until(lambda c: 0 in c.ids() and len(c.positions()) >= 2)
                hb = [m for m in c.messages if m['msgid'] == 0]
                self.assertTrue(hb, c.ids())
                self.assertEqual(hb[0]['fields']['type'], mv.MAV_TYPE_QUADROTOR)
                self.assertEqual(hb[0]['fields']['autopilot'], mv.MAV_AUTOPILOT_ARDUPILOTMEGA)
                self.assertEqual(hb[0]['sysid'], 3)
                pos = c.positions()
                self.assertGreaterEqual(len(pos), 2, 'the default rate before any request')
                self.assertEqual((pos[0]['lat'], pos[0]['lon'], pos[0]['alt']), (0, 0, 0))
                self.assertEqual((pos[1]['lat'], pos[1]['lon'], pos[1]['alt']), (0, 0, 0))
                # The emulator's heartbeat, then 20 Hz position, attitude stopped.
                c.send(mv.encode(0, {'type': 18, 'autopilot': 8, 'system_status': 4,
                                     'mavlink_version': 3}, sysid=3, compid=191))
                for msg_id, interval in ((33, 50000.0), (30, -1.0)):
                    c.send(mv.encode(76, {'target_system': 3, 'target_component': 1,
                                          'command': 511, 'param1': float(msg_id),
                                          'param2': interval}, sysid=3, compid=191))
                v.wait_for(76, count=2, timeout=30)
                c.messages.clear()
                c.read_until(lambda c: c.ids().count(77) >= 2 and len(c.positions()) >= 12)
                acks = [m['fields'] for m in c.messages if m['msgid'] == 77]
                self.assertEqual([(a['command'], a['result'], a['target_component'])
                                  for a in acks], [(511, 0, 191)] * 2)
                pos = c.positions()
                self.assertGreaterEqual(len(pos), 12)
                # 20 Hz, against 2 Hz before the request (the first may still be slow).
                self.assertLess(median_interval_s(pos), 0.2, 'about 0.05 s apart at 20 Hz')
                self.assertLessEqual(c.ids().count(30), 1, 'attitude stopped')
                self.assertEqual(pos[-1]['lat'], 430010000)
                self.assertEqual(pos[-1]['alt'], 260000)
                self.assertEqual(pos[-1]['relative_alt'], 10000)
                self.assertEqual(pos[-1]['hdg'], round(1.5 * 180 / 3.141592653589793 * 100))
                # Garbage and a corrupt frame reach the client as such.
                self.assertTrue(v.inject_garbage(50))
                self.assertTrue(v.inject_corrupt_frame())
                c.read_until(lambda c: c.decoder.garbage_bytes >= 50 and c.decoder.bad_crc >= 1)
                self.assertGreaterEqual(c.decoder.garbage_bytes, 50)
                self.assertEqual(c.decoder.bad_crc, 1)
            self.assertEqual(v.received_ids()[:3], [0, 76, 76])
            self.assertEqual(v.interval_s(33), 0.05)
            self.assertIsNone(v.interval_s(30))

    def test_v1_framing_and_signing_options(self):
        for version, signed in ((1, False), (2, True)):
            port = free_port()
            with mv.MavlinkVehicle(version=version, signed=signed, rate_hz=10) as v:
                v.serve_tcp(port)
                with socket.create_connection(('127.0.0.1', port), timeout=2) as s:
                    c = Client(s)
                    c.read_until(lambda c: len(c.messages) >= 2)
            self.assertTrue(c.messages)
            self.assertEqual({m['version'] for m in c.messages}, {version})
            self.assertEqual({m['signed'] for m in c.messages}, {signed})


class OverUdp(unittest.TestCase):
    def test_sends_to_the_port_and_honours_request_data_stream(self):
        port = free_port()
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            s.bind(('127.0.0.1', port))
            with mv.MavlinkVehicle(sysid=5, rate_hz=1) as v:
                v.send_udp(port)
                c = Client(s)
                c.read_until(lambda c: 0 in c.ids())
                self.assertIn(0, c.ids())
                # REQUEST_DATA_STREAM POSITION at 25 Hz (v1 frame, as old GCSs send).
                c.send(mv.encode(66, {'target_system': 5, 'target_component': 1,
                                      'req_stream_id': 6, 'req_message_rate': 25,
                                      'start_stop': 1}, sysid=5, compid=191, version=1))
                v.wait_for(66, timeout=30)
                c.messages.clear()
                c.read_until(lambda c: len(c.positions()) >= 15)
                self.assertGreaterEqual(len(c.positions()), 15)
                # 25 Hz, against 1 Hz before the request.
                self.assertLess(median_interval_s(c.positions()), 0.2, 'about 0.04 s apart')
                got = v.received_messages(66)[0]
                self.assertEqual((got['version'], got['fields']['req_message_rate']), (1, 25))


if __name__ == '__main__':
    unittest.main()
