// Small helpers shared by the two source files of Session (server_session.cpp and
// server_session_cut.cpp). Private to the server.
#pragma once
#include "server_session.hpp"

namespace polycut::server::detail {

/// A result that did not change the scene.
inline Applied done(protocol::Result result) {
    return Applied { std::move(result), false, {} };
}

inline Vec3 to_vec(const protocol::Vector3& v) {
    return Vec3(v[0], v[1], v[2]);
}

inline protocol::Triangle3 to_triangle(const std::array<Vec3, 3>& t) {
    protocol::Triangle3 out;
    for (std::size_t k = 0; k < 3; ++k)
        out[k] = { t[k].x(), t[k].y(), t[k].z() };
    return out;
}

} // namespace polycut::server::detail
