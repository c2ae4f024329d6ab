"""A minimal WebSocket client (RFC 6455) for the dashboard's /ws: masked text
frames out, unmasked frames in. Standard library only; shared by the
integration tests and the dashboard benchmarks."""

import base64
import json
import os
import socket
import struct


class WsClient:
    def __init__(self, host, port, target="/ws", timeout=10.0, rcvbuf=None):
        """Connects and upgrades; raises AssertionError when the server refuses
        (status_line says how) or closes during the upgrade. `rcvbuf`: a small
        kernel receive buffer, so that the server's queue holds what is unread."""
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        if rcvbuf is not None:
            self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
        self.sock.settimeout(timeout)
        self.sock.connect((host, port))
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET {target} HTTP/1.1\r\nHost: {host}:{port}\r\n"
                           "Upgrade: websocket\r\nConnection: Upgrade\r\n"
                           f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n")
                          .encode())
        head = b""
        while b"\r\n\r\n" not in head:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise AssertionError("the dashboard closed the WebSocket upgrade: " + repr(head))
            head += chunk
        head, self._buf = head.split(b"\r\n\r\n", 1)
        self.status_line = head.split(b"\r\n")[0].decode(errors="replace")
        if " 101 " not in self.status_line:
            raise AssertionError("WebSocket upgrade refused: " + head.decode(errors="replace"))

    def _take(self, n):
        while len(self._buf) < n:
            chunk = self.sock.recv(max(65536, n - len(self._buf)))
            if not chunk:
                raise ConnectionError("the dashboard closed the WebSocket")
            self._buf += chunk
        out, self._buf = self._buf[:n], self._buf[n:]
        return out

    def read_frame(self):
        """The next frame: (opcode, fin, payload)."""
        b0, b1 = self._take(2)
        n = b1 & 0x7F
        if n == 126:
            n = struct.unpack(">H", self._take(2))[0]
        elif n == 127:
            n = struct.unpack(">Q", self._take(8))[0]
        return b0 & 0x0F, bool(b0 & 0x80), self._take(n)

    def read(self):
        """The next text message, parsed (the server sends each in one frame)."""
        while True:
            opcode, _, payload = self.read_frame()
            if opcode == 8:
                raise ConnectionError("the dashboard closed the WebSocket")
            if opcode == 1:
                return json.loads(payload)

    def send(self, message):
        """Sends `message` as JSON text in one masked frame."""
        data = json.dumps(message).encode()
        mask = os.urandom(4)
        if len(data) < 126:
            header = bytes([0x81, 0x80 | len(data)])
        else:
            header = bytes([0x81, 0xFE]) + struct.pack(">H", len(data))
        self.sock.sendall(header + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))

    def close(self):
        self.sock.close()
