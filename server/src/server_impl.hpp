// Private state of polycut::server::Server, shared by server.cpp (loop and schedule),
// server_control.cpp (requests) and server_stream.cpp (publishing). Single-threaded: only the
// loop thread touches it.
#pragma once

#include "polycut/protocol/protocol.hpp"
#include "server.hpp"
#include "server_command_log.hpp"
#include "server_curve.hpp"
#include "server_reply_cache.hpp"
#include "server_scene_build.hpp"
#include "server_session.hpp"

#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>
#include <zmq.hpp>

namespace polycut::server {

using Clock = std::chrono::steady_clock;

/// What the server keeps per control peer (routing identity).
struct ClientInfo {
    double last_seen_s = 0.0; ///< monotonic [s]
    double tokens = 0.0; ///< rate limit bucket [messages]
    double json_bytes = 0.0; ///< JSON parse budget bucket [bytes]
};

/// The first rejected notification of a client since the last flush, and how many followed.
struct PendingRejection {
    std::string detail_json; ///< the event detail without `count`
    std::uint64_t count = 0;
};

/// A `step` request waiting for its ticks.
struct PendingStep {
    protocol::Message envelope;
    std::optional<protocol::RequestId> id; ///< nullopt: a notification, no reply
    std::uint32_t remaining = 0;
};

/// A `load_scene` whose scene is being built on a worker thread (server_load.cpp).
struct PendingLoad {
    protocol::Message envelope;
    protocol::Request request; ///< recorded in the command log when the scene is installed
    std::string name; ///< the scene's wire name
    std::int64_t tick_requested = 0; ///< the old scene's tick when the build started
    std::chrono::steady_clock::time_point started;
    std::unique_ptr<SceneBuild> build;
};

struct Server::Impl {
    Impl(ServerConfig config, std::atomic<bool>& stop);

    // --- server.cpp: schedule and loop
    void run();
    /// One pass of the loop: a tick when due, then the control socket for the time left.
    void loop_once();
    void run_tick();
    double now_s() const;
    double period_ms() const { return 1000.0 / rate_hz; }
    void set_rate(double hz);
    void housekeeping();
    void log_line();

    // --- server_control.cpp: requests
    /// Waits up to `timeout_ms` for control traffic, then handles what is queued (bounded).
    void service_control(long timeout_ms);
    /// Receives one message (frame-count cap, rest drained); false when none is queued.
    bool receive(protocol::Message& frames, std::size_t& total_frames);
    void handle(protocol::Message frames, std::size_t total_frames);
    void dispatch(const protocol::Message& envelope, const protocol::Request& request);
    void reply(const protocol::Message& envelope, protocol::Message body);
    void reply_error(const protocol::Message& envelope, const protocol::RequestId& id,
        const protocol::RpcError& error);
    /// Counts a rejected notification; its `rejected` event is coalesced per client until
    /// flush_rejections() (docs/protocol.md "Events").
    void reject_notification(
        const std::string& identity, std::string_view method, const protocol::RpcError& error);
    /// Publishes the coalesced `rejected` events (at most kMaxRejectedEventsPerFlush).
    void flush_rejections();
    /// Answers a message the rate or JSON byte budget refuses, without parsing a large one.
    void refuse_busy(
        const protocol::Routed& routed, const std::string& identity, const std::string& reason);
    /// Publishes a `rejected` event per scalpel stroke whose sweep the session could not cut.
    void publish_sweep_rejections();
    ClientInfo& touch_client(const std::string& identity);
    protocol::HelloResult hello() const;
    protocol::RunState run_state() const;
    protocol::Stats stats() const;
    void finish_steps();

    // --- server_load.cpp: scenes built off the loop thread
    /// Starts building a `load_scene`'s scene on a worker thread (the old scene goes on); a
    /// load while another is being built is refused (-32006), a bad scene answered at once.
    void start_load(const protocol::Message& envelope, const protocol::Request& request);
    /// Installs the built scene and answers the load, or answers its error (the old scene
    /// stays); does nothing while the build runs. Called by the loop between ticks.
    void finish_load();
    /// After the scene changed (load or reset): the new scene's first frame, the `scene`
    /// event; the replaced scene (if any) freed and the memory back to the system, off the
    /// loop.
    void announce_scene(
        const std::string& reason, std::unique_ptr<sim::Simulation> replaced = nullptr);
    /// Answers `error` to a request, or counts and publishes it for a notification.
    void answer_error(const protocol::Message& envelope,
        const std::optional<protocol::RequestId>& id, protocol::Method method,
        const protocol::RpcError& error);

    // --- server_stream.cpp: publishing
    /// Publishes the current surface as the next stream frame and caches it for get_surface.
    void publish_surface(const sim::StepReport& report, bool force_topology);
    void publish_event(std::string kind, std::string detail_json, std::uint64_t seq);
    void send_stream(const protocol::Message& message);
    protocol::SurfaceSnapshot snapshot() const;

    ServerConfig config;
    std::atomic<bool>& stop;
    zmq::context_t context { 1 };
    zmq::socket_t control;
    zmq::socket_t stream;
    std::unique_ptr<ZapHandler> zap; ///< with --curve-keys: admits the authorized clients
    std::string control_endpoint;
    std::string stream_endpoint;

    Session session;
    std::optional<PendingLoad> pending_load; ///< the load_scene being built, if any
    SceneDisposal disposal; ///< frees replaced scenes off the loop
    std::unique_ptr<CommandLog> command_log;
    ReplyCache reply_cache;
    std::map<std::string, ClientInfo, std::less<>> clients;

    // Run state and schedule (absolute: deadline k = anchor + k * period).
    bool running = true;
    double rate_hz = 60.0;
    Clock::time_point start_time;
    Clock::time_point anchor;
    std::int64_t ticks_since_anchor = 0;
    Clock::time_point next_deadline;
    std::deque<PendingStep> pending_steps;
    bool shutting_down = false;

    // Stream state.
    std::uint64_t seq = 0; ///< last published seq (0: none yet)
    std::uint64_t published_topology = 0; ///< topology_version of the last published arrays
    bool topology_pending = true; ///< next frame carries triangles and tags
    protocol::SurfaceHeader last_header;
    std::vector<float> last_positions;
    std::vector<std::uint32_t> last_triangles;
    std::vector<std::uint8_t> last_tags;
    std::vector<protocol::RequestId> applied; ///< ids applied since the last frame
    std::optional<protocol::RequestId> last_cut_id; ///< for the topology event
    std::uint64_t stream_dropped = 0;
    std::map<std::string, PendingRejection, std::less<>> pending_rejections;
    std::uint64_t replies_dropped = 0;
    std::uint64_t events_published = 0; ///< the last event's event_seq
    std::uint64_t events_coalesced = 0;
    std::uint64_t events_suppressed = 0;
    std::uint64_t busy = 0;

    // Accounting.
    std::uint64_t requests = 0;
    std::uint64_t errors = 0;
    std::uint64_t ticks_over_budget = 0;
    std::uint64_t ticks_total = 0;
    double worst_tick_ms = 0.0;
    double command_ms_since_tick = 0.0; ///< command work since the last tick [ms]
    /// A tick's step: when [s], wall and CPU time of the step [ms].
    struct RecentStep {
        double time_s = 0.0, wall_ms = 0.0, cpu_ms = 0.0;
    };
    std::deque<RecentStep> recent_steps; ///< the last second
    double step_p50_ms = 0.0, step_p99_ms = 0.0;
    /// CPU time of the step on the loop thread [ms]: far below the wall time = a starved loop.
    double step_cpu_p50_ms = 0.0, step_cpu_p99_ms = 0.0;
    double last_log_s = 0.0;
    std::uint64_t ticks_at_last_log = 0;
    double last_overrun_event_s = -1e9;
    double last_housekeeping_s = 0.0;
};

} // namespace polycut::server
