#!/usr/bin/env python3
"""Writes the hand-made seeds of fuzz/corpus/ (the scenario seeds are copies of
scenarios/*.yaml). Run from anywhere: python3 fuzz/make_seeds.py"""
import json
import os
import shutil
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
T = b'\r\r\n\n'


def w(target, name, data):
    d = os.path.join(HERE, 'corpus', target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), 'wb') as f:
        f.write(data.encode() if isinstance(data, str) else data)


# net_framing: [max_payload u16 le][cut-point seed][stream]
def hdr(mp, seed):
    return struct.pack('<H', mp) + bytes([seed])


w('net_framing', 'ubanc_frames', hdr(2048 | 0xF000, 7) + b'\x01\x02hello from 1' + T + b'\x02\xffbroadcast' + T)
w('net_framing', 'ping_80_bytes', hdr(0xF800, 3) + b'\x01\x02' + bytes(range(80)) + T)
w('net_framing', 'oversized_resync', hdr(8, 1) + b'\x01\x02' + b'x' * 20 + T + b'\x03\x04ok' + T)
w('net_framing', 'too_short_and_split_terminator', hdr(16, 9) + b'\x05' + T + b'\x01\x02ab\r\r' + b'\n\n')

# agent_control: a net port's status reply as text
w('agent_control', 'status_with_nodes', 'rfsitl status node=2 agent=0 max_payload=2048 nodes=1-4,9,254')
w('agent_control', 'status_without_nodes', 'rfsitl status node=2 agent=1 max_payload=80')


# link_table: [which: even = /api/links document, odd = query][text]
w('link_table', 'document', b'\x00' + json.dumps({
    'nodes': 2, 'payload_bytes': 80, 'noise_db': -90.0, 'links_total': 2,
    'links': [{'tx': 1, 'rx': 2, 'distance_m': 50.0, 'gain_db': -74.4, 'snr_db': 15.6,
               'per': 0.0, 'received': 12, 'lost': 0},
              {'tx': 2, 'rx': 1, 'distance_m': None, 'gain_db': None, 'snr_db': None,
               'per': None, 'received': 0, 'lost': 3}]}).encode())
w('link_table', 'query', b'\x01payload=80&top=5&min_snr_db=-3.5')


# ethernet_frame: [self id][node-id bitmap, 32 bytes][MTU u16 be][frame]
def eth_hdr(self_id, ids, mtu):
    bitmap = bytearray(32)
    for i in ids:
        bitmap[i // 8] |= 1 << (i % 8)
    return bytes([self_id]) + bytes(bitmap) + struct.pack('>H', mtu)


def mac(i):
    return bytes([2, 0, 0, 0, 0, i])


ARP_REQUEST = (b'\xff' * 6 + mac(1) + b'\x08\x06' + bytes.fromhex('0001080006040001') + mac(1) +
               bytes([10, 77, 0, 1]) + bytes(6) + bytes([10, 77, 0, 2]))
w('ethernet_frame', 'arp_request', eth_hdr(1, [1, 2, 3], 2033) + ARP_REQUEST)
w('ethernet_frame', 'ipv4_unicast', eth_hdr(1, [1, 2], 2033) + mac(2) + mac(1) + b'\x08\x00' +
  bytes.fromhex('4500001c0000400040010000') + bytes([10, 77, 0, 1, 10, 77, 0, 2]) + bytes(8))
w('ethernet_frame', 'ipv6_multicast', eth_hdr(2, [1, 2], 1500) + b'\x33\x33\x00\x00\x00\x01' +
  mac(2) + b'\x86\xdd' + bytes(40))
w('ethernet_frame', 'unknown_mac', eth_hdr(1, [1, 2], 1500) + mac(9) + mac(1) + b'\x08\x00' +
  bytes(20))
w('ethernet_frame', 'not_ip', eth_hdr(1, [1, 2], 1500) + mac(2) + mac(1) + b'\x88\xb5' + bytes(46))

# location_parser: the forms of README.md "Location ports", and some rejects
w('location_parser', 'plain', '43.0008 -78.7890 25.0\n43.0008,-78.7890,25.0\n')
w('location_parser', 'json_geodetic', '{"lat": 43.0008, "lon": -78.7890, "alt": 25}\n')
w('location_parser', 'json_local', '{"x": 12.5, "y": -3.0, "z": 20}\n')
w('location_parser', 'nmea_gga', '$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n')
w('location_parser', 'rejects',
  '91 0 0\n{"lat":1}\n$GPGGA,123519,4807.038,N,01131.000,E,0,08,0.9,545.4,M,46.9,M,,*46\n   \n')


# wire_protocol: [mode][...] (see wire_protocol_fuzzer.cpp)
def header(t, flags=0, tick=0, time=0, count=0, extra=0, magic=0x58534652):
    return struct.pack('<IHHQQII', magic, t, flags, tick, time, count, extra)


hello_s = json.dumps({"node_id": 3, "role": "samples", "program": "gr"}).encode()
hello_t = json.dumps({"node_id": 7, "role": "transceiver", "program": "rfsitl node"}).encode()
w('wire_protocol', 'm0_tick', bytes([0]) + header(4, 0, 5, 1250, 2, 0) + struct.pack('<4f', 1, 0, 0, 1))
w('wire_protocol', 'm0_hello', bytes([0]) + header(1, extra=len(hello_s)) + hello_s)
w('wire_protocol', 'm1_hello_samples', bytes([1]) + hello_s)
w('wire_protocol', 'm1_hello_transceiver', bytes([1]) + hello_t)
w('wire_protocol', 'm1_hello_wrong_role', bytes([1]) + json.dumps({"node_id": 3, "role": "transceiver"}).encode())
w('wire_protocol', 'm2_hello_raw', bytes([2]) + header(1, extra=len(hello_t)) + hello_t)
phy = {"type": "gmsk", "rate_mbps": 6.0, "code": "", "modulation": "", "samples_per_chip": 2,
       "adaptive": False, "samples_per_symbol": 2, "filter_delay_symbols": 3, "bandwidth_time": 0.5,
       "max_payload_bytes": 2048, "tx_queue_frames": 64}
wel = json.dumps({"protocol": 1, "node_id": 5, "sample_rate_hz": 1e6, "tick_samples": 250,
                  "time_mode": "virtual", "phy": phy}).encode()
w('wire_protocol', 'm3_welcome', bytes([3, 0]) + wel)
w('wire_protocol', 'm3_reject', bytes([3, 2]) + b'node 5 is not an external node of this scenario')
w('wire_protocol', 'm4_welcome_raw', bytes([4]) + header(2, extra=len(wel)) + wel)
rec = struct.pack('<IBBBBffII', 42, 1, 2, 1, 1, -30.0, -25.0, 3, 2) + b'abc' + struct.pack('<4f', 1, 0, 0, 1)
w('wire_protocol', 'm5_rx_result', bytes([5, 1]) + rec + rec)
w('wire_protocol', 'm6_tx', bytes([6, 1]) + struct.pack('<8f', *([0.5] * 8)))
disc_req = json.dumps({"discovery": 1, "program": "soapy find"}).encode()
disc = json.dumps({"discovery": 1, "nodes": [
    {"node_id": 3, "label": "a node 3", "role": "samples", "sample_rate_hz": 1e6,
     "tick_samples": 250, "carrier_hz": 2.4e9, "time_mode": "realtime", "claimed": False}]}).encode()
w('wire_protocol', 'm7_discover', bytes([7, 0]) + disc_req)
w('wire_protocol', 'm7_discovery_answer', bytes([7, 1]) + disc)
w('wire_protocol', 'm2_discover_raw', bytes([2]) + header(9, extra=len(disc_req)) + disc_req)
hello_x = json.dumps({"node_id": 3, "role": "samples", "program": "soapy", "exclusive": True}).encode()
w('wire_protocol', 'm1_hello_exclusive', bytes([1]) + hello_x)
wel_s = json.dumps({"protocol": 1, "node_id": 5, "sample_rate_hz": 1e6, "tick_samples": 250,
                    "time_mode": "realtime", "tx_report": 1}).encode()
w('wire_protocol', 'm3_welcome_tx_report', bytes([3, 0]) + wel_s)
report = struct.pack('<IIQ', 1, 0, 7)
w('wire_protocol', 'm8_tx_report', bytes([8, 2]) + struct.pack('<4f', 0.5, 0, 0, 0.5) + report)
w('wire_protocol', 'm8_tx_no_report', bytes([8, 1]) + struct.pack('<2f', 0.5, 0))
w('wire_protocol', 'm8_tx_short_report', bytes([8, 0]) + report[:9])

# dashboard_http: requests as a browser, curl or a script sends them
w('dashboard_http', 'get_index', 'GET / HTTP/1.1\r\nHost: 127.0.0.1:15700\r\n\r\n')
w('dashboard_http', 'get_api_pipelined',
  'GET /api/stats HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\nGET /api/snapshot?x=1 HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n'
  'GET /metrics HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n')
body = '{"x": 12.5, "y": -3.0, "z": 20}'
w('dashboard_http', 'post_local',
  'POST /api/nodes/2/position HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n'
  'Content-Length: %d\r\n\r\n%s' % (len(body), body))
body = '{"lat": 43.0008, "lon": -78.789}'
w('dashboard_http', 'post_geodetic_same_origin',
  'POST /api/nodes/9/position HTTP/1.1\r\nHost: 127.0.0.1:15700\r\nOrigin: http://127.0.0.1:15700\r\n'
  'Content-Length: %d\r\n\r\n%s' % (len(body), body))
w('dashboard_http', 'post_cross_origin',
  'POST /api/nodes/1/position HTTP/1.1\r\nHost: localhost\r\nOrigin: http://evil\r\nContent-Length: 2\r\n\r\n{}')
w('dashboard_http', 'ws_upgrade',
  'GET /ws HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n'
  'Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n')
w('dashboard_http', 'post_chunked',
  'POST /api/nodes/3/position HTTP/1.1\r\nHost: 127.0.0.1\r\nTransfer-Encoding: chunked\r\n\r\n'
  '7\r\n{"x":1,\r\n10\r\n"y":2,"z":3}    \r\n0\r\n\r\n')

# dashboard_ws: viewer messages, one per line (docs/dashboard.md)
w('dashboard_ws', 'watch', '{"type":"watch","node":2}\n{"type":"watch","node":null}')
w('dashboard_ws', 'move', '{"type":"move","node":3,"x":1,"y":2,"z":3}\n'
  '{"type":"move","node":1,"lat":43.0008,"lon":-78.789,"alt":10}')
w('dashboard_ws', 'rejects', '{"type":"watch"}\n[1]\n{"type":"jump","node":1}\n{"type":"move","node":9,"x":"a"}')

# scenario: the shipped scenario files
repo = os.path.dirname(HERE)
for name in sorted(os.listdir(os.path.join(repo, 'scenarios'))):
    if name.endswith('.yaml'):
        os.makedirs(os.path.join(HERE, 'corpus', 'scenario'), exist_ok=True)
        shutil.copyfile(os.path.join(repo, 'scenarios', name), os.path.join(HERE, 'corpus', 'scenario', name))
# ... and a few as JSON documents (the Python module's dicts: scenario_from_json)
import yaml  # noqa: E402
for name in ('six_uav_batch.yaml', 'wifi_multipath.yaml'):
    with open(os.path.join(repo, 'scenarios', name)) as f:
        w('scenario', name.replace('.yaml', '.json'), json.dumps(yaml.safe_load(f)))

# campaign: first byte even: a campaign file (the shipped examples and one of
# every form); odd: a results table.
for name in sorted(os.listdir(os.path.join(repo, 'examples', 'campaigns'))):
    if name.endswith('.yaml'):
        with open(os.path.join(repo, 'examples', 'campaigns', name), 'rb') as f:
            w('campaign', name, b'\x00' + f.read())
w('campaign', 'zip_and_list', b'\x00scenario: s.yaml\nsettings: {time.duration_s: 1}\n'
  b'parameters:\n  a: [1, 2]\nzip:\n  - {b: [x, y], c: [3, 4]}\nseeds: [5, 9]\ntimeout_s: 10\n')
w('campaign', 'table', b'\x01a,b,seed,scenario_hash,status,error,delivery_ratio,delivered\n'
  b'1,x,5,0123456789abcdef,ok,,0.5,3\n"2,3",y,9,0123456789abcdef,failed,"exit code 2: ""x""",,\n')

# scenario: channel plans and nodes on their own frequencies (hand-made: no
# shipped scenario uses them yet), and the mistakes the reader must name.
SPECTRUM_HEAD = ('time: {mode: virtual, duration_s: 0.1, sample_rate_hz: 20e6}\n'
                 'phy: {type: ofdm}\nradio: {carrier_hz: 2.437e9}\n'
                 'spectrum:\n  plans:\n'
                 '    wifi24: {first_hz: 2.412e9, spacing_hz: 5e6, channels: 13, bandwidth_hz: 20e6}\n'
                 '    ism915: {first_hz: 902.2e6, spacing_hz: 400e3, channels: 64, bandwidth_hz: 200e3}\n')
w('scenario', 'spectrum_plans.yaml', SPECTRUM_HEAD +
  'nodes:\n  - {id: 1, channel: wifi24/1, position: {x: 0, y: 0, z: 10}}\n'
  '  - {id: 2, channel: wifi24/11, duplex: half, position: {x: 5, y: 0, z: 10}}\n'
  '  - {id: 3, tx_hz: 1.7325e9, rx_hz: 2.1325e9, bandwidth_hz: 1.4e6, duplex: full}\n'
  '  - {id: 4, channel: ism915/64}\n')
w('scenario', 'spectrum_mistakes.yaml', SPECTRUM_HEAD +
  'nodes:\n  - {id: 1, channel: wifi24/14}\n  - {id: 2, channel: nope/1}\n'
  '  - {id: 3, channel: wifi24/1, tx_hz: 2.4e9}\n  - {id: 4, bandwidth_hz: 40e6}\n')


# vehicle_link: [settings][chunks of [len][dt tenths][bytes]] (vehicle_link_fuzzer.cpp),
# frames from the spec-written test vehicle.
def vehicle_seeds():
    import sys
    sys.path.insert(0, os.path.join(HERE, '..', 'tests', 'integration'))
    import mavlink_vehicle as mv
    hb = {'type': 2, 'autopilot': 3, 'base_mode': 1, 'custom_mode': 0, 'system_status': 4,
          'mavlink_version': 3}

    def pos(lat, lon, alt):
        return {'time_boot_ms': 1000, 'lat': lat, 'lon': lon, 'alt': alt, 'relative_alt': 0,
                'vx': 100, 'vy': -50, 'vz': 0, 'hdg': 9000}
    att = {'time_boot_ms': 1000, 'roll': 0.1, 'pitch': -0.1, 'yaw': 1.0, 'rollspeed': 0.0,
           'pitchspeed': 0.0, 'yawspeed': 0.0}
    ack = {'command': 511, 'result': 3, 'target_system': 1, 'target_component': 191}

    def chunks(frames, dt=3):
        return b''.join(bytes([len(f), dt]) + f for f in frames)
    for version in (1, 2):
        frames = [mv.encode(mv.HEARTBEAT, hb, 0, 1, 1, version),
                  mv.encode(mv.GLOBAL_POSITION_INT, pos(0, 0, 0), 1, 1, 1, version),
                  mv.encode(mv.GLOBAL_POSITION_INT, pos(430008000, -787890000, 250000), 2, 1, 1,
                            version),
                  mv.encode(mv.ATTITUDE, att, 3, 1, 1, version),
                  mv.encode(77, ack, 4, 1, 1, version),
                  mv.encode(mv.GLOBAL_POSITION_INT, pos(950000000, 10, 0), 5, 9, 1, version)]
        w('vehicle_link', f'vehicle_v{version}', bytes([0x30]) + chunks(frames))
    w('vehicle_link', 'configured_sysid_signed',
      bytes([0x13]) + chunks([mv.encode(mv.GLOBAL_POSITION_INT, pos(1, 1, 1), 0, 0x13, 1, 2,
                                        signed=True)], dt=40))


vehicle_seeds()
