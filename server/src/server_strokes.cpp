// Open scalpel strokes (see server_strokes.hpp).
#include "server_strokes.hpp"

namespace polycut::server {

Stroke* StrokeTable::find(std::string_view client, std::uint64_t stroke) {
    auto it = m_strokes.find(Key { std::string(client), stroke });
    return it == m_strokes.end() ? nullptr : &it->second;
}

const Stroke* StrokeTable::find(std::string_view client, std::uint64_t stroke) const {
    auto it = m_strokes.find(Key { std::string(client), stroke });
    return it == m_strokes.end() ? nullptr : &it->second;
}

Stroke& StrokeTable::open(std::string_view client, std::uint64_t stroke, double now_s) {
    std::size_t of_client = 0;
    for (const auto& [key, value] : m_strokes) {
        of_client += key.first == client ? 1 : 0;
    }
    while (of_client >= m_limits.max_per_client && of_client > 0) {
        evict_oldest(client);
        --of_client;
    }
    while (m_strokes.size() >= m_limits.max_total && !m_strokes.empty()) {
        evict_oldest({});
    }
    Stroke& s = m_strokes[Key { std::string(client), stroke }];
    s = Stroke {};
    s.last_used_s = now_s;
    return s;
}

bool StrokeTable::close(std::string_view client, std::uint64_t stroke) {
    return m_strokes.erase(Key { std::string(client), stroke }) > 0;
}

void StrokeTable::drop_client(std::string_view client) {
    std::erase_if(m_strokes, [&](const auto& entry) { return entry.first.first == client; });
}

void StrokeTable::expire(double now_s) {
    std::erase_if(m_strokes,
        [&](const auto& entry) { return now_s - entry.second.last_used_s > m_limits.idle_s; });
}

void StrokeTable::evict_oldest(std::string_view only_client) {
    auto oldest = m_strokes.end();
    for (auto it = m_strokes.begin(); it != m_strokes.end(); ++it) {
        if (!only_client.empty() && it->first.first != only_client) {
            continue;
        }
        if (oldest == m_strokes.end() || it->second.last_used_s < oldest->second.last_used_s) {
            oldest = it;
        }
    }
    if (oldest != m_strokes.end()) {
        m_strokes.erase(oldest);
    }
}

} // namespace polycut::server
