"""A minimal stand-in for the rfsitl emulator's external-node socket.

It speaks the "samples" role of the wire protocol
(include/rfsitl/external/client/wire_protocol.hpp) in plain Python, so tests and
flowgraph authors can drive emulator_source / emulator_sink tick by tick
without the emulator. It is a protocol double, not a channel model: the
caller decides what each node receives.

    with FakeEmulator("/tmp/x.sock", tick_samples=250) as emu:
        node = emu.accept(timeout=10)         # handshake with one node
        tx = node.tick(rx)                    # kTick with rx, returns the kTx samples
"""

import json
import os
import select
import socket
import struct
import time

import numpy as np

MAGIC = 0x58534652  # "RFSX" in little-endian memory
HELLO, WELCOME, REJECT, TICK, TX = 1, 2, 3, 4, 5

# MsgHeader: magic u32, type u16, flags u16, tick u64, time u64, count u32,
# extra_bytes u32; host byte order, no padding (32 bytes).
HEADER = struct.Struct("=IHHQQII")
assert HEADER.size == 32

MAX_MESSAGE_BYTES = 200 * 1024


class ProtocolError(Exception):
    """The peer sent something the protocol does not allow."""


def pack(msg_type, tick=0, time_=0, samples=None, extra=b"", flags=0):
    """One protocol message as bytes."""
    data = b"" if samples is None else np.asarray(samples, dtype=np.complex64).tobytes()
    count = len(data) // 8
    return HEADER.pack(MAGIC, msg_type, flags, tick, time_, count, len(extra)) + data + extra


def unpack(data):
    """(type, flags, tick, time, samples complex64, extra bytes) of one message."""
    if len(data) < HEADER.size:
        raise ProtocolError(f"message of {len(data)} bytes is shorter than the header")
    magic, msg_type, flags, tick, time_, count, extra_bytes = HEADER.unpack_from(data)
    if magic != MAGIC:
        raise ProtocolError(f"bad magic {magic:#x}")
    if HEADER.size + 8 * count + extra_bytes != len(data):
        raise ProtocolError("sizes in the header do not add up")
    samples = np.frombuffer(data, dtype=np.complex64, count=count, offset=HEADER.size)
    extra = data[HEADER.size + 8 * count:]
    return msg_type, flags, tick, time_, samples, extra


def _recv(sock, timeout):
    ready, _, _ = select.select([sock], [], [], timeout)
    if not ready:
        raise TimeoutError("no message within %.3f s" % timeout)
    data = sock.recv(MAX_MESSAGE_BYTES)
    if not data:
        raise ConnectionError("peer closed the connection")
    return unpack(data)


class Peer:
    """One joined node. tick() is one lock-step round trip."""

    def __init__(self, sock, node_id, hello, emulator, start_tick):
        self.sock = sock
        self.node_id = node_id
        self.hello = hello
        self.emulator = emulator
        self.next_tick = start_tick

    def send_tick(self, rx=None, index=None):
        """Sends kTick `index` (default: the next one) carrying `rx`."""
        if index is not None:
            self.next_tick = index
        k = self.next_tick
        self.next_tick += 1
        self.sock.send(pack(TICK, tick=k, time_=k * self.emulator.tick_samples, samples=rx))
        return k

    def recv_tx(self, tick, timeout=None):
        """Waits for the kTx answering `tick`; returns its samples (complex64)."""
        timeout = self.emulator.tx_timeout_s if timeout is None else timeout
        msg_type, _, k, _, samples, _ = _recv(self.sock, timeout)
        if msg_type != TX:
            raise ProtocolError(f"expected tx, got message type {msg_type}")
        if k != tick:
            raise ProtocolError(f"tx for tick {k}, expected {tick}")
        if len(samples) > self.emulator.tick_samples:
            raise ProtocolError(f"tx of {len(samples)} samples exceeds the tick")
        return samples.copy()

    def tick(self, rx=None, index=None, timeout=None):
        """kTick with `rx` (None: no samples), then its kTx; returns the tx samples."""
        k = self.send_tick(rx, index)
        return self.recv_tx(k, timeout)

    def close(self):
        self.sock.close()


class FakeEmulator:
    """Listens on `path` (SOCK_SEQPACKET) like the emulator's external socket."""

    def __init__(self, path, sample_rate_hz=1e6, tick_samples=250, time_mode="virtual",
                 tx_timeout_s=1.0):
        self.path = path
        self.sample_rate_hz = sample_rate_hz
        self.tick_samples = tick_samples
        self.time_mode = time_mode
        self.tx_timeout_s = tx_timeout_s
        if os.path.exists(path):
            os.unlink(path)
        self.listener = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        self.listener.bind(path)
        self.listener.listen(8)

    def accept(self, timeout=10.0, start_tick=0, reject=None):
        """Accepts one node and answers its hello. With `reject` (a reason
        string) the node is refused with kReject instead and None returned."""
        ready, _, _ = select.select([self.listener], [], [], timeout)
        if not ready:
            raise TimeoutError("no node connected within %.1f s" % timeout)
        sock, _ = self.listener.accept()
        msg_type, _, _, _, _, extra = _recv(sock, 5.0)
        if msg_type != HELLO:
            sock.close()
            raise ProtocolError(f"expected hello, got message type {msg_type}")
        hello = json.loads(extra.decode())
        if reject is not None:
            sock.send(pack(REJECT, extra=reject.encode()))
            sock.close()
            return None
        welcome = {
            "protocol": 1,
            "node_id": hello["node_id"],
            "sample_rate_hz": self.sample_rate_hz,
            "tick_samples": self.tick_samples,
            "time_mode": self.time_mode,
        }
        sock.send(pack(WELCOME, extra=json.dumps(welcome).encode()))
        return Peer(sock, hello["node_id"], hello, self, start_tick)

    def close(self):
        """Stops listening and removes the socket file: the emulator is gone."""
        self.listener.close()
        if os.path.exists(self.path):
            os.unlink(self.path)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def wait_until(predicate, timeout, interval=0.01):
    """Polls `predicate` until it is true or `timeout` seconds pass; returns its last value."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value or time.monotonic() >= deadline:
            return value
        time.sleep(interval)
