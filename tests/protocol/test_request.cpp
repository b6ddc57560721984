// Request round trips: every method's params survive encode_request -> decode_request exactly.
#include "polycut/protocol/request.hpp"

#include <cstring>
#include <gtest/gtest.h>

namespace polycut::protocol {
namespace {

/// One representative params value per method (index = Method).
std::vector<Params> sample_params() {
    return {
        HelloParams { "test-client", "polycut/1" },
        LoadSceneParams { "cut_halves", std::nullopt },
        ResetParams {},
        PauseParams {},
        ResumeParams {},
        StepParams { 25 },
        SetRateParams { 120.5 },
        ApplyForceParams { { 0.01, -0.02, 0.03 }, { 0.0, 0.0, -1.5 }, 0.005, 0.25 },
        RemoveForceParams { 7 },
        GrabParams { { 0.0, 0.0, 0.05 }, 350.0, 0.004 },
        MoveGrabParams { 3, { 0.001, 0.002, 0.06 } },
        ReleaseParams { 3 },
        CutParams { { Triangle3 { { { 0.0, 0.0, 0.1 }, { 0.1, 0.0, 0.1 }, { 0.0, 0.0, -0.1 } } },
            Triangle3 { { { 0.1, 0.0, 0.1 }, { 0.1, 0.0, -0.1 }, { 0.0, 0.0, -0.1 } } } } },
        ScalpelParams { 4, { 0.0, 0.01, 0.05 }, { 0.0, 0.01, -0.01 } },
        EndStrokeParams { 4 },
        GetSurfaceParams {},
        GetStatsParams {},
        ShutdownParams {},
        ToolCreateParams { "capsule", 0.004, 0.08, std::nullopt, { 0.0, 0.01, 0.09 },
            Quaternion { 0.9238795, 0.3826834, 0.0, 0.0 }, 2e6, 0.3 },
        ToolMoveParams { 5, { 0.0, 0.012, 0.085 }, Quaternion { 1.0, 0.0, 0.0, 0.0 } },
        ToolRemoveParams { 5 },
    };
}

TEST(ProtocolRequest, EveryMethodHasASampleInEnumOrder) {
    const auto samples = sample_params();
    ASSERT_EQ(samples.size(), kMethodCount);
    for (std::size_t i = 0; i < kMethodCount; ++i) {
        EXPECT_EQ(method_of(samples[i]), kAllMethods[i]);
        EXPECT_EQ(method_from_name(method_name(kAllMethods[i])), kAllMethods[i]);
    }
    EXPECT_FALSE(method_from_name("Hello").has_value());
}

TEST(ProtocolRequest, EveryMethodRoundTripsWithNumberStringAndNullIds) {
    const std::vector<RequestId> ids
        = { std::int64_t { 42 }, std::int64_t { -7 }, std::string("req-\"1\"/\u00e9"), nullptr };
    for (const auto& params : sample_params()) {
        for (const auto& id : ids) {
            const Request request { id, params };
            const Message message = encode_request(request);
            ASSERT_EQ(message.size(), 1u);
            const auto decoded = decode_request(message);
            ASSERT_TRUE(decoded.ok())
                << method_name(request.method()) << ": " << decoded.error().error.reason;
            EXPECT_EQ(decoded.value(), request) << message[0];
        }
    }
}

TEST(ProtocolRequest, NotificationHasNoIdMember) {
    const Request request { std::nullopt, ScalpelParams { 1, { 0, 0, 0 }, { 0, 0, 0.01 } } };
    const Message message = encode_request(request);
    EXPECT_EQ(message[0].find("\"id\""), std::string::npos);
    const auto decoded = decode_request(message);
    ASSERT_TRUE(decoded.ok());
    EXPECT_TRUE(decoded->is_notification());
    EXPECT_EQ(decoded.value(), request);
}

TEST(ProtocolRequest, OptionalParamsAbsentRoundTrip) {
    const std::vector<Params> params = { HelloParams {},
        LoadSceneParams { std::nullopt, R"({"geometry":{"box":[0.1,0.1,0.05]}})" },
        ApplyForceParams { { 0, 0, 0 }, { 1, 0, 0 }, 0.01, std::nullopt },
        GrabParams { { 0, 0, 0 }, std::nullopt, std::nullopt } };
    for (const auto& p : params) {
        const Request request { std::int64_t { 1 }, p };
        const auto decoded = decode_request(encode_request(request));
        ASSERT_TRUE(decoded.ok()) << decoded.error().error.reason;
        EXPECT_EQ(decoded.value(), request);
    }
}

TEST(ProtocolRequest, StepTicksDefaultsToOneAndParamsMayBeOmitted) {
    const auto decoded = decode_request(Message { R"({"jsonrpc":"2.0","id":1,"method":"step"})" });
    ASSERT_TRUE(decoded.ok());
    EXPECT_EQ(std::get<StepParams>(decoded->params).ticks, 1u);
    // An integral float is an integer.
    const auto floaty = decode_request(
        Message { R"({"jsonrpc":"2.0","id":1,"method":"step","params":{"ticks":3.0}})" });
    ASSERT_TRUE(floaty.ok());
    EXPECT_EQ(std::get<StepParams>(floaty->params).ticks, 3u);
}

TEST(ProtocolRequest, CutTrianglesRoundTripThroughAFloat32Frame) {
    // Values exactly representable in float32, so the round trip is exact.
    CutParams cut;
    for (int t = 0; t < 5; ++t) {
        const double x = 0.125 * t;
        cut.triangles.push_back(
            Triangle3 { { { x, 0.0, 0.5 }, { x + 0.25, 0.0, 0.5 }, { x, 0.0, -0.5 } } });
    }
    const Request request { std::string("cut-1"), cut };
    const Message message = encode_request(request, EncodeOptions { .binary_arrays = true });
    ASSERT_EQ(message.size(), 2u);
    EXPECT_EQ(message[1].size(), 5u * 9u * 4u);
    EXPECT_NE(message[0].find(R"("$frame":1)"), std::string::npos) << message[0];
    const auto decoded = decode_request(message);
    ASSERT_TRUE(decoded.ok()) << decoded.error().error.reason;
    EXPECT_EQ(decoded.value(), request);
}

TEST(ProtocolRequest, InlineSceneIsCarriedAsCompactJsonText) {
    const auto decoded = decode_request(Message {
        R"({"jsonrpc":"2.0","id":"s","method":"load_scene","params":{"scene":{"b": [1, 2], "a": {"c": null}}}})" });
    ASSERT_TRUE(decoded.ok()) << decoded.error().error.reason;
    const auto& params = std::get<LoadSceneParams>(decoded->params);
    ASSERT_TRUE(params.scene_json.has_value());
    EXPECT_EQ(*params.scene_json, R"({"b":[1,2],"a":{"c":null}})"); // author order kept
    EXPECT_FALSE(params.name.has_value());
}

TEST(ProtocolRequest, IdToJsonTextIsDistinctPerId) {
    EXPECT_EQ(to_json_text(RequestId { std::int64_t { 5 } }), "5");
    EXPECT_EQ(to_json_text(RequestId { std::string("5") }), "\"5\"");
    EXPECT_EQ(to_json_text(RequestId { nullptr }), "null");
}

TEST(ProtocolRequest, IntegralFloatIdsAreIntegersAndFractionalOnesAreNot) {
    // docs/protocol.md: integer members accept integral floats (3.0).
    for (const char* text : { R"({"jsonrpc":"2.0","id":3.0,"method":"hello"})",
             R"({"jsonrpc":"2.0","id":3e0,"method":"hello"})" }) {
        const std::string_view frame(text);
        const auto r = decode_request(std::span<const std::string_view>(&frame, 1));
        ASSERT_TRUE(r.ok()) << text;
        EXPECT_EQ(r.value().id, RequestId { std::int64_t { 3 } }) << text;
    }
    for (const char* text : { R"({"jsonrpc":"2.0","id":3.5,"method":"hello"})",
             R"({"jsonrpc":"2.0","id":1e300,"method":"hello"})" }) {
        const std::string_view frame(text);
        const auto r = decode_request(std::span<const std::string_view>(&frame, 1));
        ASSERT_FALSE(r.ok()) << text;
        EXPECT_EQ(r.error().error.code, ErrorCode::InvalidRequest) << text;
        EXPECT_EQ(r.error().error.pointer, "/id") << text;
    }
}

TEST(ProtocolRequest, ANulByteAnywhereInTheJsonFrameIsAParseError) {
    // nlohmann's lexer stops at a NUL: without the check "{...}\0garbage" decoded as "{...}".
    const std::string text
        = std::string(R"({"jsonrpc":"2.0","id":1,"method":"reset"})") + '\0' + "garbage";
    const std::string_view frame(text);
    const auto r = decode_request(std::span<const std::string_view>(&frame, 1));
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().error.code, ErrorCode::ParseError);
    EXPECT_TRUE(r.error().reply_expected);
}

TEST(ProtocolRequest, ARejectedNotificationKeepsItsMethodAndIsNeverAnswered) {
    const std::string_view frames[] = { R"({"jsonrpc":"2.0","method":"hello"})", "unreferenced" };
    auto r = decode_request(std::span<const std::string_view>(frames));
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().error.code, ErrorCode::InvalidRequest);
    EXPECT_FALSE(r.error().reply_expected);
    EXPECT_EQ(r.error().method, "hello");
    const std::string_view unknown(R"({"jsonrpc":"2.0","method":"Cut"})");
    r = decode_request(std::span<const std::string_view>(&unknown, 1));
    ASSERT_FALSE(r.ok());
    EXPECT_FALSE(r.error().reply_expected);
    EXPECT_EQ(r.error().method, "Cut");
    // An envelope error cannot tell a notification from a request: answered with id null.
    const std::string_view bad(R"({"jsonrpc":"1.0","method":"hello"})");
    r = decode_request(std::span<const std::string_view>(&bad, 1));
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(r.error().reply_expected);
}

} // namespace
} // namespace polycut::protocol
