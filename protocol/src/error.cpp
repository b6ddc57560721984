// Error codes, messages and JSON pointer building.
#include "polycut/protocol/error.hpp"

#include <string>

namespace polycut::protocol {

std::string_view default_message(ErrorCode code) {
    switch (code) {
    case ErrorCode::ParseError:
        return "Parse error";
    case ErrorCode::InvalidRequest:
        return "Invalid Request";
    case ErrorCode::MethodNotFound:
        return "Method not found";
    case ErrorCode::InvalidParams:
        return "Invalid params";
    case ErrorCode::InternalError:
        return "Internal error";
    case ErrorCode::SimulationError:
        return "Simulation error";
    case ErrorCode::SceneError:
        return "Scene error";
    case ErrorCode::CutRejected:
        return "Cut rejected";
    case ErrorCode::NotFound:
        return "Not found";
    case ErrorCode::Busy:
        return "Busy";
    case ErrorCode::PayloadTooLarge:
        return "Payload too large";
    case ErrorCode::StateConflict:
        return "State conflict";
    }
    return "Server error";
}

bool is_envelope_error(ErrorCode code) {
    return code == ErrorCode::ParseError || code == ErrorCode::InvalidRequest;
}

RpcError make_error(ErrorCode code, std::string pointer, std::string reason) {
    return RpcError { code, std::string(default_message(code)), std::move(pointer),
        std::move(reason) };
}

std::string pointer_append(std::string_view pointer, std::string_view token) {
    std::string out(pointer);
    out.reserve(out.size() + token.size() + 1);
    out += '/';
    for (char c : token) {
        if (c == '~') {
            out += "~0";
        } else if (c == '/') {
            out += "~1";
        } else {
            out += c;
        }
    }
    return out;
}

std::string pointer_append(std::string_view pointer, std::size_t index) {
    std::string out(pointer);
    out += '/';
    out += std::to_string(index);
    return out;
}

} // namespace polycut::protocol
