// Multipart messages and binary array frames. A message is one JSON frame plus optional further
// frames holding bulk arrays (little-endian, C order), each declared in the JSON where the array
// would be, by a frame reference {"$frame": k, "dtype": "float32", "shape": [T, 3, 3]}; k counts
// the frames after the JSON frame, starting at 1 (docs/protocol.md "Binary frames").
#pragma once

#include "polycut/protocol/error.hpp"
#include "polycut/protocol/expected.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace polycut::protocol {

/// One frame of a multipart message (raw bytes).
using Frame = std::string;
/// A multipart message: frames in order. For control messages, frame 0 is the JSON frame (the
/// ROUTER envelope is not part of it, see split_envelope); for stream messages, frame 0 is the
/// topic and frame 1 the JSON header.
using Message = std::vector<Frame>;

/// Element type of a binary array.
enum class DType : std::uint8_t { Float32, UInt32, UInt8 };

/// "float32", "uint32", "uint8".
std::string_view dtype_name(DType dtype);
/// Inverse of dtype_name; nullopt for anything else.
std::optional<DType> dtype_from_name(std::string_view name);
/// Bytes per element (4, 4, 1).
std::size_t dtype_size(DType dtype);

/// A frame reference as it appears in JSON.
struct FrameRef {
    std::uint32_t frame = 1; ///< index of the frame after the JSON frame (1 = the next one)
    DType dtype = DType::Float32;
    std::vector<std::uint64_t> shape; ///< C-order dimensions

    /// Product of `shape` (1 for an empty shape), or nullopt on overflow past 2^63.
    std::optional<std::uint64_t> element_count() const;
    bool operator==(const FrameRef&) const = default;
};

/// Little-endian bytes of an array (one frame).
Frame encode_array(std::span<const float> values);
Frame encode_array(std::span<const std::uint32_t> values);
Frame encode_array(std::span<const std::uint8_t> values);

/// Decodes a frame holding `ref` (dtype must match the overload). Checks the byte length is
/// exactly element_count * itemsize and, for float32, that every value is finite. Errors are
/// -32602 with `pointer` extended by the C-order index of the first bad element, or `pointer`
/// itself for a length mismatch.
Expected<std::vector<float>, RpcError> decode_float32(
    std::string_view bytes, const FrameRef& ref, std::string_view pointer);
Expected<std::vector<std::uint32_t>, RpcError> decode_uint32(
    std::string_view bytes, const FrameRef& ref, std::string_view pointer);
Expected<std::vector<std::uint8_t>, RpcError> decode_uint8(
    std::string_view bytes, const FrameRef& ref, std::string_view pointer);

/// A ROUTER message split into its routing envelope and body.
struct Routed {
    Message envelope; ///< identity frame(s), plus the empty delimiter when the peer is a REQ
    Message body; ///< JSON frame and binary frames
};

/// Splits a message received on a ROUTER socket: the first frame is the peer identity; if the
/// next frame is empty it is a REQ delimiter and stays in the envelope. Send replies as
/// envelope + reply frames.
Routed split_envelope(Message message);

/// Non-owning views of a message's frames (for zero-copy decoding of received zmq messages).
std::vector<std::string_view> frame_views(const Message& message);

} // namespace polycut::protocol
