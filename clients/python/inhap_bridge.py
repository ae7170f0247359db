"""inhap device bridge client, Python 3 standard library only (docs/bridge.md).

Units: mm, N, s. One exchange per servo tick: send the probe state, receive the force.

    from inhap_bridge import BridgeClient
    with BridgeClient("127.0.0.1", 47110) as c:          # key="..." for a LAN
        force, status = c.exchange(t, (x, y, z), sensor_force=None, timeout=0.002)

Run as a script it is a small scripted device: it moves a probe along a line for a while and
prints the forces inhap answered (a smoke test of a running `inhap serve --device udp`).
"""

import argparse
import hashlib
import hmac
import math
import os
import socket
import struct
import sys
import time

MAGIC = 0x42504849
VERSION = 1
DEFAULT_PORT = 47110
FLAG_SENSOR = 1
FLAG_SIGNED = 2
STATUS_CONTACT = 1
STATUS_ZEROED = 2
STATUS_STOPPING = 4

_STATE = struct.Struct("<IHBBIId3d3dI")  # 76 bytes
_FORCE = struct.Struct("<IHBBII3dI")  # 44 bytes
_HEADER = struct.Struct("<IHBBII")  # 16 bytes
_TAG = 32
_NONCE = 32
_LABEL = b"inhap bridge session key v1"
REHANDSHAKE_AFTER = 100  # time-outs in a row (with a key): the session key is stale


def _key_block(key):
    if not key:
        return None
    k = key.encode() if isinstance(key, str) else bytes(key)
    if len(k) > 64:
        k = hashlib.sha256(k).digest()
    return k.ljust(64, b"\0")


class BridgeClient:
    """The device side of the bridge."""

    def __init__(self, host="127.0.0.1", port=DEFAULT_PORT, key=None):
        self.addr = (host, port)
        self.key = _key_block(key)  # the shared secret's HMAC key block
        self.session_key = None  # with a key: this session's, from the handshake
        self.nonce = None
        self.misses = 0
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.session = struct.unpack("<I", os.urandom(4))[0] or 1
        self.sequence = 0
        self.stats = {"sent": 0, "answered": 0, "timeouts": 0, "stale": 0, "malformed": 0,
                      "bad_auth": 0}

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        self.sock.close()

    def _sign(self, body, key=None):
        return hmac.new(key or self.session_key, body, hashlib.sha256).digest()

    def handshake(self, timeout=0.5):
        """With a key: hello with a fresh nonce, inhap's welcome with its own; the session key is
        HMAC(shared, label | session | both nonces). True when done within timeout s."""
        self.nonce = os.urandom(_NONCE)
        body = _HEADER.pack(MAGIC, VERSION, 3, FLAG_SIGNED, self.session, 0) + self.nonce
        self.sock.sendto(body + self._sign(body, self.key), self.addr)
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return False
            self.sock.settimeout(left)
            try:
                data = self.sock.recv(256)
            except socket.timeout:
                return False
            body, tag = data[:-_TAG], data[-_TAG:]
            if len(data) != _HEADER.size + 2 * _NONCE + _TAG:
                self.stats["malformed"] += 1
                continue
            magic, ver, kind, _, session, _ = _HEADER.unpack(body[:_HEADER.size])
            if magic != MAGIC or ver != VERSION or kind != 4:
                self.stats["malformed"] += 1
                continue
            if not hmac.compare_digest(self._sign(body, self.key), tag):
                self.stats["bad_auth"] += 1
                continue
            nonces = body[_HEADER.size:]
            if session != self.session or nonces[:_NONCE] != self.nonce:
                self.stats["stale"] += 1
                continue
            k = self._sign(_LABEL + struct.pack("<I", self.session) + nonces, self.key)
            self.session_key = k.ljust(64, b"\0")
            self.misses = 0
            return True

    def state_packet(self, t, position, sensor_force=None, buttons=0):
        """The bytes of the next state packet (advances the sequence)."""
        self.sequence = (self.sequence + 1) & 0xFFFFFFFF
        flags = (FLAG_SENSOR if sensor_force is not None else 0) | (FLAG_SIGNED if self.key else 0)
        f = sensor_force if sensor_force is not None else (0.0, 0.0, 0.0)
        body = _STATE.pack(MAGIC, VERSION, 1, flags, self.session, self.sequence, float(t),
                           *map(float, position), *map(float, f), buttons)
        return body + self._sign(body) if self.key else body

    def _parse(self, data):
        if len(data) < 8:
            self.stats["malformed"] += 1
            return None
        signed = data[7] & FLAG_SIGNED
        if len(data) != _FORCE.size + (_TAG if signed else 0):
            self.stats["malformed"] += 1
            return None
        magic, ver, kind, _, session, seq, fx, fy, fz, status = _FORCE.unpack(data[:_FORCE.size])
        if magic != MAGIC or ver != VERSION or kind != 2:
            self.stats["malformed"] += 1
            return None
        if self.key:
            if not signed or not hmac.compare_digest(self._sign(data[:_FORCE.size]),
                                                     data[_FORCE.size:]):
                self.stats["bad_auth"] += 1
                return None
        if session != self.session or seq != self.sequence:
            self.stats["stale"] += 1
            return None
        if not all(math.isfinite(v) for v in (fx, fy, fz)):
            self.stats["malformed"] += 1
            return None
        return (fx, fy, fz), status

    def exchange(self, t, position, sensor_force=None, buttons=0, timeout=0.002):
        """Sends one state and waits up to timeout s for its force; (force N, status) or
        ((0, 0, 0), None) on time-out. With a key, the first exchange (and one after
        REHANDSHAKE_AFTER time-outs in a row) first makes the handshake (up to timeout s)."""
        if self.key and self.misses >= REHANDSHAKE_AFTER:
            self.session_key = None
        if self.key and self.session_key is None and not self.handshake(timeout):
            self.stats["timeouts"] += 1
            return (0.0, 0.0, 0.0), None
        self.sock.sendto(self.state_packet(t, position, sensor_force, buttons), self.addr)
        self.stats["sent"] += 1
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                self.stats["timeouts"] += 1
                self.misses += 1
                return (0.0, 0.0, 0.0), None
            self.sock.settimeout(left)
            try:
                data = self.sock.recv(256)
            except socket.timeout:
                self.stats["timeouts"] += 1
                self.misses += 1
                return (0.0, 0.0, 0.0), None
            got = self._parse(data)
            if got is not None:
                self.stats["answered"] += 1
                self.misses = 0
                return got


def main(argv=None):
    ap = argparse.ArgumentParser(description="scripted bridge device: a probe moving down "
                                 "along z (mm) at 1 kHz, printing inhap's forces (N)")
    ap.add_argument("--host", default="127.0.0.1")
    ap.add_argument("--port", type=int, default=DEFAULT_PORT)
    ap.add_argument("--key", default=os.environ.get("INHAP_BRIDGE_KEY"))
    ap.add_argument("--seconds", type=float, default=2.0)
    ap.add_argument("--from-z", type=float, default=5.0, help="start height, mm")
    ap.add_argument("--to-z", type=float, default=-3.0, help="end height, mm")
    a = ap.parse_args(argv)
    n = int(a.seconds * 1000)
    with BridgeClient(a.host, a.port, a.key) as c:
        for i in range(n):
            z = a.from_z + (a.to_z - a.from_z) * i / max(n - 1, 1)
            f, status = c.exchange(i * 1e-3, (0.0, 0.0, z), timeout=0.01)
            if i % 100 == 0:
                print(f"t={i * 1e-3:.3f} z={z:.3f} f=({f[0]:.3f},{f[1]:.3f},{f[2]:.3f}) "
                      f"status={status}")
            time.sleep(0.001)
        print(c.stats, file=sys.stderr)


if __name__ == "__main__":
    main()
