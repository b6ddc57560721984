"""The control channel: JSON-RPC 2.0 requests over a ZeroMQ DEALER (docs/protocol.md).

    with polycut.Client("tcp://127.0.0.1:5555") as c:
        c.load_scene(name="default")
        c.cut(np.array([[[x, y, z], ...]]))          # float32 binary frame
        mirror = c.surface_mirror()                   # late-joiner-safe surface copy

Errors come back as :class:`RpcError` carrying the JSON-RPC code, the JSON pointer of the bad
field and the reason. Units are SI (m, N, s, N/m).
"""
import itertools
import json

import numpy as np
import zmq

from .results import CutResult, Hello, RunState, SceneInfo, Stats, Surface

_DTYPES = {"float32": "<f4", "uint32": "<u4", "uint8": "u1"}


class RpcError(Exception):
    """A JSON-RPC error answered by the server: ``code``, ``message``, ``pointer`` (RFC 6901,
    the bad field of the request) and ``reason``."""

    def __init__(self, error):
        data = error.get("data") or {}
        self.code = error.get("code")
        self.message = error.get("message", "")
        self.pointer = data.get("pointer", "")
        self.reason = data.get("reason", "")
        super().__init__(f"{self.code} {self.message} at '{self.pointer}': {self.reason}")


def decode_array(ref, frames):
    """A frame reference {"$frame", "dtype", "shape"} -> numpy array (little-endian); `frames`
    are the binary frames after the JSON frame (so "$frame": 1 is frames[0])."""
    return np.frombuffer(frames[ref["$frame"] - 1], dtype=_DTYPES[ref["dtype"]]).reshape(ref["shape"])


def _vec(v):
    return [float(x) for x in v]


class Client:
    """A DEALER connection to polycut-server's control socket.

    Requests are answered one at a time (:meth:`request` waits for its reply); notifications
    (:meth:`notify`, e.g. scalpel samples at a device's rate) get none. Every protocol method has
    a typed method; :meth:`call` reaches any method by name.

    :param endpoint: the control endpoint, e.g. ``"tcp://127.0.0.1:5555"``
    :param identity: a stable ZeroMQ routing id, so a retried request after a reconnect is
        answered from the server's reply cache (docs/protocol.md "Retries")
    :param timeout_ms: how long a request waits for its reply [ms]
    """

    def __init__(self, endpoint="tcp://127.0.0.1:5555", identity=None, timeout_ms=10000,
                 context=None):
        self.context = context or zmq.Context.instance()
        self.socket = self.context.socket(zmq.DEALER)
        self.socket.setsockopt(zmq.LINGER, 0)
        if identity:
            self.socket.setsockopt(zmq.ROUTING_ID, identity.encode())
        self.socket.connect(endpoint)
        self.endpoint = endpoint
        self.timeout_ms = timeout_ms
        self._ids = itertools.count(1)
        self._hello = None

    def close(self):
        """Closes the socket (subscriptions made by :meth:`subscribe` are the caller's)."""
        self.socket.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # -- generic -------------------------------------------------------------------------
    def request(self, method, params=None, frames=(), id=None):
        """Sends a request and returns ``(result, binary frames)``; raises :class:`RpcError`,
        or ``TimeoutError`` after ``timeout_ms``."""
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
        """Calls any method with keyword params; returns the result as a dict."""
        return self.request(method, params)[0]

    def notify(self, method, **params):
        """Sends a notification: executed, never answered (errors become `rejected` events)."""
        message = {"jsonrpc": "2.0", "method": method, "params": params}
        self.socket.send(json.dumps(message).encode())

    # -- session -------------------------------------------------------------------------
    def hello(self, client="polycut-python"):
        """Handshake: protocol, limits, capabilities and the stream endpoint."""
        self._hello = Hello.from_json(self.call("hello", client=client, protocol="polycut/1"))
        return self._hello

    def load_scene(self, name=None, scene=None):
        """Loads a scene of the server's scene directory by `name`, or an inline `scene` dict
        (the scene file format, docs/scenes.md)."""
        params = {"name": name} if scene is None else {"scene": scene}
        return SceneInfo.from_json(self.request("load_scene", params)[0])

    def reset(self):
        """Back to the scene's initial state (uncut, at rest, tick 0)."""
        return RunState.from_json(self.call("reset"))

    def pause(self):
        return RunState.from_json(self.call("pause"))

    def resume(self):
        return RunState.from_json(self.call("resume"))

    def step(self, ticks=1):
        """Runs `ticks` ticks while paused; returns after the last one."""
        return RunState.from_json(self.call("step", ticks=int(ticks)))

    def set_rate(self, hz):
        """Sets the tick rate [Hz]."""
        return RunState.from_json(self.call("set_rate", hz=float(hz)))

    def shutdown(self):
        """Stops the server after the reply; returns the last tick."""
        return self.call("shutdown")["tick"]

    # -- loads and tools -----------------------------------------------------------------
    def apply_force(self, point, force, radius, duration=None):
        """A force [N] spread over the material within `radius` [m] of `point` [m], for
        `duration` [s] or until :meth:`remove_force`; returns its id."""
        params = {"point": _vec(point), "force": _vec(force), "radius": float(radius)}
        if duration is not None:
            params["duration"] = float(duration)
        return self.request("apply_force", params)[0]["id"]

    def remove_force(self, force_id):
        self.call("remove_force", id=int(force_id))

    def grab(self, point, stiffness=None, radius=None):
        """Grabs the material at `point` [m] with a spring of `stiffness` [N/m]; returns its id."""
        params = {"point": _vec(point)}
        if stiffness is not None:
            params["stiffness"] = float(stiffness)
        if radius is not None:
            params["radius"] = float(radius)
        return self.request("grab", params)[0]["id"]

    def move_grab(self, grab_id, target):
        """Moves a grab's anchor to `target` [m]."""
        self.call("move_grab", id=int(grab_id), target=_vec(target))

    def release(self, grab_id):
        self.call("release", id=int(grab_id))

    # -- cutting -------------------------------------------------------------------------
    def cut(self, triangles, id=None):
        """Cuts along sweep triangles (T x 3 x 3 world coordinates [m]), sent as a float32
        binary frame."""
        tris = np.ascontiguousarray(triangles, dtype="<f4").reshape(-1, 3, 3)
        ref = {"$frame": 1, "dtype": "float32", "shape": list(tris.shape)}
        return CutResult.from_json(self.request("cut", {"triangles": ref}, [tris.tobytes()], id=id)[0])

    def scalpel(self, stroke, a, b, wait=False):
        """One blade sample of stroke `stroke` (blade endpoints `a`, `b` [m]). Sent as a
        notification (cut at the next tick); with ``wait=True`` as a request, cut at once and
        answered with the sweep triangles it added."""
        params = {"stroke": int(stroke), "a": _vec(a), "b": _vec(b)}
        if wait:
            return self.request("scalpel", params)[0]["triangles"]
        self.notify("scalpel", **params)
        return None

    def end_stroke(self, stroke):
        """Closes a stroke; its pending sweep is applied."""
        return CutResult.from_json(self.call("end_stroke", stroke=int(stroke)))

    # -- state ---------------------------------------------------------------------------
    def get_surface(self):
        """The current surface (a :class:`Surface`; unpacks as header, positions, triangles,
        tags)."""
        result, frames = self.request("get_surface")
        return Surface(result, decode_array(result["positions"], frames),
                       decode_array(result["triangles"], frames), decode_array(result["tags"], frames))

    def get_stats(self):
        return Stats.from_json(self.call("get_stats"))

    # -- the stream ----------------------------------------------------------------------
    def subscribe(self, topics=(b"surface",)):
        """A SUB socket on the server's stream endpoint (from hello)."""
        hello = self._hello or self.hello()
        sub = self.context.socket(zmq.SUB)
        sub.setsockopt(zmq.LINGER, 0)
        sub.connect(hello.stream)
        for topic in topics:
            sub.setsockopt(zmq.SUBSCRIBE, topic)
        return sub

    def surface_mirror(self):
        """A :class:`~polycut.SurfaceMirror`, subscribed and synchronized."""
        from .mirror import SurfaceMirror
        return SurfaceMirror(self)
