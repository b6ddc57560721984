"""Kept for scripts written before the package: the client now lives in the ``polycut`` package
beside this file (``pip install ./clients/python``; docs in polycut/__init__.py)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from polycut.client import Client, RpcError  # noqa: E402,F401
from polycut.mirror import SurfaceMirror  # noqa: E402,F401

__all__ = ["Client", "RpcError", "SurfaceMirror"]
