// JSON-RPC 2.0 replies: encode (server side), decode (client side).
#include "codec_internal.hpp"

namespace polycut::protocol {

using detail::json;

namespace {

constexpr ErrorCode kCode = ErrorCode::InvalidRequest;

json envelope(const RequestId& id) {
    json root = json::object();
    root["jsonrpc"] = "2.0";
    root["id"] = detail::request_id_to_json(id);
    return root;
}

json parse_reply_object(std::string_view frame) {
    json root = detail::parse_frame(frame);
    if (!root.is_object()) {
        detail::fail(kCode, "", "a reply must be a JSON object");
    }
    const auto version = root.find("jsonrpc");
    if (version == root.end() || *version != "2.0") {
        detail::fail(kCode, "/jsonrpc", "\"jsonrpc\" must be \"2.0\"");
    }
    if (!root.contains("id")) {
        detail::fail(kCode, "/id", "missing \"id\"");
    }
    return root;
}

RpcError read_error(const json& value) {
    detail::ObjectReader r(value, "/error", kCode);
    RpcError error;
    error.code = static_cast<ErrorCode>(detail::read_int(r.required("code"), r.at("code"),
        std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max(), kCode));
    error.message = detail::read_string(r.required("message"), r.at("message"), 4096, kCode);
    if (const json* data = r.optional("data"); data != nullptr && data->is_object()) {
        if (auto it = data->find("pointer"); it != data->end() && it->is_string()) {
            error.pointer = it->get<std::string>();
        }
        if (auto it = data->find("reason"); it != data->end() && it->is_string()) {
            error.reason = it->get<std::string>();
        }
    }
    return error;
}

Reply decode(std::span<const std::string_view> frames, Method method) {
    if (frames.empty()) {
        detail::fail(kCode, "", "empty message");
    }
    const json root = parse_reply_object(frames[0]);
    Reply reply;
    reply.id = detail::read_request_id(root.at("id"), "/id", kCode);
    const auto result = root.find("result");
    const auto error = root.find("error");
    if ((result == root.end()) == (error == root.end())) {
        detail::fail(kCode, "", "a reply holds exactly one of \"result\" or \"error\"");
    }
    detail::FrameSet binary(frames.subspan(1));
    if (error != root.end()) {
        reply.outcome = read_error(*error);
    } else {
        reply.outcome = detail::decode_result(method, *result, binary);
    }
    binary.check_all_used();
    return reply;
}

} // namespace

Message encode_result(const RequestId& id, const Result& result) {
    json root = envelope(id);
    Message binary;
    root["result"] = detail::encode_result_json(result, binary);
    Message message;
    message.reserve(1 + binary.size());
    message.push_back(detail::dump(root));
    for (auto& frame : binary) {
        message.push_back(std::move(frame));
    }
    return message;
}

Message encode_error(const RequestId& id, const RpcError& error) {
    json root = envelope(id);
    root["error"] = json { { "code", static_cast<int>(error.code) },
        { "message",
            error.message.empty() ? std::string(default_message(error.code)) : error.message },
        { "data", json { { "pointer", error.pointer }, { "reason", error.reason } } } };
    return Message { detail::dump(root) };
}

Expected<Reply, RpcError> decode_reply(std::span<const std::string_view> frames, Method method) {
    try {
        return decode(frames, method);
    } catch (const detail::Failure& failure) {
        return failure.error;
    } catch (const std::exception& e) {
        return make_error(ErrorCode::InternalError, "", std::string("decoder: ") + e.what());
    }
}

Expected<Reply, RpcError> decode_reply(const Message& message, Method method) {
    const auto views = frame_views(message);
    return decode_reply(std::span<const std::string_view>(views), method);
}

Expected<RequestId, RpcError> peek_reply_id(std::string_view json_frame) {
    try {
        const json root = parse_reply_object(json_frame);
        return detail::read_request_id(root.at("id"), "/id", kCode);
    } catch (const detail::Failure& failure) {
        return failure.error;
    } catch (const std::exception& e) {
        return make_error(ErrorCode::InternalError, "", std::string("decoder: ") + e.what());
    }
}

} // namespace polycut::protocol
