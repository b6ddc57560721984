// The method names of the control channel (part of the contract, issue 6 item 2).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace polycut::protocol {

/// Every control method. The order matches the alternatives of `Params` (params.hpp).
enum class Method : std::uint8_t {
    Hello,
    LoadScene,
    Reset,
    Pause,
    Resume,
    Step,
    SetRate,
    ApplyForce,
    RemoveForce,
    Grab,
    MoveGrab,
    Release,
    Cut,
    Scalpel,
    EndStroke,
    GetSurface,
    GetStats,
    Shutdown,
    ToolCreate,
    ToolMove,
    ToolRemove,
};

/// Number of methods.
inline constexpr std::size_t kMethodCount = 21;

/// All methods in enum order.
inline constexpr std::array<Method, kMethodCount> kAllMethods = { Method::Hello, Method::LoadScene,
    Method::Reset, Method::Pause, Method::Resume, Method::Step, Method::SetRate, Method::ApplyForce,
    Method::RemoveForce, Method::Grab, Method::MoveGrab, Method::Release, Method::Cut,
    Method::Scalpel, Method::EndStroke, Method::GetSurface, Method::GetStats, Method::Shutdown,
    Method::ToolCreate, Method::ToolMove, Method::ToolRemove };

/// Wire name, e.g. Method::ApplyForce -> "apply_force".
std::string_view method_name(Method method);
/// Inverse of method_name (exact, case-sensitive); nullopt for an unknown name.
std::optional<Method> method_from_name(std::string_view name);

} // namespace polycut::protocol
