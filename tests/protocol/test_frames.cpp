// Binary frames: exact little-endian layout, size checks, non-finite rejection, envelopes.
#include "polycut/protocol/frames.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <limits>

namespace polycut::protocol {
namespace {

TEST(ProtocolFrames, LittleEndianByteLayout) {
    const std::vector<float> f = { 1.0f, -2.0f };
    const Frame ff = encode_array(std::span<const float>(f));
    // IEEE 754: 1.0f = 0x3f800000, -2.0f = 0xc0000000.
    EXPECT_EQ(ff, std::string("\x00\x00\x80\x3f\x00\x00\x00\xc0", 8));
    const std::vector<std::uint32_t> u = { 0x01020304u };
    EXPECT_EQ(encode_array(std::span<const std::uint32_t>(u)), std::string("\x04\x03\x02\x01", 4));
    const std::vector<std::uint8_t> b = { 1, 2, 255 };
    EXPECT_EQ(encode_array(std::span<const std::uint8_t>(b)), std::string("\x01\x02\xff", 3));
}

TEST(ProtocolFrames, RoundTripEachDtype) {
    const std::vector<float> f = { 0.5f, -1e-30f, 3.25e20f, 0.0f, -0.0f, 7.0f };
    const FrameRef fref { 1, DType::Float32, { 2, 3 } };
    const auto fd = decode_float32(encode_array(std::span<const float>(f)), fref, "/x");
    ASSERT_TRUE(fd.ok());
    EXPECT_EQ(fd.value(), f);
    const std::vector<std::uint32_t> u = { 0, 1, 0xffffffffu };
    const auto ud = decode_uint32(encode_array(std::span<const std::uint32_t>(u)),
        FrameRef { 2, DType::UInt32, { 1, 3 } }, "/t");
    ASSERT_TRUE(ud.ok());
    EXPECT_EQ(ud.value(), u);
    const std::vector<std::uint8_t> b = { 1, 2, 2, 1 };
    const auto bd = decode_uint8(
        encode_array(std::span<const std::uint8_t>(b)), FrameRef { 3, DType::UInt8, { 4 } }, "/g");
    ASSERT_TRUE(bd.ok());
    EXPECT_EQ(bd.value(), b);
}

TEST(ProtocolFrames, ByteLengthMustMatchShapeExactly) {
    const FrameRef ref { 1, DType::Float32, { 2, 3 } };
    for (std::size_t bytes : { 0u, 23u, 25u, 48u }) {
        const auto d = decode_float32(std::string(bytes, '\0'), ref, "/p");
        ASSERT_FALSE(d.ok()) << bytes;
        EXPECT_EQ(d.error().code, ErrorCode::InvalidParams);
        EXPECT_EQ(d.error().pointer, "/p");
    }
    EXPECT_TRUE(decode_float32(std::string(24, '\0'), ref, "/p").ok());
    // Empty shape dimension: zero elements, zero bytes.
    EXPECT_TRUE(decode_uint32("", FrameRef { 1, DType::UInt32, { 0, 3 } }, "/t").ok());
}

TEST(ProtocolFrames, NonFiniteFloatsPointAtTheElement) {
    std::vector<float> f(12, 1.0f);
    f[7] = -std::numeric_limits<float>::infinity();
    const auto d = decode_float32(
        encode_array(std::span<const float>(f)), FrameRef { 1, DType::Float32, { 2, 2, 3 } }, "/a");
    ASSERT_FALSE(d.ok());
    EXPECT_EQ(d.error().pointer, "/a/1/0/1"); // 7 = 1*6 + 0*3 + 1
}

TEST(ProtocolFrames, DtypeMismatchAndOverflow) {
    const auto d = decode_uint32(std::string(4, '\0'), FrameRef { 1, DType::Float32, { 1 } }, "/a");
    ASSERT_FALSE(d.ok());
    EXPECT_EQ(d.error().pointer, "/a/dtype");
    const FrameRef huge { 1, DType::Float32, { 1u << 31, 1u << 31, 1u << 31 } };
    EXPECT_FALSE(huge.element_count().has_value());
    EXPECT_FALSE(decode_float32("", huge, "/a").ok());
    EXPECT_EQ(dtype_from_name("float64"), std::nullopt);
    EXPECT_EQ(dtype_size(DType::UInt8), 1u);
}

TEST(ProtocolFrames, SplitEnvelopeDealerAndReq) {
    const auto dealer = split_envelope(Message { "ID", "{}", "bin" });
    EXPECT_EQ(dealer.envelope, (Message { "ID" }));
    EXPECT_EQ(dealer.body, (Message { "{}", "bin" }));
    const auto req = split_envelope(Message { "ID", "", "{}" });
    EXPECT_EQ(req.envelope, (Message { "ID", "" }));
    EXPECT_EQ(req.body, (Message { "{}" }));
    const auto only_id = split_envelope(Message { "ID" });
    EXPECT_TRUE(only_id.body.empty());
}

} // namespace
} // namespace polycut::protocol
