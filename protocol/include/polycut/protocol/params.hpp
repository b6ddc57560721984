// Typed params of every control method. Units SI; points are world-space [m]. Validation rules
// (ranges, sizes) are listed per field and enforced by decode_request (request.hpp).
#pragma once

#include "polycut/protocol/methods.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace polycut::protocol {

/// A 3-vector on the wire: [x, y, z]. Every component finite.
using Vector3 = std::array<double, 3>;
/// A triangle: three corners [m].
using Triangle3 = std::array<Vector3, 3>;

/// `hello`: optional client identification.
struct HelloParams {
    std::optional<std::string> client; ///< free text, <= 256 bytes (for logs)
    std::optional<std::string> protocol; ///< protocol the client speaks; must be "polycut/1"
    bool operator==(const HelloParams&) const = default;
};

/// `load_scene`: exactly one of `name` or `scene`.
struct LoadSceneParams {
    /// A scene of the server's scene directory: [A-Za-z0-9_-]{1,64}, never a path.
    std::optional<std::string> name;
    /// An inline scene description (docs/scenes.md), as compact JSON text of an object.
    std::optional<std::string> scene_json;
    bool operator==(const LoadSceneParams&) const = default;
};

/// `reset`: back to the scene's initial state (uncut, at rest, tick 0).
struct ResetParams {
    bool operator==(const ResetParams&) const = default;
};
/// `pause`: stop ticking (stream frames stop).
struct PauseParams {
    bool operator==(const PauseParams&) const = default;
};
/// `resume`: tick again at the current rate.
struct ResumeParams {
    bool operator==(const ResumeParams&) const = default;
};

/// `step`: run `ticks` ticks while paused (-32006 while running).
struct StepParams {
    std::uint32_t ticks = 1; ///< in [1, Limits::max_step_ticks]; absent = 1
    bool operator==(const StepParams&) const = default;
};

/// `set_rate`: the tick rate.
struct SetRateParams {
    double hz = 60.0; ///< in (0, Limits::max_rate_hz] [Hz]
    bool operator==(const SetRateParams&) const = default;
};

/// `apply_force`: a force spread over the material within `radius` of `point`.
struct ApplyForceParams {
    Vector3 point {}; ///< world-space application point [m], |component| <= kMaxCoordinate
    Vector3 force {}; ///< total force [N], |component| <= kMaxForce
    double radius = 0.0; ///< in (0, kMaxRadius] [m]
    std::optional<double> duration; ///< in (0, kMaxDuration] [s]; absent = until remove_force
    bool operator==(const ApplyForceParams&) const = default;
};

/// `remove_force`.
struct RemoveForceParams {
    std::uint64_t id = 0; ///< id returned by apply_force, in [1, 2^53)
    bool operator==(const RemoveForceParams&) const = default;
};

/// `grab`: attach a spring to the material point nearest `point` (or the material within
/// `radius`), initially anchored at `point`.
struct GrabParams {
    Vector3 point {}; ///< world-space point [m]
    std::optional<double>
        stiffness; ///< in (0, kMaxStiffness] [N/m]; absent = kDefaultGrabStiffness
    std::optional<double> radius; ///< in (0, kMaxRadius] [m]; absent = nearest material point only
    bool operator==(const GrabParams&) const = default;
};

/// `move_grab`: move a grab's spring anchor.
struct MoveGrabParams {
    std::uint64_t id = 0; ///< id returned by grab, in [1, 2^53)
    Vector3 target {}; ///< new world-space anchor [m]
    bool operator==(const MoveGrabParams&) const = default;
};

/// `release`: remove a grab.
struct ReleaseParams {
    std::uint64_t id = 0; ///< id returned by grab, in [1, 2^53)
    bool operator==(const ReleaseParams&) const = default;
};

/// `cut`: world-space sweep triangles with finite coordinates (their geometry is checked by
/// core/cut's pipeline when the cut is applied: -32002 pointing at the triangle); 1 to
/// Limits::max_triangles_per_cut of them. On the wire either nested arrays (T x 3 x 3) or a
/// float32 frame of shape [T, 3, 3].
struct CutParams {
    std::vector<Triangle3> triangles;
    bool operator==(const CutParams&) const = default;
};

/// `scalpel`: one blade sample; consecutive samples of a stroke form sweep triangles.
struct ScalpelParams {
    std::uint64_t stroke = 0; ///< client-chosen stroke id, in [0, 2^53)
    Vector3 a {}; ///< blade endpoint (e.g. tip) [m]
    Vector3 b {}; ///< other blade endpoint [m]; |b - a| > 0
    bool operator==(const ScalpelParams&) const = default;
};

/// `end_stroke`: close a stroke (its pending sweep is applied).
struct EndStrokeParams {
    std::uint64_t stroke = 0; ///< in [0, 2^53)
    bool operator==(const EndStrokeParams&) const = default;
};

/// `get_surface`: a snapshot of the surface.
struct GetSurfaceParams {
    bool operator==(const GetSurfaceParams&) const = default;
};
/// `get_stats`.
struct GetStatsParams {
    bool operator==(const GetStatsParams&) const = default;
};
/// `shutdown`: stop the server after replying.
struct ShutdownParams {
    bool operator==(const ShutdownParams&) const = default;
};

/// A unit quaternion on the wire: [w, x, y, z] (normalized by the server; not all zero).
using Quaternion = std::array<double, 4>;

/// `tool_create`: a rigid tool the tissue cannot enter (penalty contact, docs/protocol.md
/// "Tools"), in its own frame placed at `position` / `orientation`.
struct ToolCreateParams {
    /// "sphere" (a ball of `radius` at the origin), "capsule" (a shaft of `length` along local
    /// z centred at the origin, `radius` around it) or "blade" (a box of edge lengths `size`)
    std::string shape = "sphere";
    std::optional<double> radius; ///< sphere, capsule: in (0, kMaxRadius] [m]
    std::optional<double> length; ///< capsule: in [0, kMaxRadius] [m]
    std::optional<Vector3> size; ///< blade: each in (0, kMaxRadius] [m]
    Vector3 position {}; ///< tool frame origin [m], |component| <= kMaxCoordinate
    std::optional<Quaternion> orientation; ///< absent = identity
    /// penalty stiffness in (0, kMaxContactStiffness] [N/m^3]; absent = the scene's
    std::optional<double> stiffness;
    std::optional<double> friction; ///< Coulomb coefficient in [0, kMaxFriction]; absent = scene's
    bool operator==(const ToolCreateParams&) const = default;
};

/// `tool_move`: the tool's new pose (sent at the input device's rate, usually as a
/// notification); applied at the next tick boundary, the last one before a tick wins.
struct ToolMoveParams {
    std::uint64_t id = 0; ///< id returned by tool_create, in [1, 2^53)
    Vector3 position {}; ///< [m]
    std::optional<Quaternion> orientation; ///< absent = unchanged
    bool operator==(const ToolMoveParams&) const = default;
};

/// `tool_remove`.
struct ToolRemoveParams {
    std::uint64_t id = 0; ///< id returned by tool_create, in [1, 2^53)
    bool operator==(const ToolRemoveParams&) const = default;
};

/// The params of any method; `index()` equals the Method enum value.
using Params = std::variant<HelloParams, LoadSceneParams, ResetParams, PauseParams, ResumeParams,
    StepParams, SetRateParams, ApplyForceParams, RemoveForceParams, GrabParams, MoveGrabParams,
    ReleaseParams, CutParams, ScalpelParams, EndStrokeParams, GetSurfaceParams, GetStatsParams,
    ShutdownParams, ToolCreateParams, ToolMoveParams, ToolRemoveParams>;

/// The method whose params these are.
inline Method method_of(const Params& params) {
    return static_cast<Method>(params.index());
}

} // namespace polycut::protocol
