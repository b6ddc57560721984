// The Clone-pattern surface mirror (see surface_mirror.hpp).
#include "surface_mirror.hpp"

namespace polycut::igtl_bridge {

namespace {
constexpr std::size_t kMaxBuffered = 256;
}

SurfaceMirror::Next SurfaceMirror::frame(protocol::SurfaceFrame frame) {
    if (m_syncing) {
        if (m_buffer.size() >= kMaxBuffered) {
            m_buffer.pop_front();
        }
        m_buffer.push_back(std::move(frame));
        return Next::Nothing;
    }
    if (apply(frame)) {
        return Next::Updated;
    }
    m_syncing = true;
    m_buffer.push_back(std::move(frame));
    return Next::NeedSnapshot;
}

SurfaceMirror::Next SurfaceMirror::snapshot(protocol::SurfaceSnapshot snapshot) {
    ++m_snapshots;
    m_surface = std::move(snapshot);
    m_syncing = false;
    std::deque<protocol::SurfaceFrame> buffered;
    buffered.swap(m_buffer);
    for (auto& f : buffered) {
        if (f.header.seq <= m_surface->header.seq) {
            continue;
        }
        if (!apply(f)) {
            m_syncing = true;
            return Next::NeedSnapshot;
        }
    }
    return Next::Updated;
}

bool SurfaceMirror::apply(protocol::SurfaceFrame& frame) {
    auto& s = *m_surface;
    const bool follows = frame.header.seq == s.header.seq + 1;
    const bool topology_known = frame.header.has_topology
        || (frame.header.topology_version == s.header.topology_version
            && frame.positions.size() == s.positions.size());
    if (!follows || !topology_known) {
        return false;
    }
    s.positions = std::move(frame.positions);
    if (frame.header.has_topology) {
        s.triangles = std::move(frame.triangles);
        s.tags = std::move(frame.tags);
    }
    s.header = std::move(frame.header);
    return true;
}

} // namespace polycut::igtl_bridge
