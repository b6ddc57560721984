// Private: strict readers from nlohmann::json with JSON-pointer error reporting. Failures throw
// detail::Failure internally; the public decode functions catch it and return the RpcError, so
// nothing escapes to the wire-facing API.
#pragma once

#include "polycut/protocol/error.hpp"
#include "polycut/protocol/frames.hpp"
#include "polycut/protocol/params.hpp"
#include "polycut/protocol/request_id.hpp"

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace polycut::protocol::detail {

/// Insertion-ordered objects: replies read in the documented member order and inline scenes
/// keep their author's order.
using json = nlohmann::ordered_json;

/// Internal exception carrying the error to answer.
struct Failure {
    RpcError error;
};

/// Throws Failure{make_error(code, pointer, reason)}.
[[noreturn]] void fail(ErrorCode code, std::string pointer, std::string reason);

/// "object", "array", "string", "number", "boolean", "null".
std::string_view json_type_name(const json& value);
/// Shortest round-trip text of a number, for messages.
std::string format_number(double value);

/// Member `key` of an object, or nullptr when absent.
const json* find_member(const json& object, std::string_view key);

/// Parses a JSON frame: invalid UTF-8 or syntax -> -32700 with the byte offset in the reason.
json parse_frame(std::string_view text);
/// Compact JSON text; invalid UTF-8 in strings is replaced (never throws).
std::string dump(const json& value);

/// A closed/open interval check for numbers.
struct Range {
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool lo_open = false;
    bool hi_open = false;
};

/// Reads one member at a time from an object and reports missing and unknown members.
class ObjectReader {
public:
    /// `code` is used for every failure (InvalidParams for params, InvalidRequest elsewhere).
    ObjectReader(const json& value, std::string pointer, ErrorCode code = ErrorCode::InvalidParams);

    /// The member, or nullptr if absent; marks it as known.
    const json* optional(std::string_view key);
    /// The member; fails "missing required member" if absent.
    const json& required(std::string_view key);
    /// Pointer to a member.
    std::string at(std::string_view key) const { return pointer_append(m_pointer, key); }
    /// Fails on the first member that was never asked for ("unknown member").
    void finish() const;
    ErrorCode code() const { return m_code; }
    const std::string& pointer() const { return m_pointer; }

private:
    const json& m_value;
    std::string m_pointer;
    ErrorCode m_code;
    std::vector<std::string_view> m_known;
};

/// Finite number within `range`.
double read_number(const json& value, const std::string& pointer, Range range = {},
    ErrorCode code = ErrorCode::InvalidParams);
/// Integer (an integral float like 3.0 is accepted) in [lo, hi].
std::uint64_t read_uint(const json& value, const std::string& pointer, std::uint64_t lo,
    std::uint64_t hi, ErrorCode code = ErrorCode::InvalidParams);
std::int64_t read_int(const json& value, const std::string& pointer, std::int64_t lo,
    std::int64_t hi, ErrorCode code = ErrorCode::InvalidParams);
bool read_bool(
    const json& value, const std::string& pointer, ErrorCode code = ErrorCode::InvalidParams);
/// String of at most `max_bytes` bytes.
std::string read_string(const json& value, const std::string& pointer, std::size_t max_bytes,
    ErrorCode code = ErrorCode::InvalidParams);
/// [x, y, z], each finite with |c| <= max_abs.
Vector3 read_vector3(const json& value, const std::string& pointer, double max_abs,
    ErrorCode code = ErrorCode::InvalidParams);

/// JSON-RPC ids: integer, string or null; else fails with `code`.
RequestId read_request_id(const json& value, const std::string& pointer, ErrorCode code);
json request_id_to_json(const RequestId& id);

/// Largest integer exactly representable in a double (ids stay below it for JS clients).
inline constexpr std::uint64_t kMaxSafeInteger = (std::uint64_t { 1 } << 53) - 1;

/// The binary frames after the JSON frame, with use tracking.
class FrameSet {
public:
    explicit FrameSet(std::span<const std::string_view> frames);
    /// Number of binary frames.
    std::size_t size() const { return m_frames.size(); }
    /// True if `value` is an object with a "$frame" member (a frame reference).
    static bool is_ref(const json& value);
    /// Parses a frame reference {"$frame", "dtype", "shape"} and checks the frame exists.
    FrameRef read_ref(const json& value, const std::string& pointer, ErrorCode code);
    /// Bytes of frame k (1-based), marking it used.
    std::string_view bytes(const FrameRef& ref);
    /// Fails (-32600) if some frame was never referenced.
    void check_all_used() const;

private:
    std::span<const std::string_view> m_frames;
    std::vector<bool> m_used;
};

/// JSON of a frame reference.
json frame_ref_json(std::uint32_t frame, DType dtype, std::vector<std::uint64_t> shape);

} // namespace polycut::protocol::detail
