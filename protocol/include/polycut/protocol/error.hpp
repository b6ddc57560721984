// JSON-RPC 2.0 error codes and the error object every failure on the wire is answered with.
// docs/protocol.md "Errors" documents each code; the schema is protocol/schema/error.json.
#pragma once

#include <string>
#include <string_view>

namespace polycut::protocol {

/// JSON-RPC error codes: the standard ones (-32768..-32000 reserved range) and polycut's
/// application codes (-32000 and below).
enum class ErrorCode : int {
    ParseError = -32700, ///< frame is not JSON, or not valid UTF-8
    InvalidRequest = -32600, ///< not a JSON-RPC 2.0 request object, or malformed frame set
    MethodNotFound = -32601, ///< unknown method name
    InvalidParams = -32602, ///< wrong/missing/unknown param, wrong type, size, range, non-finite
    InternalError = -32603, ///< server bug; the state is unchanged
    SimulationError = -32000, ///< the simulation failed to carry out the command (e.g. no scene)
    SceneError = -32001, ///< the scene could not be loaded (unknown name, invalid description)
    CutRejected = -32002, ///< degenerate sweep geometry, or the cut could not be applied
    NotFound = -32003, ///< unknown force, grab or stroke id
    Busy = -32004, ///< overloaded: rate limit exceeded or work queue full; retry later
    PayloadTooLarge = -32005, ///< frame too large, too many frames, too many triangles
    StateConflict = -32006, ///< command not valid in the current state (e.g. step while running)
};

/// The default `message` for a code (JSON-RPC `error.message`), e.g. "Invalid params".
std::string_view default_message(ErrorCode code);

/// True for the codes JSON-RPC 2.0 answers even for notifications (-32700, -32600): the id
/// could not be determined, so the reply carries `"id": null`.
bool is_envelope_error(ErrorCode code);

/// A JSON-RPC error object: {"code", "message", "data": {"pointer", "reason"}}.
struct RpcError {
    ErrorCode code = ErrorCode::InternalError;
    std::string message; ///< short text; default_message(code) when built by make_error
    std::string pointer; ///< RFC 6901 JSON pointer to the bad field in the request ("" = whole)
    std::string reason; ///< human-readable detail, e.g. "must be > 0, got -1"

    bool operator==(const RpcError&) const = default;
};

/// An RpcError with the default message for `code`.
RpcError make_error(ErrorCode code, std::string pointer, std::string reason);

/// Appends one reference token to a JSON pointer, escaping '~' and '/' (RFC 6901).
std::string pointer_append(std::string_view pointer, std::string_view token);
/// Appends an array index to a JSON pointer.
std::string pointer_append(std::string_view pointer, std::size_t index);

} // namespace polycut::protocol
