// JSON-RPC control client (see control_client.hpp).
#include "control_client.hpp"

#include "polycut/common/error.hpp"

namespace polycut::record {

protocol::Message receive_message(zmq::socket_t& socket) {
    protocol::Message frames;
    bool more = true;
    while (more) {
        zmq::message_t part;
        if (!socket.recv(part, zmq::recv_flags::none)) {
            break;
        }
        frames.emplace_back(part.data<char>(), part.size());
        more = part.more();
    }
    return frames;
}

void send_message(zmq::socket_t& socket, const protocol::Message& message) {
    for (std::size_t k = 0; k < message.size(); ++k) {
        socket.send(zmq::buffer(message[k]),
            k + 1 < message.size() ? zmq::send_flags::sndmore : zmq::send_flags::none);
    }
}

std::string describe(const protocol::RpcError& error) {
    std::string text = std::to_string(static_cast<int>(error.code)) + " " + error.message;
    if (!error.pointer.empty()) {
        text += " at " + error.pointer;
    }
    if (!error.reason.empty()) {
        text += ": " + error.reason;
    }
    return text;
}

ControlClient::ControlClient(zmq::context_t& context, const std::string& endpoint)
    : m_socket(context, zmq::socket_type::dealer) {
    m_socket.set(zmq::sockopt::linger, 0);
    m_socket.connect(endpoint);
}

std::int64_t ControlClient::send(const protocol::Params& params) {
    const std::int64_t id = ++m_next_id;
    protocol::Request request { protocol::RequestId { id }, params };
    send_message(m_socket, protocol::encode_request(request));
    m_pending[id] = protocol::method_of(params);
    return id;
}

std::optional<protocol::Reply> ControlClient::receive(std::chrono::milliseconds timeout) {
    zmq::pollitem_t item { m_socket.handle(), 0, ZMQ_POLLIN, 0 };
    if (zmq::poll(&item, 1, timeout) == 0) {
        return std::nullopt;
    }
    const protocol::Message message = receive_message(m_socket);
    if (message.empty()) {
        throw Error("control", "empty reply");
    }
    const auto id = protocol::peek_reply_id(message.front());
    if (!id || !std::holds_alternative<std::int64_t>(id.value())) {
        throw Error("control", "reply without a known id: " + message.front().substr(0, 200));
    }
    const auto it = m_pending.find(std::get<std::int64_t>(id.value()));
    if (it == m_pending.end()) {
        throw Error("control", "reply to an unknown id: " + message.front().substr(0, 200));
    }
    const protocol::Method method = it->second;
    m_pending.erase(it);
    auto reply = protocol::decode_reply(message, method);
    if (!reply) {
        throw Error("control", "malformed reply: " + describe(reply.error()));
    }
    return std::move(reply).value();
}

protocol::Result ControlClient::call(
    const protocol::Params& params, std::chrono::milliseconds timeout) {
    const std::int64_t id = send(params);
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    const std::string method(protocol::method_name(protocol::method_of(params)));
    while (true) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) {
            m_pending.erase(id);
            throw Error("control",
                "no reply to " + method + " within " + std::to_string(timeout.count())
                    + " ms (is polycut-server running?)");
        }
        auto reply = receive(left);
        if (!reply || reply->id != protocol::RequestId { id }) {
            continue;
        }
        if (!reply->ok()) {
            throw Error("control",
                method + " failed: " + describe(std::get<protocol::RpcError>(reply->outcome)));
        }
        return std::get<protocol::Result>(std::move(reply->outcome));
    }
}

} // namespace polycut::record
