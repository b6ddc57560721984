"""A small Python client for polycut-server (docs/protocol.md), on pyzmq and numpy.

    from polycut_client import Client
    with Client("tcp://127.0.0.1:5555") as c:
        print(c.call("hello", client="me"))
        c.call("load_scene", name="default")
        c.cut(np.array([[[x, y, z], ...]]))          # float32 binary frame
        mirror = c.surface_mirror()                   # late-joiner-safe surface copy
        mirror.update(timeout_ms=100)

Errors come back as RpcError exceptions carrying the JSON-RPC code, the JSON pointer of the bad
field and the reason. Run with /usr/bin/python3 (Debian's python3-zmq and python3-numpy).
"""

import itertools
import json

import numpy as np
import zmq

__all__ = ["Client", "RpcError", "SurfaceMirror"]


class RpcError(Exception):
    """A JSON-RPC error answered by the server."""

    def __init__(self, error):
        data = error.get("data") or {}
        self.code = error.get("code")
        self.message = error.get("message", "")
        self.pointer = data.get("pointer", "")
        self.reason = data.get("reason", "")
        super().__init__(f"{self.code} {self.message} at '{self.pointer}': {self.reason}")


def _decode_array(ref, frames):
    """A frame reference {"$frame", "dtype", "shape"} -> numpy array (little-endian)."""
    dtype = {"float32": "<f4", "uint32": "<u4", "uint8": "u1"}[ref["dtype"]]
    return np.frombuffer(frames[ref["$frame"] - 1], dtype=dtype).reshape(ref["shape"])


class Client:
    """A DEALER connection to the control socket; one request at a time (call) or
    fire-and-forget notifications (notify)."""

    def __init__(self, endpoint="tcp://127.0.0.1:5555", identity=None, timeout_ms=10000,
                 context=None):
        self.context = context or zmq.Context.instance()
        self.socket = self.context.socket(zmq.DEALER)
        self.socket.setsockopt(zmq.LINGER, 0)
        if identity:
            # A stable identity lets retries after a reconnect hit the server's reply cache.
            self.socket.setsockopt(zmq.ROUTING_ID, identity.encode())
        self.socket.connect(endpoint)
        self.timeout_ms = timeout_ms
        self._ids = itertools.count(1)
        self._hello = None

    def close(self):
        self.socket.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def request(self, method, params=None, frames=(), id=None):
        """Sends a request and returns (result, binary frames); raises RpcError."""
        rid = next(self._ids) if id is None else id
        message = {"jsonrpc": "2.0", "id": rid, "method": method, "params": params or {}}
        self.socket.send_multipart([json.dumps(message).encode(), *frames])
        while True:
            if not self.socket.poll(self.timeout_ms):
                raise TimeoutError(f"no reply to {method} within {self.timeout_ms} ms")
            reply, *arrays = self.socket.recv_multipart()
            answer = json.loads(reply)
            if answer.get("id") == rid or answer.get("id") is None:
                break  # (a reply to an earlier, timed-out request is skipped)
        if "error" in answer:
            raise RpcError(answer["error"])
        return answer["result"], arrays

    def call(self, method, **params):
        """Calls a method with keyword params; returns the result object."""
        return self.request(method, params)[0]

    def notify(self, method, **params):
        """Sends a notification (no reply, e.g. high-rate scalpel samples)."""
        message = {"jsonrpc": "2.0", "method": method, "params": params}
        self.socket.send(json.dumps(message).encode())

    def hello(self):
        self._hello = self.call("hello", client="polycut_client.py", protocol="polycut/1")
        return self._hello

    def cut(self, triangles, id=None):
        """Cuts along sweep triangles (T x 3 x 3 world coordinates [m]), sent as a float32
        frame."""
        tris = np.ascontiguousarray(triangles, dtype="<f4").reshape(-1, 3, 3)
        ref = {"$frame": 1, "dtype": "float32", "shape": list(tris.shape)}
        return self.request("cut", {"triangles": ref}, [tris.tobytes()], id=id)[0]

    def get_surface(self):
        """The snapshot: (header dict, positions V x 3, triangles T x 3, tags T)."""
        result, frames = self.request("get_surface")
        return (result, _decode_array(result["positions"], frames),
                _decode_array(result["triangles"], frames), _decode_array(result["tags"], frames))

    def subscribe(self, topics=(b"surface",)):
        """A SUB socket on the server's stream endpoint (from hello)."""
        hello = self._hello or self.hello()
        sub = self.context.socket(zmq.SUB)
        sub.setsockopt(zmq.LINGER, 0)
        sub.connect(hello["stream"])
        for topic in topics:
            sub.setsockopt(zmq.SUBSCRIBE, topic)
        return sub

    def surface_mirror(self):
        """A SurfaceMirror subscribed and synchronized (zguide Clone pattern)."""
        return SurfaceMirror(self)


class SurfaceMirror:
    """A client-side copy of the published surface that survives late joining and lost frames:
    subscribe first, take a get_surface snapshot (seq S), apply frames with seq > S in order,
    and take a new snapshot on a gap (docs/protocol.md "Late joiners and gaps")."""

    def __init__(self, client):
        self.client = client
        self.sub = client.subscribe((b"surface",))
        self.snapshots = 0
        self._snapshot()

    def _snapshot(self):
        self.header, self.positions, self.triangles, self.tags = self.client.get_surface()
        self.snapshots += 1

    def apply(self, frames):
        """Applies one stream message ([topic, header, positions, (triangles, tags)])."""
        header = json.loads(frames[1])
        seq = header["seq"]
        if seq <= self.header["seq"]:
            return
        if seq != self.header["seq"] + 1 or (
                header["topology_version"] != self.header["topology_version"]
                and not header["has_topology"]):
            self._snapshot()  # frames were lost: start over from a snapshot
            return
        arrays = frames[2:]
        self.positions = _decode_array(header["positions"], arrays)
        if header["has_topology"]:
            self.triangles = _decode_array(header["triangles"], arrays)
            self.tags = _decode_array(header["tags"], arrays)
        self.header = header

    def update(self, timeout_ms=0):
        """Applies every frame that arrives within timeout_ms; returns how many."""
        n = 0
        while self.sub.poll(timeout_ms):
            self.apply(self.sub.recv_multipart())
            n += 1
            timeout_ms = 0
        return n
