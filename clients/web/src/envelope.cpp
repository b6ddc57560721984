// WebSocket envelope of multipart messages (see envelope.hpp).
#include "envelope.hpp"

namespace polycut::web {

namespace {

void put_u32(std::string& out, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) {
        out.push_back(static_cast<char>((v >> (8 * k)) & 0xffu));
    }
}

std::uint32_t get_u32(std::string_view in, std::size_t at) {
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) {
        v |= std::uint32_t(static_cast<unsigned char>(in[at + std::size_t(k)])) << (8 * k);
    }
    return v;
}

} // namespace

std::string pack_frames(const std::vector<std::string>& frames) {
    std::size_t total = 4 + 4 * frames.size();
    for (const auto& f : frames) {
        total += f.size();
    }
    std::string out;
    out.reserve(total);
    put_u32(out, std::uint32_t(frames.size()));
    for (const auto& f : frames) {
        put_u32(out, std::uint32_t(f.size()));
    }
    for (const auto& f : frames) {
        out += f;
    }
    return out;
}

std::optional<std::vector<std::string>> unpack_frames(
    std::string_view message, std::size_t max_frames) {
    if (message.size() < 4) {
        return std::nullopt;
    }
    const std::size_t count = get_u32(message, 0);
    if (count == 0 || count > max_frames || message.size() < 4 + 4 * count) {
        return std::nullopt;
    }
    std::size_t at = 4 + 4 * count;
    std::vector<std::string> frames;
    frames.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t size = get_u32(message, 4 + 4 * i);
        if (size > message.size() - at) {
            return std::nullopt;
        }
        frames.emplace_back(message.substr(at, size));
        at += size;
    }
    if (at != message.size()) {
        return std::nullopt;
    }
    return frames;
}

} // namespace polycut::web
