"""A client-side copy of the streamed surface (docs/protocol.md "Late joiners and gaps")."""
import json

from .client import decode_array


class SurfaceMirror:
    """The published surface, kept by the zguide Clone pattern: subscribe first, take a
    ``get_surface`` snapshot (seq S), apply frames with seq > S in order, and take a new snapshot
    when a frame does not follow (a gap, a topology change without arrays, or a seq that went
    back because the server restarted).

    ``header`` (the last frame's header dict), ``positions`` (V x 3 float32 [m]), ``triangles``
    (T x 3 uint32) and ``tags`` (T uint8: 1 skin, 2 cut) are the current surface; ``snapshots``
    counts snapshots taken (1 + resynchronizations).
    """

    def __init__(self, client):
        self.client = client
        self.sub = client.subscribe((b"surface",))
        self.snapshots = 0
        self._snapshot()

    def _snapshot(self):
        self.header, self.positions, self.triangles, self.tags = self.client.get_surface()
        self.snapshots += 1

    def apply(self, frames):
        """Applies one stream message ``[topic, header, positions, (triangles, tags)]``."""
        header = json.loads(frames[1])
        seq = header["seq"]
        if seq == self.header["seq"] + 1 and (header["has_topology"] or header["topology_version"]
                                              == self.header["topology_version"]):
            arrays = frames[2:]
            self.positions = decode_array(header["positions"], arrays)
            if header["has_topology"]:
                self.triangles = decode_array(header["triangles"], arrays)
                self.tags = decode_array(header["tags"], arrays)
            self.header = header
        elif seq > self.header["seq"] or seq + 100 < self.header["seq"]:
            self._snapshot()  # frames were lost, or a new server counts from 1: start over
        # else: an older frame, already in the snapshot

    def update(self, timeout_ms=0):
        """Applies every frame that arrives within `timeout_ms` [ms]; returns how many."""
        n = 0
        while self.sub.poll(timeout_ms):
            self.apply(self.sub.recv_multipart())
            n += 1
            timeout_ms = 0
        return n

    def close(self):
        self.sub.close()
