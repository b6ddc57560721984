// The surface stream (PUB/SUB): `surface` frames after every tick, `event` messages, and the
// surface header shared with the get_surface snapshot (docs/protocol.md "The stream").
#pragma once

#include "polycut/protocol/error.hpp"
#include "polycut/protocol/expected.hpp"
#include "polycut/protocol/frames.hpp"
#include "polycut/protocol/request_id.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace polycut::protocol {

/// Topic frame of surface messages.
inline constexpr std::string_view kSurfaceTopic = "surface";
/// Topic frame of event messages.
inline constexpr std::string_view kEventTopic = "event";

/// Per-triangle tag values of the `tags` array (same values as mesh::FaceTag).
enum class SurfaceTag : std::uint8_t { Skin = 1, Cut = 2 };

/// What the tick's step did.
struct StepReport {
    double step_ms = 0.0; ///< wall time of the step [ms]
    std::uint32_t solver_iterations = 0; ///< Newton/PCG iterations (solver-defined)
    double residual = 0.0; ///< final relative residual (dimensionless)
    std::vector<std::string> warnings; ///< warnings counted during the step
    bool operator==(const StepReport&) const = default;
};

/// What the tissue does to a tool or an obstacle (penalty contact) in the state of a frame:
/// the force a haptic device renders.
struct ContactReport {
    std::string kind = "tool"; ///< "tool" or "obstacle"
    std::uint64_t id = 0; ///< the tool's id (tool_create), or the obstacle's index in the scene
    std::array<double, 3> force {}; ///< force of the tissue on the body [N]
    /// torque about the tool frame origin (an obstacle: its centre, point or axis midpoint)
    /// [N m]
    std::array<double, 3> torque {};
    std::uint32_t points = 0; ///< tissue samples inside the body
    double depth = 0.0; ///< deepest penetration [m]
    bool operator==(const ContactReport&) const = default;
};

/// Header of a surface frame and of the get_surface snapshot.
struct SurfaceHeader {
    std::uint64_t seq = 0; ///< stream sequence number, +1 per published frame
    std::int64_t tick = 0; ///< ticks completed since the scene was loaded or reset
    double sim_time = 0.0; ///< simulated time [s]
    std::uint64_t topology_version = 0; ///< +1 whenever triangles/tags change
    std::uint32_t vertex_count = 0; ///< V (rows of positions)
    std::uint32_t triangle_count = 0; ///< T of the current topology (sent or not)
    bool has_topology = false; ///< triangles and tags follow (always true in a snapshot)
    StepReport step; ///< report of the step that produced this frame
    std::vector<RequestId> applied; ///< ids of requests applied at this tick's boundary
    /// sweep triangles waiting for the next tick's cut (past this tick's cut budget)
    std::uint32_t cut_deferred = 0;
    /// every tool, then every obstacle of the scene (omitted on the wire when empty)
    std::vector<ContactReport> contacts;
    bool operator==(const SurfaceHeader&) const = default;
};

/// A surface with its arrays (a decoded stream frame, or a snapshot).
struct SurfaceFrame {
    SurfaceHeader header;
    std::vector<float> positions; ///< (#V x 3) row-major [m]
    std::vector<std::uint32_t> triangles; ///< (#T x 3) vertex indices, CCW seen from outside
    std::vector<std::uint8_t> tags; ///< (#T) SurfaceTag values; empty when !has_topology
    bool operator==(const SurfaceFrame&) const = default;
};

/// A get_surface snapshot: the header (has_topology true, seq = the stream frame it reflects)
/// plus all three arrays.
using SurfaceSnapshot = SurfaceFrame;

/// An `event` message.
struct Event {
    /// "topology", "warning", "scene", "rejected", "overrun" (docs/protocol.md "Events").
    std::string kind;
    std::int64_t tick = 0; ///< tick at which it happened
    std::uint64_t seq = 0; ///< stream seq of the surface frame it relates to (0 = none)
    std::string detail_json = "{}"; ///< kind-specific object, compact JSON text
    /// +1 per event published (from 1; 0 = not reported): a gap means the PUB socket dropped
    /// events for this subscriber.
    std::uint64_t event_seq = 0;
    bool operator==(const Event&) const = default;
};

/// A decoded stream message.
using StreamMessage = std::variant<SurfaceFrame, Event>;

/// Builds the multipart surface message: ["surface", header JSON, positions (float32 V x 3),
/// and when header.has_topology also triangles (uint32 T x 3) and tags (uint8 T)].
/// vertex_count is taken from positions (size / 3), and, when has_topology, triangle_count from
/// triangles (size / 3); positions must be finite (the server guards the step).
Message encode_surface(const SurfaceHeader& header, std::span<const float> positions,
    std::span<const std::uint32_t> triangles, std::span<const std::uint8_t> tags);

/// Builds an event message: ["event", event JSON]. detail_json must be a JSON object text
/// (invalid text is replaced by {}).
Message encode_event(const Event& event);

/// Decodes a stream message (topic frame first). Checks the header against its schema, the
/// frame sizes against the counts, finite positions, triangle indices < V and tag values.
Expected<StreamMessage, RpcError> decode_stream(std::span<const std::string_view> frames);
/// Convenience overload.
Expected<StreamMessage, RpcError> decode_stream(const Message& message);

} // namespace polycut::protocol
