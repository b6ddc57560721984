// The WebSocket framing of polycut-web: a ZeroMQ multipart message travels to the browser as one
// binary WebSocket message, the frames packed unchanged behind a small table of their sizes, so
// the browser reads the same JSON-RPC replies and binary surface frames as a ZeroMQ client
// (docs/viewer.md, "Wire"). Browser to bridge: a text message is a one-frame request; a binary
// message is an envelope (a request with binary frames).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace polycut::web {

/// Packs frames as: uint32 count, count x uint32 byte sizes, then the frames back to back
/// (all little-endian, no padding).
std::string pack_frames(const std::vector<std::string>& frames);

/// Unpacks an envelope; nullopt when the sizes do not add up to the message's length, or when it
/// holds more than `max_frames` frames.
std::optional<std::vector<std::string>> unpack_frames(
    std::string_view message, std::size_t max_frames);

} // namespace polycut::web
