// libFuzzer target: the control-message decoder (issue 14 item 6). Input: byte 0 = number of
// binary frames (0..3, mod 4), the rest split into the JSON frame and those frames at the
// following bytes' offsets. The decoder must never throw, and whatever it accepts must encode
// and decode to the same request.
#include "polycut/protocol/request.hpp"

#include <array>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace polycut::protocol;
    if (size == 0) {
        return 0;
    }
    const std::size_t extra = data[0] % 4;
    std::string_view rest(reinterpret_cast<const char*>(data + 1), size - 1);
    // Each binary frame takes the last 36 bytes (or what is left), the JSON frame the rest.
    std::array<std::string_view, 4> frames {};
    for (std::size_t k = extra; k >= 1; --k) {
        const std::size_t take = std::min<std::size_t>(36, rest.size());
        frames[k] = rest.substr(rest.size() - take);
        rest.remove_suffix(take);
    }
    frames[0] = rest;
    Limits limits;
    limits.max_triangles_per_cut = 64;
    const auto decoded
        = decode_request(std::span<const std::string_view>(frames.data(), extra + 1), limits);
    if (decoded) {
        const Message again = encode_request(decoded.value(), EncodeOptions { extra % 2 == 1 });
        const auto round = decode_request(again, limits);
        if (!round || round.value().id != decoded.value().id
            || round.value().method() != decoded.value().method()) {
            std::abort(); // an accepted request that does not survive its own encoding
        }
    }
    return 0;
}
