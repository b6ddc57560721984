// Reply cache for retried requests (see server_reply_cache.hpp).
#include "server_reply_cache.hpp"

namespace polycut::server {

const protocol::Message* ReplyCache::find(std::string_view client, std::string_view id_text) const {
    auto it = m_clients.find(client);
    if (it == m_clients.end()) {
        return nullptr;
    }
    for (const Entry& e : it->second) {
        if (e.id_text == id_text) {
            return &e.reply;
        }
    }
    return nullptr;
}

void ReplyCache::store(
    std::string_view client, std::string id_text, protocol::Message reply, double now_s) {
    auto it = m_clients.find(client);
    if (it == m_clients.end()) {
        it = m_clients.emplace(std::string(client), std::deque<Entry> {}).first;
    }
    auto& entries = it->second;
    entries.push_back(Entry { std::move(id_text), std::move(reply), now_s });
    while (entries.size() > m_limits.per_client) {
        entries.pop_front();
    }
}

void ReplyCache::expire(double now_s) {
    for (auto it = m_clients.begin(); it != m_clients.end();) {
        auto& entries = it->second;
        while (!entries.empty() && now_s - entries.front().stored_s > m_limits.max_age_s) {
            entries.pop_front();
        }
        it = entries.empty() ? m_clients.erase(it) : std::next(it);
    }
}

void ReplyCache::drop_client(std::string_view client) {
    auto it = m_clients.find(client);
    if (it != m_clients.end()) {
        m_clients.erase(it);
    }
}

std::size_t ReplyCache::size() const {
    std::size_t n = 0;
    for (const auto& [client, entries] : m_clients) {
        n += entries.size();
    }
    return n;
}

} // namespace polycut::server
