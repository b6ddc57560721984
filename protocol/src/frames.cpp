// Binary array frames: little-endian encode/decode with exact size and finiteness checks.
#include "polycut/protocol/frames.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace polycut::protocol {

namespace {

constexpr bool kLittle = std::endian::native == std::endian::little;
static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big,
    "mixed-endian hosts are not supported");

std::uint32_t byteswap32(std::uint32_t v) {
    return __builtin_bswap32(v);
}

template <class T> Frame encode_4byte(std::span<const T> values) {
    static_assert(sizeof(T) == 4);
    Frame out(values.size() * 4, '\0');
    if constexpr (kLittle) {
        if (!values.empty()) {
            std::memcpy(out.data(), values.data(), out.size());
        }
    } else {
        for (std::size_t i = 0; i < values.size(); ++i) {
            std::uint32_t word;
            std::memcpy(&word, &values[i], 4);
            word = byteswap32(word);
            std::memcpy(out.data() + 4 * i, &word, 4);
        }
    }
    return out;
}

template <class T> void read_4byte(std::string_view bytes, std::vector<T>& out) {
    out.resize(bytes.size() / 4);
    if (out.empty()) {
        return;
    }
    std::memcpy(out.data(), bytes.data(), out.size() * 4);
    if constexpr (!kLittle) {
        for (auto& v : out) {
            std::uint32_t word;
            std::memcpy(&word, &v, 4);
            word = byteswap32(word);
            std::memcpy(&v, &word, 4);
        }
    }
}

/// C-order multi-index of flat element `flat` appended to `pointer`.
std::string element_pointer(std::string_view pointer, const FrameRef& ref, std::uint64_t flat) {
    std::vector<std::uint64_t> index(ref.shape.size(), 0);
    for (std::size_t d = ref.shape.size(); d-- > 0;) {
        const std::uint64_t extent = ref.shape[d] == 0 ? 1 : ref.shape[d];
        index[d] = flat % extent;
        flat /= extent;
    }
    std::string out(pointer);
    for (auto i : index) {
        out = pointer_append(out, static_cast<std::size_t>(i));
    }
    return out;
}

/// Checks dtype and byte length; returns an error or nullopt.
std::optional<RpcError> check_layout(
    std::string_view bytes, const FrameRef& ref, DType expected, std::string_view pointer) {
    if (ref.dtype != expected) {
        return make_error(ErrorCode::InvalidParams, pointer_append(pointer, "dtype"),
            "dtype must be " + std::string(dtype_name(expected)) + ", got "
                + std::string(dtype_name(ref.dtype)));
    }
    const auto count = ref.element_count();
    const std::uint64_t itemsize = dtype_size(expected);
    if (!count || *count > std::numeric_limits<std::uint64_t>::max() / itemsize) {
        return make_error(
            ErrorCode::PayloadTooLarge, pointer_append(pointer, "shape"), "shape overflows");
    }
    if (bytes.size() != *count * itemsize) {
        return make_error(ErrorCode::InvalidParams, std::string(pointer),
            "binary frame " + std::to_string(ref.frame) + " holds " + std::to_string(bytes.size())
                + " bytes; shape and dtype require " + std::to_string(*count * itemsize));
    }
    return std::nullopt;
}

} // namespace

std::string_view dtype_name(DType dtype) {
    switch (dtype) {
    case DType::Float32:
        return "float32";
    case DType::UInt32:
        return "uint32";
    case DType::UInt8:
        return "uint8";
    }
    return "?";
}

std::optional<DType> dtype_from_name(std::string_view name) {
    if (name == "float32") {
        return DType::Float32;
    }
    if (name == "uint32") {
        return DType::UInt32;
    }
    if (name == "uint8") {
        return DType::UInt8;
    }
    return std::nullopt;
}

std::size_t dtype_size(DType dtype) {
    return dtype == DType::UInt8 ? 1 : 4;
}

std::optional<std::uint64_t> FrameRef::element_count() const {
    std::uint64_t n = 1;
    for (auto extent : shape) {
        if (extent != 0 && n > (std::uint64_t { 1 } << 63) / extent) {
            return std::nullopt;
        }
        n *= extent;
    }
    return n;
}

Frame encode_array(std::span<const float> values) {
    return encode_4byte(values);
}
Frame encode_array(std::span<const std::uint32_t> values) {
    return encode_4byte(values);
}
Frame encode_array(std::span<const std::uint8_t> values) {
    return Frame(reinterpret_cast<const char*>(values.data()), values.size());
}

Expected<std::vector<float>, RpcError> decode_float32(
    std::string_view bytes, const FrameRef& ref, std::string_view pointer) {
    if (auto error = check_layout(bytes, ref, DType::Float32, pointer)) {
        return *error;
    }
    std::vector<float> out;
    read_4byte(bytes, out);
    for (std::size_t i = 0; i < out.size(); ++i) {
        if (!std::isfinite(out[i])) {
            return make_error(ErrorCode::InvalidParams, element_pointer(pointer, ref, i),
                std::string(std::isnan(out[i]) ? "NaN" : "infinite value") + " in float32 frame "
                    + std::to_string(ref.frame) + " at element " + std::to_string(i));
        }
    }
    return out;
}

Expected<std::vector<std::uint32_t>, RpcError> decode_uint32(
    std::string_view bytes, const FrameRef& ref, std::string_view pointer) {
    if (auto error = check_layout(bytes, ref, DType::UInt32, pointer)) {
        return *error;
    }
    std::vector<std::uint32_t> out;
    read_4byte(bytes, out);
    return out;
}

Expected<std::vector<std::uint8_t>, RpcError> decode_uint8(
    std::string_view bytes, const FrameRef& ref, std::string_view pointer) {
    if (auto error = check_layout(bytes, ref, DType::UInt8, pointer)) {
        return *error;
    }
    return std::vector<std::uint8_t>(bytes.begin(), bytes.end());
}

Routed split_envelope(Message message) {
    Routed routed;
    std::size_t body_begin = message.empty() ? 0 : 1;
    if (message.size() > 1 && message[1].empty()) {
        body_begin = 2;
    }
    routed.envelope.assign(std::make_move_iterator(message.begin()),
        std::make_move_iterator(message.begin() + static_cast<std::ptrdiff_t>(body_begin)));
    routed.body.assign(
        std::make_move_iterator(message.begin() + static_cast<std::ptrdiff_t>(body_begin)),
        std::make_move_iterator(message.end()));
    return routed;
}

std::vector<std::string_view> frame_views(const Message& message) {
    return std::vector<std::string_view>(message.begin(), message.end());
}

} // namespace polycut::protocol
