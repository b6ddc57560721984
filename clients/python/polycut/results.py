"""Typed results of polycut-server's methods (docs/protocol.md "Methods").

Each result keeps the reply's JSON object in ``raw`` and can be indexed like it
(``result["tick"]``), so code written against plain dicts keeps working; members the server adds
within polycut/1 are in ``raw``.
"""
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional

import numpy as np


class _Result:
    raw: Dict[str, Any]

    def __getitem__(self, key):
        return self.raw[key]

    def get(self, key, default=None):
        return self.raw.get(key, default)


@dataclass
class Hello(_Result):
    """``hello``: the protocol, limits and the stream endpoint."""
    protocol: str
    server: str
    stream: str
    tick: int
    rate_hz: float
    running: bool
    scene: Optional[str]
    limits: Dict[str, Any]
    capabilities: List[str]
    raw: Dict[str, Any] = field(repr=False, default_factory=dict)

    @classmethod
    def from_json(cls, r):
        return cls(r["protocol"], r["server"], r["stream"], r["tick"], r["rate_hz"], r["running"],
                   r.get("scene"), r["limits"], r["capabilities"], r)


@dataclass
class SceneInfo(_Result):
    """``load_scene``: the loaded scene's name and sizes."""
    name: str
    tick: int
    topology_version: int
    vertex_count: int
    triangle_count: int
    cell_count: int
    raw: Dict[str, Any] = field(repr=False, default_factory=dict)

    @classmethod
    def from_json(cls, r):
        return cls(r["name"], r["tick"], r["topology_version"], r["vertex_count"],
                   r["triangle_count"], r["cell_count"], r)


@dataclass
class RunState(_Result):
    """``reset``, ``pause``, ``resume``, ``step``, ``set_rate``: the tick and run state."""
    tick: int
    running: bool
    rate_hz: float
    raw: Dict[str, Any] = field(repr=False, default_factory=dict)

    @classmethod
    def from_json(cls, r):
        return cls(r["tick"], r["running"], r["rate_hz"], r)


@dataclass
class CutResult(_Result):
    """``cut`` and ``end_stroke``: sweep triangles applied now and left to later ticks."""
    tick: int
    topology_version: int
    triangles: int
    deferred: int
    raw: Dict[str, Any] = field(repr=False, default_factory=dict)

    @classmethod
    def from_json(cls, r):
        return cls(r["tick"], r["topology_version"], r["triangles"], r.get("deferred", 0), r)


@dataclass
class Stats(_Result):
    """``get_stats``: server statistics (the most used members; all of them in ``raw``)."""
    tick: int
    sim_time: float
    running: bool
    seq: int
    topology_version: int
    vertex_count: int
    triangle_count: int
    cell_count: int
    step_ms_p50: float
    step_ms_p99: float
    ticks_over_budget: int
    forces: int
    grabs: int
    raw: Dict[str, Any] = field(repr=False, default_factory=dict)

    @classmethod
    def from_json(cls, r):
        return cls(r["tick"], r["sim_time"], r["running"], r["seq"], r["topology_version"],
                   r["vertex_count"], r["triangle_count"], r["cell_count"], r["step_ms_p50"],
                   r["step_ms_p99"], r["ticks_over_budget"], r["forces"], r["grabs"], r)


@dataclass
class Surface:
    """A surface: the frame header, positions (V x 3 float32 [m], world space), triangles
    (T x 3 uint32, counter-clockwise seen from outside) and tags (T uint8: 1 skin, 2 cut).
    Unpacks as ``header, positions, triangles, tags``."""
    header: Dict[str, Any]
    positions: np.ndarray
    triangles: np.ndarray
    tags: np.ndarray

    def __iter__(self):
        return iter((self.header, self.positions, self.triangles, self.tags))

    @property
    def seq(self):
        return self.header["seq"]

    @property
    def cut_triangles(self):
        """Number of triangles on a cut surface."""
        return int(np.count_nonzero(self.tags == 2))
