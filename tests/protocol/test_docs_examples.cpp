// The examples of docs/protocol.md agree with the C++ codec: every annotated request decodes to
// its method, every reply decodes, every `bad-request` example gets the documented code and
// pointer. (check_docs_examples.py validates the same examples against the JSON Schemas.)
#include "polycut/protocol/reply.hpp"
#include "polycut/protocol/request.hpp"
#include "polycut/protocol/stream.hpp"

#include <fstream>
#include <gtest/gtest.h>
#include <regex>
#include <sstream>

namespace polycut::protocol {
namespace {

struct Example {
    int line = 0;
    std::string kind; ///< "schema" or "bad-request"
    std::string argument;
    std::string text;
};

std::vector<Example> read_examples() {
    std::ifstream in(std::string(POLYCUT_SOURCE_DIR) + "/docs/protocol.md");
    EXPECT_TRUE(in.good());
    const std::regex annotation(R"(<!--\s*(schema|bad-request):\s*(.*?)\s*-->)");
    std::vector<Example> out;
    std::optional<Example> pending;
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        std::smatch match;
        if (std::regex_search(line, match, annotation)) {
            pending = Example { number, match[1], match[2], "" };
        } else if (line.rfind("```json", 0) == 0) {
            std::string text;
            while (std::getline(in, line) && line.rfind("```", 0) != 0) {
                ++number;
                text += line + "\n";
            }
            ++number;
            if (pending) {
                pending->text = text;
                out.push_back(*pending);
            }
            pending.reset();
        }
    }
    return out;
}

/// Synthesizes the binary frames an example references: float32 frames repeat a valid
/// triangle, uint32 frames are zeros (vertex 0), uint8 frames are 1 (skin).
Message with_frames(const std::string& json_text) {
    Message message { json_text };
    const std::regex ref(
        R"re("\$frame":\s*(\d+),\s*"dtype":\s*"(\w+)",\s*"shape":\s*\[([0-9,\s]+)\])re");
    std::map<int, Frame> frames;
    for (auto it = std::sregex_iterator(json_text.begin(), json_text.end(), ref);
         it != std::sregex_iterator(); ++it) {
        const int k = std::stoi((*it)[1]);
        std::size_t count = 1;
        std::stringstream dims((*it)[3].str());
        std::string dim;
        while (std::getline(dims, dim, ',')) {
            count *= std::stoul(dim);
        }
        const std::string dtype = (*it)[2];
        if (dtype == "float32") {
            const float pattern[9] = { 0, 0, 0, 0.01f, 0, 0, 0, 0.01f, 0 };
            std::vector<float> values(count);
            for (std::size_t i = 0; i < count; ++i) {
                values[i] = pattern[i % 9];
            }
            frames[k] = encode_array(std::span<const float>(values));
        } else if (dtype == "uint32") {
            frames[k] = encode_array(
                std::span<const std::uint32_t>(std::vector<std::uint32_t>(count, 0)));
        } else {
            frames[k]
                = encode_array(std::span<const std::uint8_t>(std::vector<std::uint8_t>(count, 1)));
        }
    }
    for (auto& [k, frame] : frames) {
        EXPECT_EQ(static_cast<std::size_t>(k), message.size()) << json_text;
        message.push_back(frame);
    }
    return message;
}

TEST(ProtocolDocs, ExamplesAgreeWithTheCodec) {
    const auto examples = read_examples();
    ASSERT_GE(examples.size(), 2 * kMethodCount);
    int checked = 0;
    for (const auto& ex : examples) {
        SCOPED_TRACE("docs/protocol.md:" + std::to_string(ex.line) + " [" + ex.argument + "]");
        if (ex.kind == "bad-request") {
            std::stringstream expect(ex.argument);
            int code = 0;
            std::string pointer;
            expect >> code >> pointer;
            const auto decoded = decode_request(Message { ex.text });
            ASSERT_FALSE(decoded.ok());
            EXPECT_EQ(static_cast<int>(decoded.error().error.code), code)
                << decoded.error().error.reason;
            EXPECT_EQ(decoded.error().error.pointer, pointer);
            ++checked;
            continue;
        }
        const auto dot = ex.argument.find('.');
        const std::string head = ex.argument.substr(0, dot);
        const std::string part = dot == std::string::npos ? "" : ex.argument.substr(dot + 1);
        if (part == "request") {
            const auto decoded = decode_request(with_frames(ex.text));
            ASSERT_TRUE(decoded.ok())
                << decoded.error().error.pointer << ": " << decoded.error().error.reason;
            EXPECT_EQ(method_name(decoded->method()), head);
            ++checked;
        } else if (part == "reply") {
            const auto method = head == "error" ? Method::Hello : method_from_name(head).value();
            const auto decoded = decode_reply(with_frames(ex.text), method);
            ASSERT_TRUE(decoded.ok()) << decoded.error().pointer << ": " << decoded.error().reason;
            EXPECT_EQ(decoded->ok(), head != "error");
            ++checked;
        } else if (ex.argument == "surface" || ex.argument == "event") {
            Message message = with_frames(ex.text);
            message.insert(message.begin(), Frame(ex.argument));
            const auto decoded = decode_stream(message);
            ASSERT_TRUE(decoded.ok()) << decoded.error().pointer << ": " << decoded.error().reason;
            EXPECT_EQ(decoded->index(), ex.argument == "surface" ? 0u : 1u);
            ++checked;
        }
    }
    EXPECT_EQ(checked, static_cast<int>(examples.size()));
}

} // namespace
} // namespace polycut::protocol
