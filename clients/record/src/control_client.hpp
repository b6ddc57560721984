// A minimal JSON-RPC client of polycut-server's control channel (a DEALER socket), shared by
// polycut-record and polycut-bench (polycut-scalpel uses its multipart helpers): send requests
// with increasing integer ids, match replies by id, decode them with the protocol codec. One
// thread only (ZeroMQ sockets are not thread-safe).
#pragma once

#include "polycut/protocol/protocol.hpp"

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <zmq.hpp>

namespace polycut::record {

/// Receives every frame of one multipart message (blocking).
protocol::Message receive_message(zmq::socket_t& socket);
/// Sends a multipart message.
void send_message(zmq::socket_t& socket, const protocol::Message& message);

/// The control connection.
class ControlClient {
public:
    /// Connects a DEALER to `endpoint` (e.g. "tcp://127.0.0.1:5555").
    ControlClient(zmq::context_t& context, const std::string& endpoint);

    /// Sends a request with a fresh id and returns the id.
    std::int64_t send(const protocol::Params& params);
    /// Waits up to `timeout` for one reply (any id). nullopt on timeout. Throws polycut::Error
    /// for a reply that cannot be decoded or answers an unknown id.
    std::optional<protocol::Reply> receive(std::chrono::milliseconds timeout);
    /// Sends and waits for this request's reply (other replies are dropped). Throws
    /// polycut::Error on timeout or if the server answered an error.
    protocol::Result call(const protocol::Params& params,
        std::chrono::milliseconds timeout = std::chrono::milliseconds(10000));

    /// The socket, for zmq::poll.
    zmq::socket_t& socket() { return m_socket; }
    /// Requests sent and not yet answered.
    std::size_t outstanding() const { return m_pending.size(); }

private:
    zmq::socket_t m_socket;
    std::int64_t m_next_id = 0;
    std::map<std::int64_t, protocol::Method> m_pending;
};

/// Text of an RpcError: "code message at pointer: reason".
std::string describe(const protocol::RpcError& error);

} // namespace polycut::record
