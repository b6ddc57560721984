// Open scalpel strokes: the last blade sample of each (client, stroke id), so consecutive samples
// can be joined into sweep triangles. Bounded per client and in total, and expired when idle, so
// a client that disappears mid-stroke leaves nothing behind for long.
#pragma once

#include "polycut/protocol/params.hpp"

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <utility>

namespace polycut::server {

/// Bounds of the stroke table.
struct StrokeLimits {
    std::size_t max_per_client = 64; ///< open strokes per client; the least recently used goes
    std::size_t max_total = 4096; ///< open strokes over all clients; the least recently used goes
    double idle_s = 60.0; ///< a stroke without samples for this long is dropped [s]
};

/// One open stroke.
struct Stroke {
    protocol::Vector3 a {}; ///< last blade sample swept to, endpoint a [m]
    protocol::Vector3 b {}; ///< last blade sample swept to, endpoint b [m]
    /// The newest sample when the blade has not yet moved far enough from (a, b) to be swept
    /// (Simulation::blade_min_advance); swept by the next sample or end_stroke.
    bool held = false;
    protocol::Vector3 held_a {}, held_b {}; ///< [m]
    std::uint32_t triangles = 0; ///< sweep triangles applied so far
    double last_used_s = 0.0; ///< monotonic wall time of the last sample [s]
};

/// The table of open strokes keyed by (client identity, stroke id).
class StrokeTable {
public:
    using Key = std::pair<std::string, std::uint64_t>;

    explicit StrokeTable(StrokeLimits limits = {})
        : m_limits(limits) { }

    /// The open stroke, or nullptr.
    Stroke* find(std::string_view client, std::uint64_t stroke);
    const Stroke* find(std::string_view client, std::uint64_t stroke) const;
    /// Opens a stroke (evicting the least recently used ones past the limits) and returns it.
    Stroke& open(std::string_view client, std::uint64_t stroke, double now_s);
    /// Closes a stroke; false when it was not open.
    bool close(std::string_view client, std::uint64_t stroke);
    /// Drops every stroke of a client.
    void drop_client(std::string_view client);
    /// Drops strokes idle for longer than limits.idle_s.
    void expire(double now_s);
    /// Drops everything (scene load or reset).
    void clear() { m_strokes.clear(); }

    std::size_t size() const { return m_strokes.size(); }
    const std::map<Key, Stroke>& entries() const { return m_strokes; }

private:
    void evict_oldest(std::string_view only_client);

    StrokeLimits m_limits;
    std::map<Key, Stroke> m_strokes;
};

} // namespace polycut::server
