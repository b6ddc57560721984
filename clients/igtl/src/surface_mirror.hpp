// A client's copy of the streamed surface, kept by the Clone pattern of docs/protocol.md "Late
// joiners and gaps": frames arriving before the first snapshot (or during a resync) are
// buffered; a snapshot replaces the state and the buffered frames after it are applied; a frame
// that does not follow (seq gap, a seq that went back because the server restarted, a topology
// change without arrays) asks for a new snapshot.
#pragma once

#include "polycut/protocol/stream.hpp"

#include <deque>
#include <optional>

namespace polycut::igtl_bridge {

class SurfaceMirror {
public:
    /// What the caller must do after handing over a frame.
    enum class Next { Nothing, Updated, NeedSnapshot };

    /// A stream frame. Updated when the surface changed; NeedSnapshot when the caller must call
    /// get_surface and hand its result to snapshot() (the frame is kept meanwhile).
    Next frame(protocol::SurfaceFrame frame);
    /// A get_surface result; applies the buffered frames after it. Returns whether a buffered
    /// frame did not follow (then another snapshot is needed).
    Next snapshot(protocol::SurfaceSnapshot snapshot);

    /// The current surface (header, positions, triangles, tags), if synchronized.
    const std::optional<protocol::SurfaceFrame>& surface() const { return m_surface; }
    /// Snapshots taken, i.e. 1 + resynchronizations.
    long snapshots() const { return m_snapshots; }
    /// True while a snapshot is awaited.
    bool syncing() const { return m_syncing; }

private:
    /// Applies a frame that follows the current surface; false when it does not.
    bool apply(protocol::SurfaceFrame& frame);

    std::optional<protocol::SurfaceFrame> m_surface;
    std::deque<protocol::SurfaceFrame> m_buffer;
    bool m_syncing = true;
    long m_snapshots = 0;
};

} // namespace polycut::igtl_bridge
