// JSON-RPC 2.0 requests: decode with precise errors (server side), encode (client side).
#include "codec_internal.hpp"

#include <algorithm>

namespace polycut::protocol {

namespace {

using detail::fail;
using detail::json;

constexpr std::array<std::string_view, 4> kEnvelopeMembers
    = { "jsonrpc", "id", "method", "params" };

struct DecodeState {
    RequestId id = nullptr;
    std::string method; ///< the method member, once read as a string
    bool notification = false; ///< known to be a notification (envelope read successfully)
};

void check_frame_limits(std::span<const std::string_view> frames, const Limits& limits) {
    if (frames.size() > limits.max_frames_per_message) {
        fail(ErrorCode::PayloadTooLarge, "",
            "message has " + std::to_string(frames.size()) + " frames; the limit is "
                + std::to_string(limits.max_frames_per_message));
    }
    for (std::size_t k = 1; k < frames.size(); ++k) {
        if (frames[k].size() > limits.max_frame_bytes) {
            fail(ErrorCode::PayloadTooLarge, "",
                "binary frame " + std::to_string(k) + " is " + std::to_string(frames[k].size())
                    + " bytes; the limit is " + std::to_string(limits.max_frame_bytes));
        }
    }
}

Request decode(std::span<const std::string_view> frames, const Limits& limits, DecodeState& state) {
    if (frames.empty()) {
        fail(ErrorCode::InvalidRequest, "", "empty message");
    }
    if (frames[0].size() > std::min(limits.max_frame_bytes, limits.max_json_bytes)) {
        fail(ErrorCode::PayloadTooLarge, "",
            "JSON frame is " + std::to_string(frames[0].size()) + " bytes; the limit is "
                + std::to_string(std::min(limits.max_frame_bytes, limits.max_json_bytes))
                + " (send bulk arrays as binary frames)");
    }
    const json root = detail::parse_frame(frames[0]);
    if (!root.is_object()) {
        fail(ErrorCode::InvalidRequest, "",
            "a request must be a JSON object, got " + std::string(detail::json_type_name(root))
                + (root.is_array() ? " (batches are not supported)" : ""));
    }
    // The id first, so that every later error can be answered to it.
    const json* id_value = detail::find_member(root, "id");
    if (id_value != nullptr) {
        state.id = detail::read_request_id(*id_value, "/id", ErrorCode::InvalidRequest);
    }
    const json* version = detail::find_member(root, "jsonrpc");
    if (version == nullptr || !version->is_string() || *version != "2.0") {
        fail(ErrorCode::InvalidRequest, "/jsonrpc", "\"jsonrpc\" must be the string \"2.0\"");
    }
    const json* method_value = detail::find_member(root, "method");
    if (method_value != nullptr && method_value->is_string()) {
        state.method = method_value->get<std::string>().substr(0, 64);
    }
    if (method_value == nullptr) {
        fail(ErrorCode::InvalidRequest, "/method", "missing \"method\"");
    }
    if (!method_value->is_string()) {
        fail(ErrorCode::InvalidRequest, "/method",
            "\"method\" must be a string, got "
                + std::string(detail::json_type_name(*method_value)));
    }
    for (const auto& [key, value] : root.items()) {
        if (std::find(kEnvelopeMembers.begin(), kEnvelopeMembers.end(), key)
            == kEnvelopeMembers.end()) {
            fail(ErrorCode::InvalidRequest, pointer_append("", key),
                "unknown member \"" + key + "\" in the request object");
        }
    }
    const json* params_value = detail::find_member(root, "params");
    if (params_value != nullptr && !params_value->is_object()) {
        fail(ErrorCode::InvalidRequest, "/params",
            "\"params\" must be an object (by-name params), got "
                + std::string(detail::json_type_name(*params_value)));
    }
    state.notification = id_value == nullptr;
    check_frame_limits(frames, limits);

    const std::string name = method_value->get<std::string>();
    const auto method = method_from_name(name);
    if (!method) {
        fail(ErrorCode::MethodNotFound, "/method", "unknown method \"" + name + "\"");
    }
    detail::FrameSet binary(frames.subspan(1));
    Request request;
    if (!state.notification) {
        request.id = state.id;
    }
    request.params = detail::decode_params(*method, params_value, binary, limits);
    binary.check_all_used();
    return request;
}

} // namespace

Expected<Request, RequestError> decode_request(
    std::span<const std::string_view> frames, const Limits& limits) {
    DecodeState state;
    try {
        return decode(frames, limits, state);
    } catch (const detail::Failure& failure) {
        // A notification is known once its envelope was read: every later error (method,
        // params, frame limits, an unreferenced frame) goes unanswered (JSON-RPC 2.0 sec. 4.1).
        const bool silent = state.notification;
        return RequestError { state.id, !silent, failure.error, state.method };
    } catch (const std::exception& e) {
        // Defensive: nothing above should throw anything else; never let it reach the wire.
        return RequestError { state.id, !state.notification,
            make_error(ErrorCode::InternalError, "", std::string("decoder: ") + e.what()),
            state.method };
    }
}

Expected<Request, RequestError> decode_request(const Message& body, const Limits& limits) {
    const auto views = frame_views(body);
    return decode_request(std::span<const std::string_view>(views), limits);
}

Message encode_request(const Request& request, const EncodeOptions& options) {
    Message binary;
    json root = json::object();
    root["jsonrpc"] = "2.0";
    if (request.id) {
        root["id"] = detail::request_id_to_json(*request.id);
    }
    root["method"] = std::string(method_name(request.method()));
    root["params"] = detail::encode_params(request.params, options, binary);
    Message message;
    message.reserve(1 + binary.size());
    message.push_back(detail::dump(root));
    for (auto& frame : binary) {
        message.push_back(std::move(frame));
    }
    return message;
}

} // namespace polycut::protocol
