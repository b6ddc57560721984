// The JSON-RPC request id: a number (integer here), a string, or null.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <variant>

namespace polycut::protocol {

/// JSON-RPC id. Numbers must be integers in [-2^63, 2^63) (JSON-RPC says ids SHOULD NOT be
/// fractional; polycut rejects fractional ids with -32600). nullptr = JSON null.
using RequestId = std::variant<std::nullptr_t, std::int64_t, std::string>;

/// The id as compact JSON text: `null`, `42`, `"abc"` (quotes and escapes included). Distinct ids
/// give distinct strings, so this is a usable reply-cache key together with the client identity.
std::string to_json_text(const RequestId& id);

} // namespace polycut::protocol
