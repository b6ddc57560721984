"""polycut: a Python client of polycut-server (docs/protocol.md).

- :class:`Client` -- JSON-RPC 2.0 over a ZeroMQ DEALER, one typed method per protocol method.
- :class:`SurfaceMirror` -- a copy of the streamed surface kept by the Clone pattern.
- :class:`LocalServer` -- a context manager that starts a local polycut-server and stops it.
- :class:`RpcError` -- an error answered by the server (code, JSON pointer, reason).

Units are SI throughout: metres, newtons, seconds, N/m.
"""
from .client import Client, RpcError
from .mirror import SurfaceMirror
from .results import CutResult, Hello, RunState, SceneInfo, Stats, Surface
from .server import LocalServer, find_server

__all__ = ["Client", "RpcError", "SurfaceMirror", "LocalServer", "find_server", "Hello",
           "SceneInfo", "RunState", "CutResult", "Stats", "Surface"]
__version__ = "0.1.0"
