// Control requests: decode (server side, never throws, every error points at the bad field) and
// encode (client side).
#pragma once

#include "polycut/protocol/error.hpp"
#include "polycut/protocol/expected.hpp"
#include "polycut/protocol/frames.hpp"
#include "polycut/protocol/limits.hpp"
#include "polycut/protocol/params.hpp"
#include "polycut/protocol/request_id.hpp"

#include <optional>
#include <span>
#include <string_view>

namespace polycut::protocol {

/// A valid request.
struct Request {
    std::optional<RequestId> id; ///< nullopt = notification (no "id" member): no reply is sent
    Params params;

    /// The method (from the params alternative).
    Method method() const { return method_of(params); }
    /// True when no reply is expected.
    bool is_notification() const { return !id.has_value(); }
    bool operator==(const Request&) const = default;
};

/// Why a request was rejected, and whether to answer.
struct RequestError {
    RequestId id = nullptr; ///< the request's id when it could be read, else null
    /// False for a well-formed notification with bad method/params (JSON-RPC 2.0 sec. 4.1:
    /// notifications are never answered); the server should count it and may publish a
    /// `rejected` event. True otherwise (parse errors and invalid requests get "id": null).
    bool reply_expected = true;
    RpcError error;
};

/// Decodes a control message body (JSON frame, then binary frames; no routing envelope).
/// Checks, in order: frame count and sizes (-32005), UTF-8 and JSON syntax (-32700), the
/// JSON-RPC envelope (-32600), the method (-32601), the params (-32602; -32005 for too many cut
/// triangles), and that every binary frame is used.
Expected<Request, RequestError> decode_request(
    std::span<const std::string_view> frames, const Limits& limits = {});
/// Convenience overload.
Expected<Request, RequestError> decode_request(const Message& body, const Limits& limits = {});

/// How to encode a request.
struct EncodeOptions {
    /// Send bulk arrays (cut.triangles) as a float32 binary frame instead of nested JSON arrays.
    /// float32 rounds coordinates to ~1e-7 relative.
    bool binary_arrays = false;
};

/// Encodes a request: [JSON frame] or [JSON frame, binary frames...]. Optional params that are
/// absent are omitted; step.ticks is always written.
Message encode_request(const Request& request, const EncodeOptions& options = {});

} // namespace polycut::protocol
