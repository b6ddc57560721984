// Strict JSON readers with JSON-pointer errors (private to the protocol library).
#include "json_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace polycut::protocol::detail {

namespace {

/// Deepest nesting of arrays/objects accepted in a frame (keeps recursive dump/compare safe).
constexpr std::size_t kMaxDepth = 64;

/// Nesting depth of JSON text, skipping strings (only an upper bound on invalid text).
std::size_t nesting_depth(std::string_view text, std::size_t& offset) {
    std::size_t depth = 0;
    std::size_t deepest = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\') {
                ++i;
            } else if (c == '"') {
                in_string = false;
            }
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > deepest) {
                deepest = depth;
                offset = i;
            }
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

} // namespace

void fail(ErrorCode code, std::string pointer, std::string reason) {
    throw Failure { make_error(code, std::move(pointer), std::move(reason)) };
}

std::string_view json_type_name(const json& value) {
    switch (value.type()) {
    case json::value_t::object:
        return "object";
    case json::value_t::array:
        return "array";
    case json::value_t::string:
        return "string";
    case json::value_t::boolean:
        return "boolean";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float:
        return "number";
    case json::value_t::null:
        return "null";
    default:
        return "binary";
    }
}

std::string format_number(double value) {
    char text[64];
    const auto result = std::to_chars(text, text + sizeof text, value);
    return std::string(text, result.ptr);
}

namespace {
/// nlohmann's what() without its "[json.exception.<kind>.<id>] " prefix.
std::string strip_exception_prefix(const std::string& what) {
    const auto close = what.find("] ");
    return what.rfind("[json.exception.", 0) == 0 && close != std::string::npos
        ? what.substr(close + 2)
        : what;
}
} // namespace

const json* find_member(const json& object, std::string_view key) {
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
}

json parse_frame(std::string_view text) {
    // nlohmann's lexer takes a NUL byte for the end of input, so "{...}\0garbage" would parse
    // as "{...}". JSON text never holds a raw NUL (in a string it must be escaped as \u0000).
    if (const auto nul = text.find('\0'); nul != std::string_view::npos) {
        fail(ErrorCode::ParseError, "",
            "NUL byte at offset " + std::to_string(nul) + " (JSON text cannot contain one)");
    }
    std::size_t offset = 0;
    if (nesting_depth(text, offset) > kMaxDepth) {
        fail(ErrorCode::ParseError, "",
            "nesting deeper than " + std::to_string(kMaxDepth) + " levels at byte "
                + std::to_string(offset));
    }
    try {
        return json::parse(text.begin(), text.end());
    } catch (const json::parse_error& e) {
        // e.what() names the position and, for bad UTF-8, "ill-formed UTF-8 byte".
        fail(ErrorCode::ParseError, "", strip_exception_prefix(e.what()));
    } catch (const json::exception& e) {
        fail(ErrorCode::ParseError, "", strip_exception_prefix(e.what()));
    }
}

std::string dump(const json& value) {
    return value.dump(-1, ' ', false, json::error_handler_t::replace);
}

ObjectReader::ObjectReader(const json& value, std::string pointer, ErrorCode code)
    : m_value(value)
    , m_pointer(std::move(pointer))
    , m_code(code) {
    if (!value.is_object()) {
        fail(code, m_pointer, "must be an object, got " + std::string(json_type_name(value)));
    }
}

const json* ObjectReader::optional(std::string_view key) {
    m_known.push_back(key);
    const auto it = m_value.find(key);
    return it == m_value.end() ? nullptr : &*it;
}

const json& ObjectReader::required(std::string_view key) {
    const json* member = optional(key);
    if (member == nullptr) {
        fail(m_code, at(key), "missing required member \"" + std::string(key) + "\"");
    }
    return *member;
}

void ObjectReader::finish() const {
    for (const auto& [key, member] : m_value.items()) {
        if (std::find(m_known.begin(), m_known.end(), key) == m_known.end()) {
            fail(m_code, at(key), "unknown member \"" + key + "\"");
        }
    }
}

double read_number(const json& value, const std::string& pointer, Range range, ErrorCode code) {
    if (!value.is_number()) {
        fail(code, pointer, "must be a number, got " + std::string(json_type_name(value)));
    }
    const double v = value.get<double>();
    if (!std::isfinite(v)) {
        fail(code, pointer, "must be finite");
    }
    const bool below = range.lo_open ? !(v > range.lo) : !(v >= range.lo);
    const bool above = range.hi_open ? !(v < range.hi) : !(v <= range.hi);
    if (below || above) {
        std::string rule;
        if (std::isfinite(range.lo)) {
            rule += (range.lo_open ? "> " : ">= ") + format_number(range.lo);
        }
        if (std::isfinite(range.hi)) {
            rule += (rule.empty() ? "" : " and ") + std::string(range.hi_open ? "< " : "<= ")
                + format_number(range.hi);
        }
        fail(code, pointer, "must be " + rule + ", got " + format_number(v));
    }
    return v;
}

namespace {
/// The integral value of a number as long double, or fails.
long double integral_value(const json& value, const std::string& pointer, ErrorCode code) {
    if (value.is_number_unsigned()) {
        return static_cast<long double>(value.get<std::uint64_t>());
    }
    if (value.is_number_integer()) {
        return static_cast<long double>(value.get<std::int64_t>());
    }
    if (value.is_number_float()) {
        const double v = value.get<double>();
        if (!std::isfinite(v) || v != std::floor(v)) {
            fail(code, pointer, "must be an integer, got " + format_number(v));
        }
        return static_cast<long double>(v);
    }
    fail(code, pointer, "must be an integer, got " + std::string(json_type_name(value)));
}
} // namespace

std::uint64_t read_uint(const json& value, const std::string& pointer, std::uint64_t lo,
    std::uint64_t hi, ErrorCode code) {
    if (value.is_number_unsigned()) {
        const auto v = value.get<std::uint64_t>();
        if (v < lo || v > hi) {
            fail(code, pointer,
                "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got "
                    + std::to_string(v));
        }
        return v;
    }
    const long double v = integral_value(value, pointer, code);
    if (v < static_cast<long double>(lo) || v > static_cast<long double>(hi)) {
        fail(code, pointer,
            "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got "
                + dump(value));
    }
    return static_cast<std::uint64_t>(v);
}

std::int64_t read_int(const json& value, const std::string& pointer, std::int64_t lo,
    std::int64_t hi, ErrorCode code) {
    const long double v = integral_value(value, pointer, code);
    if (v < static_cast<long double>(lo) || v > static_cast<long double>(hi)) {
        fail(code, pointer,
            "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got "
                + dump(value));
    }
    if (value.is_number_integer() && !value.is_number_unsigned()) {
        return value.get<std::int64_t>();
    }
    return static_cast<std::int64_t>(v);
}

bool read_bool(const json& value, const std::string& pointer, ErrorCode code) {
    if (!value.is_boolean()) {
        fail(code, pointer, "must be a boolean, got " + std::string(json_type_name(value)));
    }
    return value.get<bool>();
}

std::string read_string(
    const json& value, const std::string& pointer, std::size_t max_bytes, ErrorCode code) {
    if (!value.is_string()) {
        fail(code, pointer, "must be a string, got " + std::string(json_type_name(value)));
    }
    const auto& text = value.get_ref<const std::string&>();
    if (text.size() > max_bytes) {
        fail(code, pointer, "longer than " + std::to_string(max_bytes) + " bytes");
    }
    return text;
}

Vector3 read_vector3(
    const json& value, const std::string& pointer, double max_abs, ErrorCode code) {
    if (!value.is_array()) {
        fail(code, pointer,
            "must be an array of 3 numbers, got " + std::string(json_type_name(value)));
    }
    if (value.size() != 3) {
        fail(code, pointer, "must have 3 elements, got " + std::to_string(value.size()));
    }
    Vector3 out {};
    for (std::size_t i = 0; i < 3; ++i) {
        out[i]
            = read_number(value[i], pointer_append(pointer, i), Range { -max_abs, max_abs }, code);
    }
    return out;
}

RequestId read_request_id(const json& value, const std::string& pointer, ErrorCode code) {
    if (value.is_null()) {
        return nullptr;
    }
    if (value.is_string()) {
        return read_string(value, pointer, 256, code);
    }
    if (value.is_number()) {
        if (value.is_number_unsigned()
            && value.get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX)) {
            fail(code, pointer, "id out of range [-2^63, 2^63)");
        }
        if (value.is_number_float()) {
            // Integral floats (3.0) are integers (docs/protocol.md "Units and conventions").
            const double d = value.get<double>();
            if (!(std::isfinite(d) && d == std::floor(d))) {
                fail(code, pointer,
                    "id must be an integer, a string or null (fractional ids are not accepted)");
            }
            if (!(d >= -9223372036854775808.0 && d < 9223372036854775808.0)) {
                fail(code, pointer, "id out of range [-2^63, 2^63)");
            }
            return static_cast<std::int64_t>(d);
        }
        return value.get<std::int64_t>();
    }
    fail(code, pointer,
        "id must be an integer, a string or null, got " + std::string(json_type_name(value)));
}

json request_id_to_json(const RequestId& id) {
    if (const auto* number = std::get_if<std::int64_t>(&id)) {
        return *number;
    }
    if (const auto* text = std::get_if<std::string>(&id)) {
        return *text;
    }
    return nullptr;
}

FrameSet::FrameSet(std::span<const std::string_view> frames)
    : m_frames(frames)
    , m_used(frames.size(), false) { }

bool FrameSet::is_ref(const json& value) {
    return value.is_object() && value.contains("$frame");
}

FrameRef FrameSet::read_ref(const json& value, const std::string& pointer, ErrorCode code) {
    ObjectReader reader(value, pointer, code);
    FrameRef ref;
    const auto frame_pointer = reader.at("$frame");
    ref.frame = static_cast<std::uint32_t>(read_uint(reader.required("$frame"), frame_pointer, 1,
        std::numeric_limits<std::uint32_t>::max(), code));
    const auto dtype_text = read_string(reader.required("dtype"), reader.at("dtype"), 16, code);
    const auto dtype = dtype_from_name(dtype_text);
    if (!dtype) {
        fail(code, reader.at("dtype"),
            "must be \"float32\", \"uint32\" or \"uint8\", got \"" + dtype_text + "\"");
    }
    ref.dtype = *dtype;
    const json& shape = reader.required("shape");
    if (!shape.is_array() || shape.empty() || shape.size() > 4) {
        fail(code, reader.at("shape"), "must be an array of 1 to 4 non-negative integers");
    }
    for (std::size_t d = 0; d < shape.size(); ++d) {
        ref.shape.push_back(read_uint(shape[d], pointer_append(reader.at("shape"), d), 0,
            std::numeric_limits<std::uint32_t>::max(), code));
    }
    reader.finish();
    if (ref.frame > m_frames.size()) {
        fail(code, frame_pointer,
            "binary frame " + std::to_string(ref.frame) + " does not exist (the message has "
                + std::to_string(m_frames.size()) + " binary frames)");
    }
    return ref;
}

std::string_view FrameSet::bytes(const FrameRef& ref) {
    m_used.at(ref.frame - 1) = true;
    return m_frames[ref.frame - 1];
}

void FrameSet::check_all_used() const {
    for (std::size_t k = 0; k < m_used.size(); ++k) {
        if (!m_used[k]) {
            fail(ErrorCode::InvalidRequest, "",
                "binary frame " + std::to_string(k + 1) + " is not referenced by the JSON frame");
        }
    }
}

json frame_ref_json(std::uint32_t frame, DType dtype, std::vector<std::uint64_t> shape) {
    return json { { "$frame", frame }, { "dtype", std::string(dtype_name(dtype)) },
        { "shape", shape } };
}

} // namespace polycut::protocol::detail

namespace polycut::protocol {

std::string to_json_text(const RequestId& id) {
    return detail::dump(detail::request_id_to_json(id));
}

} // namespace polycut::protocol
