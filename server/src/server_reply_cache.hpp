// Reply cache for retried requests (docs/protocol.md "Retries and the reply cache"): the encoded
// reply of a `cut`, `end_stroke`, `apply_force` or `grab`, keyed by (client identity, request
// id), so a request resent with the same id is answered again without being applied twice.
// Bounded per client (oldest dropped first) and by age.
#pragma once

#include "polycut/protocol/frames.hpp"

#include <cstddef>
#include <deque>
#include <map>
#include <string>
#include <string_view>

namespace polycut::server {

/// Bounds of the cache.
struct ReplyCacheLimits {
    std::size_t per_client = 64; ///< replies kept per client
    double max_age_s = 60.0; ///< replies older than this are dropped [s]
};

/// The cache. Keys: client identity bytes and the id as compact JSON text (to_json_text).
class ReplyCache {
public:
    explicit ReplyCache(ReplyCacheLimits limits = {})
        : m_limits(limits) { }

    /// The cached reply (without routing envelope), or nullptr.
    const protocol::Message* find(std::string_view client, std::string_view id_text) const;
    /// Stores a reply, dropping the client's oldest past the per-client bound.
    void store(std::string_view client, std::string id_text, protocol::Message reply, double now_s);
    /// Drops replies older than the age limit, and clients left with none.
    void expire(double now_s);
    /// Drops a client's replies.
    void drop_client(std::string_view client);
    /// Total replies held.
    std::size_t size() const;

private:
    struct Entry {
        std::string id_text;
        protocol::Message reply;
        double stored_s = 0.0;
    };
    ReplyCacheLimits m_limits;
    std::map<std::string, std::deque<Entry>, std::less<>> m_clients;
};

} // namespace polycut::server
