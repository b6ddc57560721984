// Private: conversions between the typed messages and nlohmann::json, shared by the request,
// reply and stream codecs.
#pragma once

#include "json_reader.hpp"
#include "polycut/protocol/limits.hpp"
#include "polycut/protocol/reply.hpp"
#include "polycut/protocol/request.hpp"
#include "polycut/protocol/results.hpp"
#include "polycut/protocol/stream.hpp"

namespace polycut::protocol::detail {

/// Params of `method` from the "params" member (nullptr when absent = {}), pointer "/params".
Params decode_params(Method method, const json* params, FrameSet& frames, const Limits& limits);
/// JSON of params; binary arrays (when options.binary_arrays) are appended to `frames`, whose
/// size on entry is the number of frames already in the message after the JSON frame.
json encode_params(const Params& params, const EncodeOptions& options, Message& frames);

/// Result of `method` from the "result" member, pointer "/result".
Result decode_result(Method method, const json& result, FrameSet& frames);
/// JSON of a result; arrays appended to `frames`.
json encode_result_json(const Result& result, Message& frames);

/// Surface header members (no arrays) into `out`.
void write_surface_header(const SurfaceHeader& header, json& out);
/// Surface header plus its arrays (positions always; triangles/tags when has_topology) from an
/// object; unknown members are ignored (tolerant reader). `code` is used for every failure.
SurfaceFrame read_surface(
    const json& value, const std::string& pointer, FrameSet& frames, ErrorCode code);
/// Appends positions (and triangles/tags when has_topology) as frames and their references to
/// `out`.
void write_surface_arrays(const SurfaceHeader& header, std::span<const float> positions,
    std::span<const std::uint32_t> triangles, std::span<const std::uint8_t> tags, json& out,
    Message& frames);

/// Contact reports (stream header `contacts`, get_stats `contacts`) <-> a JSON array.
json contacts_json(const std::vector<ContactReport>& contacts);
std::vector<ContactReport> read_contacts(
    const json& value, const std::string& pointer, ErrorCode code);

} // namespace polycut::protocol::detail
