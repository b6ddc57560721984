// Wire limits (reported by `hello`) and the physical ranges every numeric param is checked
// against. The server enforces Limits; the decoder enforces both.
#pragma once

#include <cstdint>
#include <string_view>

namespace polycut::protocol {

/// Protocol name and version answered by `hello` ("polycut/1").
inline constexpr std::string_view kProtocolName = "polycut/1";

/// Per-connection limits. Defaults are the server's defaults; `hello` reports the values in use.
struct Limits {
    /// Largest frame accepted [bytes] (the server sets ZMQ_MAXMSGSIZE to this). 16 MiB.
    std::uint64_t max_frame_bytes = 16u << 20;
    /// Most frames in one message, the JSON frame included (envelope frames excluded).
    std::uint32_t max_frames_per_message = 8;
    /// Most sweep triangles in one `cut` request.
    std::uint32_t max_triangles_per_cut = 65536;
    /// Most sweep triangles the cuts of one tick (each cut call: a `cut`, a stroke's sweep)
    /// apply; the rest waits for the next ticks (`deferred`, the stream's `cut_deferred`). At
    /// least one triangle per call is cut, so every stroke advances. A count, not a time, so a
    /// replayed command log cuts the same (docs/reliability.md: tick figures per cutter).
    std::uint32_t cut_triangles_per_tick = 16;
    /// Most requests per second from one client before -32004 Busy [1/s].
    double max_message_rate = 2000.0;
    /// Largest `step.ticks`.
    std::uint32_t max_step_ticks = 10000;
    /// Largest tick rate accepted by `set_rate` [Hz].
    double max_rate_hz = 1000.0;
    /// Largest JSON frame (frame 0) [bytes]; -32005 without parsing it. Parsing is the costly
    /// part of a message (~80 us/KiB of nested arrays here), so this bounds one message's work
    /// to about one 60 Hz tick; bulk arrays go in binary frames (max_frame_bytes). 256 KiB.
    std::uint64_t max_json_bytes = 256u << 10;
    /// JSON bytes one client may have parsed per tick, on average: a byte bucket refilled at
    /// this many bytes per tick, holding at most max_json_bytes; a message the bucket cannot
    /// pay is -32004 Busy [bytes/tick]. 64 KiB.
    std::uint64_t json_bytes_per_tick = 64u << 10;
    /// Replies the server queues for one client before it drops them (counted in
    /// get_stats.replies_dropped): keep fewer requests than this in flight (ROUTER SNDHWM).
    std::uint32_t max_in_flight = 1000;
    /// Largest scene a load_scene may build, as estimated before building it [bytes]
    /// (-32001 above it); 0 = no budget. The server sets it from --scene-memory.
    std::uint64_t max_scene_bytes = 0;

    bool operator==(const Limits&) const = default;
};

/// Range checks on physical params (anything outside is -32602 Invalid params).
inline constexpr double kMaxCoordinate = 1.0e3; ///< |x|, |y|, |z| of any point [m]
inline constexpr double kMaxForce = 1.0e5; ///< each component of a force [N]
inline constexpr double kMaxRadius = 1.0e2; ///< force / grab radius [m]
inline constexpr double kMaxDuration = 1.0e6; ///< force duration [s]
inline constexpr double kMaxStiffness = 1.0e9; ///< grab spring stiffness [N/m]
/// Tool contact stiffness: contact pressure per penetration depth [N/m^3].
inline constexpr double kMaxContactStiffness = 1.0e13;
/// Tool Coulomb friction coefficient (dimensionless).
inline constexpr double kMaxFriction = 10.0;
/// Grab spring stiffness used when `grab.stiffness` is absent [N/m].
inline constexpr double kDefaultGrabStiffness = 200.0;
/// Smallest triangle quality (sweep.hpp) a sweep triangle may have.
inline constexpr double kMinTriangleQuality = 1.0e-6;

} // namespace polycut::protocol
