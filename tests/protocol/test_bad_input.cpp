// Every class of bad input yields the right JSON-RPC code and a JSON pointer to the bad field
// (issue 6 item 5), and nothing throws, whatever the bytes.
#include "polycut/protocol/request.hpp"

#include <cmath>
#include <cstring>
#include <gtest/gtest.h>
#include <limits>
#include <random>

namespace polycut::protocol {
namespace {

struct BadCase {
    std::string name;
    Message message;
    ErrorCode code;
    std::string pointer;
    bool reply_expected = true;
    RequestId id = std::int64_t { 1 };
};

std::string request(std::string_view method, std::string_view params) {
    return R"({"jsonrpc":"2.0","id":1,"method":")" + std::string(method) + R"(","params":)"
        + std::string(params) + "}";
}

Frame float_frame(std::vector<float> values) {
    return encode_array(std::span<const float>(values));
}

/// A valid [2,3,3] triangle set as floats.
std::vector<float> two_triangles() {
    return { 0, 0, 0.1f, 0.1f, 0, 0.1f, 0, 0, -0.1f, 0.1f, 0, 0.1f, 0.1f, 0, -0.1f, 0, 0, -0.1f };
}

const std::string kCutRef
    = request("cut", R"({"triangles":{"$frame":1,"dtype":"float32","shape":[2,3,3]}})");
const std::string kApply = R"("point":[0,0,0.05],"force":[0,0,-1],"radius":0.01)";

std::vector<BadCase> cases() {
    auto nan_values = two_triangles();
    nan_values[5] = std::numeric_limits<float>::quiet_NaN(); // triangle 0, corner 1, z
    auto inf_values = two_triangles();
    inf_values[9] = std::numeric_limits<float>::infinity(); // triangle 1, corner 0, x
    Limits limits;
    std::vector<BadCase> out = {
        { "malformed JSON", { R"({"jsonrpc":"2.0","id":1,"method":)" }, ErrorCode::ParseError, "",
            true, nullptr },
        { "invalid UTF-8", { request("hello", "{\"client\":\"\xff\xfe\"}") }, ErrorCode::ParseError,
            "", true, nullptr },
        { "overlong UTF-8", { request("hello", "{\"client\":\"\xc0\xaf\"}") },
            ErrorCode::ParseError, "", true, nullptr },
        { "number overflow", { request("set_rate", R"({"hz":1e999})") }, ErrorCode::ParseError, "",
            true, nullptr },
        { "deep nesting", { std::string(100, '[') + std::string(100, ']') }, ErrorCode::ParseError,
            "", true, nullptr },
        { "not an object", { "[1,2]" }, ErrorCode::InvalidRequest, "", true, nullptr },
        { "empty message", {}, ErrorCode::InvalidRequest, "", true, nullptr },
        { "wrong jsonrpc", { R"({"jsonrpc":"1.0","id":1,"method":"hello","params":{}})" },
            ErrorCode::InvalidRequest, "/jsonrpc" },
        { "jsonrpc missing", { R"({"id":1,"method":"hello"})" }, ErrorCode::InvalidRequest,
            "/jsonrpc" },
        { "method not a string", { R"({"jsonrpc":"2.0","id":1,"method":5})" },
            ErrorCode::InvalidRequest, "/method" },
        { "params not an object", { R"({"jsonrpc":"2.0","id":1,"method":"step","params":[3]})" },
            ErrorCode::InvalidRequest, "/params" },
        { "id boolean", { R"({"jsonrpc":"2.0","id":true,"method":"hello"})" },
            ErrorCode::InvalidRequest, "/id", true, nullptr },
        { "id fractional", { R"({"jsonrpc":"2.0","id":1.5,"method":"hello"})" },
            ErrorCode::InvalidRequest, "/id", true, nullptr },
        { "unknown envelope member", { R"({"jsonrpc":"2.0","id":1,"method":"hello","x":0})" },
            ErrorCode::InvalidRequest, "/x" },
        { "unknown method", { request("explode", "{}") }, ErrorCode::MethodNotFound, "/method" },
        { "unknown param key", { request("apply_force", "{" + kApply + R"(,"colour":"red"})") },
            ErrorCode::InvalidParams, "/params/colour" },
        { "missing param", { request("apply_force", R"({"point":[0,0,0],"force":[0,0,-1]})") },
            ErrorCode::InvalidParams, "/params/radius" },
        { "wrong type",
            { request("apply_force", R"({"point":[0,0,0],"force":[0,0,-1],"radius":"big"})") },
            ErrorCode::InvalidParams, "/params/radius" },
        { "wrong array size", { request("grab", R"({"point":[0,0]})") }, ErrorCode::InvalidParams,
            "/params/point" },
        { "wrong element type", { request("move_grab", R"({"id":1,"target":[0,"x",0]})") },
            ErrorCode::InvalidParams, "/params/target/1" },
        { "radius <= 0",
            { request("apply_force", R"({"point":[0,0,0],"force":[0,0,-1],"radius":0})") },
            ErrorCode::InvalidParams, "/params/radius" },
        { "negative duration", { request("apply_force", "{" + kApply + R"(,"duration":-1})") },
            ErrorCode::InvalidParams, "/params/duration" },
        { "rate zero", { request("set_rate", R"({"hz":0})") }, ErrorCode::InvalidParams,
            "/params/hz" },
        { "rate above 1000 Hz", { request("set_rate", R"({"hz":1000.5})") },
            ErrorCode::InvalidParams, "/params/hz" },
        { "step zero ticks", { request("step", R"({"ticks":0})") }, ErrorCode::InvalidParams,
            "/params/ticks" },
        { "step fractional ticks", { request("step", R"({"ticks":2.5})") },
            ErrorCode::InvalidParams, "/params/ticks" },
        { "force id zero", { request("remove_force", R"({"id":0})") }, ErrorCode::InvalidParams,
            "/params/id" },
        { "coordinate out of range", { request("grab", R"({"point":[0,0,1e9]})") },
            ErrorCode::InvalidParams, "/params/point/2" },
        { "scene name with ../", { request("load_scene", R"({"name":"../etc/passwd"})") },
            ErrorCode::InvalidParams, "/params/name" },
        { "scene name with slash", { request("load_scene", R"({"name":"a/b"})") },
            ErrorCode::InvalidParams, "/params/name" },
        { "scene name and scene", { request("load_scene", R"({"name":"a","scene":{}})") },
            ErrorCode::InvalidParams, "/params" },
        { "inline scene not an object", { request("load_scene", R"({"scene":"box"})") },
            ErrorCode::InvalidParams, "/params/scene" },
        { "unsupported protocol", { request("hello", R"({"protocol":"polycut/2"})") },
            ErrorCode::InvalidParams, "/params/protocol" },
        { "scalpel zero-length blade",
            { request("scalpel", R"({"stroke":1,"a":[0,0,0],"b":[0,0,0]})") },
            ErrorCode::InvalidParams, "/params/b" },
        { "cut with no triangles", { request("cut", R"({"triangles":[]})") },
            ErrorCode::InvalidParams, "/params/triangles" },
        { "cut triangle with 2 corners", { request("cut", R"({"triangles":[[[0,0,0],[1,0,0]]]})") },
            ErrorCode::InvalidParams, "/params/triangles/0" },
        { "NaN in float32 frame", { kCutRef, float_frame(nan_values) }, ErrorCode::InvalidParams,
            "/params/triangles/0/1/2" },
        { "Inf in float32 frame", { kCutRef, float_frame(inf_values) }, ErrorCode::InvalidParams,
            "/params/triangles/1/0/0" },
        { "wrong frame byte length", { kCutRef, Frame(2 * 9 * 4 - 1, '\0') },
            ErrorCode::InvalidParams, "/params/triangles" },
        { "wrong frame shape",
            { request("cut", R"({"triangles":{"$frame":1,"dtype":"float32","shape":[2,9]}})"),
                float_frame(two_triangles()) },
            ErrorCode::InvalidParams, "/params/triangles/shape" },
        { "wrong frame dtype",
            { request("cut", R"({"triangles":{"$frame":1,"dtype":"uint32","shape":[2,3,3]}})"),
                float_frame(two_triangles()) },
            ErrorCode::InvalidParams, "/params/triangles/dtype" },
        { "missing frame", { kCutRef }, ErrorCode::InvalidParams, "/params/triangles/$frame" },
        { "unreferenced frame", { request("pause", "{}"), Frame("x") }, ErrorCode::InvalidRequest,
            "" },
        { "too many frames", Message(limits.max_frames_per_message + 1, request("pause", "{}")),
            ErrorCode::PayloadTooLarge, "" },
        { "frame too large", { request("pause", "{}"), Frame(limits.max_frame_bytes + 1, 'x') },
            ErrorCode::PayloadTooLarge, "" },
        { "too many triangles",
            { request("cut",
                  R"({"triangles":{"$frame":1,"dtype":"float32","shape":[)"
                      + std::to_string(limits.max_triangles_per_cut + 1) + R"(,3,3]}})"),
                Frame(std::size_t { 36 } * (limits.max_triangles_per_cut + 1), '\0') },
            ErrorCode::PayloadTooLarge, "/params/triangles" },
        { "notification with bad params",
            { R"({"jsonrpc":"2.0","method":"scalpel","params":{"stroke":1,"a":[0,0,0]}})" },
            ErrorCode::InvalidParams, "/params/b", false, nullptr },
        { "notification with bad envelope",
            { R"({"jsonrpc":"2.1","method":"scalpel","params":{}})" }, ErrorCode::InvalidRequest,
            "/jsonrpc", true, nullptr },
    };
    return out;
}

TEST(ProtocolBadInput, EachClassGetsItsCodeAndPointer) {
    for (const auto& c : cases()) {
        SCOPED_TRACE(c.name);
        const auto decoded = decode_request(c.message);
        ASSERT_FALSE(decoded.ok());
        const RequestError& e = decoded.error();
        EXPECT_EQ(e.error.code, c.code) << e.error.reason;
        EXPECT_EQ(e.error.pointer, c.pointer) << e.error.reason;
        EXPECT_FALSE(e.error.reason.empty());
        EXPECT_EQ(e.error.message, default_message(c.code));
        EXPECT_EQ(e.reply_expected, c.reply_expected);
        EXPECT_EQ(e.id, c.id);
    }
}

TEST(ProtocolBadInput, LimitsAreConfigurable) {
    Limits tight;
    tight.max_triangles_per_cut = 1;
    tight.max_step_ticks = 5;
    const auto cut = decode_request(Message { kCutRef, float_frame(two_triangles()) }, tight);
    ASSERT_FALSE(cut.ok());
    EXPECT_EQ(cut.error().error.code, ErrorCode::PayloadTooLarge);
    const auto step = decode_request(Message { request("step", R"({"ticks":6})") }, tight);
    ASSERT_FALSE(step.ok());
    EXPECT_EQ(step.error().error.pointer, "/params/ticks");
    // The same frames are fine under the default limits.
    EXPECT_TRUE(decode_request(Message { kCutRef, float_frame(two_triangles()) }).ok());
}

TEST(ProtocolBadInput, PointerEscapesSpecialCharacters) {
    const auto decoded = decode_request(Message { request("pause", R"({"a/b~c":1})") });
    ASSERT_FALSE(decoded.ok());
    EXPECT_EQ(decoded.error().error.pointer, "/params/a~1b~0c");
}

// Random bytes and random single-byte mutations of valid frames: never a throw, always either a
// request or an error with a defined code.
TEST(ProtocolBadInput, MutatedFramesNeverThrow) {
    std::mt19937 rng(12345);
    const std::vector<std::string> seeds = { request("apply_force", "{" + kApply + "}"),
        request("cut", R"({"triangles":[[[0,0,0],[0.1,0,0],[0,0.1,0]]]})"),
        request("load_scene", R"({"scene":{"a":[1,2,{"b":"c"}]}})"), kCutRef };
    const std::vector<ErrorCode> known
        = { ErrorCode::ParseError, ErrorCode::InvalidRequest, ErrorCode::MethodNotFound,
              ErrorCode::InvalidParams, ErrorCode::CutRejected, ErrorCode::PayloadTooLarge };
    int accepted = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        std::string text = seeds[trial % seeds.size()];
        const int edits = 1 + static_cast<int>(rng() % 3);
        for (int e = 0; e < edits; ++e) {
            text[rng() % text.size()] = static_cast<char>(rng() % 256);
        }
        Message message { text };
        if (trial % 4 == 3) {
            auto values = two_triangles();
            message.push_back(float_frame(values));
            message.back()[rng() % message.back().size()] = static_cast<char>(rng() % 256);
        }
        Expected<Request, RequestError> decoded = RequestError {};
        EXPECT_NO_THROW(decoded = decode_request(message));
        if (decoded.ok()) {
            ++accepted;
        } else {
            EXPECT_NE(
                std::find(known.begin(), known.end(), decoded.error().error.code), known.end())
                << text << " -> " << static_cast<int>(decoded.error().error.code);
        }
    }
    EXPECT_GT(accepted, 0); // some mutations (inside numbers) stay valid
}

} // namespace
} // namespace polycut::protocol
