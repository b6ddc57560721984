// Control replies: encode (server side) and decode (client side).
#pragma once

#include "polycut/protocol/error.hpp"
#include "polycut/protocol/expected.hpp"
#include "polycut/protocol/frames.hpp"
#include "polycut/protocol/methods.hpp"
#include "polycut/protocol/request_id.hpp"
#include "polycut/protocol/results.hpp"

#include <span>
#include <variant>

namespace polycut::protocol {

/// A decoded reply.
struct Reply {
    RequestId id = nullptr;
    std::variant<Result, RpcError> outcome; ///< the result, or the error the server answered

    /// True when the server answered a result.
    bool ok() const { return outcome.index() == 0; }
    bool operator==(const Reply&) const = default;
};

/// Encodes a success reply. A SurfaceSnapshot result travels as [JSON, positions, triangles,
/// tags] (its vertex/triangle counts are taken from the arrays and has_topology is forced true);
/// every other result as [JSON]. The caller prepends the routing envelope.
Message encode_result(const RequestId& id, const Result& result);

/// Encodes an error reply: {"jsonrpc":"2.0","id":..,"error":{"code","message","data":{"pointer",
/// "reason"}}}.
Message encode_error(const RequestId& id, const RpcError& error);

/// Decodes a reply to a request of `method` (the client knows which method an id was for).
/// Fails (with a -32700/-32600/-32602 RpcError describing the violation) only if the reply
/// itself is malformed; a server-side error is a successful decode with `outcome` = RpcError.
Expected<Reply, RpcError> decode_reply(std::span<const std::string_view> frames, Method method);
/// Convenience overload.
Expected<Reply, RpcError> decode_reply(const Message& message, Method method);

/// Reads only the id of a reply (to look up which method it answers).
Expected<RequestId, RpcError> peek_reply_id(std::string_view json_frame);

} // namespace polycut::protocol
