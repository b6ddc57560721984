// Latency benchmark loop (see latency_probe.hpp). One thread polls the control DEALER and the
// stream SUB together, so a reply and a frame are timestamped by the same clock as they arrive;
// extra subscribers run on their own threads and only count frames.
#include "latency_probe.hpp"

#include "control_client.hpp"
#include "polycut/common/error.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <thread>

namespace polycut::bench {

namespace {

using Clock = std::chrono::steady_clock;
using record::ControlClient;

double ms_between(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

struct Bounds {
    protocol::Vector3 lo { 0, 0, 0 };
    protocol::Vector3 hi { 0, 0, 0 };
    double extent() const {
        return std::max({ hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-3 });
    }
};

Bounds bounds_of(const std::vector<float>& positions) {
    Bounds b;
    for (int c = 0; c < 3; ++c) {
        b.lo[c] = 1e30;
        b.hi[c] = -1e30;
    }
    for (std::size_t i = 0; i + 2 < positions.size(); i += 3) {
        for (int c = 0; c < 3; ++c) {
            b.lo[c] = std::min(b.lo[c], double(positions[i + c]));
            b.hi[c] = std::max(b.hi[c], double(positions[i + c]));
        }
    }
    return b;
}

/// An extra subscriber that drains the stream on its own thread.
class ExtraSubscriber {
public:
    ExtraSubscriber(zmq::context_t& context, const std::string& endpoint)
        : m_thread([this, &context, endpoint] { run(context, endpoint); }) { }
    ~ExtraSubscriber() {
        m_stop = true;
        m_thread.join();
    }
    ExtraSubscriber(const ExtraSubscriber&) = delete;
    ExtraSubscriber& operator=(const ExtraSubscriber&) = delete;
    long frames() const { return m_frames.load(); }

private:
    void run(zmq::context_t& context, const std::string& endpoint) {
        zmq::socket_t sub(context, zmq::socket_type::sub);
        sub.set(zmq::sockopt::linger, 0);
        sub.connect(endpoint);
        sub.set(zmq::sockopt::subscribe, protocol::kSurfaceTopic);
        while (!m_stop.load()) {
            zmq::pollitem_t item { sub.handle(), 0, ZMQ_POLLIN, 0 };
            if (zmq::poll(&item, 1, std::chrono::milliseconds(50)) > 0) {
                const protocol::Message message = record::receive_message(sub);
                m_frames += message.size() > 1 ? 1 : 0;
            }
        }
    }
    std::atomic<bool> m_stop { false };
    std::atomic<long> m_frames { 0 };
    std::thread m_thread;
};

class Probe {
public:
    Probe(const ProbeOptions& options, const std::atomic<bool>& stop)
        : m_options(options)
        , m_stop(stop)
        , m_control(m_context, options.server)
        , m_sub(m_context, zmq::socket_type::sub) { }

    ProbeResult run() {
        const auto timeout = std::chrono::milliseconds(long(m_options.reply_timeout_s * 1000));
        protocol::HelloParams hello_params;
        hello_params.client = "polycut-bench";
        const auto hello = std::get<protocol::HelloResult>(m_control.call(hello_params, timeout));
        if (!m_options.scene.empty()) {
            protocol::LoadSceneParams load;
            load.name = m_options.scene;
            m_control.call(load, std::chrono::milliseconds(60000));
        }
        const std::string stream = m_options.stream.empty() ? hello.stream : m_options.stream;
        m_result.rate_hz = hello.rate_hz;
        m_sub.set(zmq::sockopt::linger, 0);
        m_sub.set(zmq::sockopt::rcvhwm, 100000);
        m_sub.connect(stream);
        m_sub.set(zmq::sockopt::subscribe, protocol::kSurfaceTopic);
        std::vector<std::unique_ptr<ExtraSubscriber>> extras;
        for (int k = 0; k < m_options.subscribers; ++k) {
            extras.push_back(std::make_unique<ExtraSubscriber>(m_context, stream));
        }

        // First frame: the tissue's bounds (where to push) and proof that the server ticks.
        const auto first_deadline = Clock::now() + std::chrono::seconds(5);
        while (!m_have_frame && Clock::now() < first_deadline && !m_stop.load()) {
            pump(std::chrono::milliseconds(50));
        }
        if (!m_have_frame) {
            throw Error("stream",
                "no surface frame from " + stream
                    + " within 5 s: is the server running (not paused) with a scene loaded?");
        }
        const auto start_stats
            = std::get<protocol::Stats>(m_control.call(protocol::GetStatsParams {}, timeout));

        const auto warm_end
            = Clock::now() + std::chrono::milliseconds(long(m_options.warmup_s * 1000));
        while (Clock::now() < warm_end && !m_stop.load()) {
            pump(std::chrono::milliseconds(10));
        }
        m_measuring = true;
        const auto t0 = Clock::now();
        const auto end = t0 + std::chrono::milliseconds(long(m_options.duration_s * 1000));
        const auto command_period = std::chrono::duration<double>(1.0 / m_options.command_rate_hz);
        const auto rtt_period = std::chrono::duration<double>(1.0 / m_options.rtt_rate_hz);
        auto next_command = t0;
        Clock::time_point next_rtt
            = t0 + std::chrono::duration_cast<Clock::duration>(rtt_period / 2);
        while (Clock::now() < end && !m_stop.load()) {
            const auto now = Clock::now();
            if (now >= next_command) {
                send_command();
                next_command += std::chrono::duration_cast<Clock::duration>(command_period);
            }
            if (now >= next_rtt) {
                m_rtt_sent[m_control.send(protocol::GetStatsParams {})] = Clock::now();
                next_rtt += std::chrono::duration_cast<Clock::duration>(rtt_period);
            }
            const auto wake = std::min({ next_command, next_rtt, end });
            pump(std::chrono::duration_cast<std::chrono::milliseconds>(wake - Clock::now()));
        }
        m_measuring = false;
        m_result.wall_s = ms_between(t0, Clock::now()) / 1000;
        // Let the last commands become visible (they count), then take the closing stats.
        const auto drain_end = Clock::now() + std::chrono::milliseconds(1000);
        while (
            (!m_command_sent.empty() || m_control.outstanding() > 0) && Clock::now() < drain_end) {
            pump(std::chrono::milliseconds(10));
        }
        const auto end_stats
            = std::get<protocol::Stats>(m_control.call(protocol::GetStatsParams {}, timeout));
        m_result.ticks = end_stats.tick - start_stats.tick;
        m_result.ticks_over_budget = end_stats.ticks_over_budget
            - std::min(end_stats.ticks_over_budget, start_stats.ticks_over_budget);
        m_result.worst_tick_ms = end_stats.worst_tick_ms;
        m_result.stats_step_ms_p50 = end_stats.step_ms_p50;
        m_result.stats_step_ms_p99 = end_stats.step_ms_p99;
        m_result.stream_dropped = end_stats.stream_dropped
            - std::min(end_stats.stream_dropped, start_stats.stream_dropped);
        m_result.vertex_count = end_stats.vertex_count;
        m_result.triangle_count = end_stats.triangle_count;
        m_result.scene = hello.scene.value_or(m_options.scene);
        if (!m_options.scene.empty()) {
            m_result.scene = m_options.scene;
        }
        for (const auto& extra : extras) {
            m_result.extra_frames.push_back(extra->frames());
        }
        return m_result;
    }

private:
    void send_command() {
        const double e = m_bounds.extent();
        const double cx = 0.5 * (m_bounds.lo[0] + m_bounds.hi[0]);
        const double cy = 0.5 * (m_bounds.lo[1] + m_bounds.hi[1]);
        const double top = m_bounds.hi[2];
        protocol::Params params;
        switch (m_options.command) {
        case ProbeCommand::ApplyForce: {
            protocol::ApplyForceParams p;
            p.point = { cx, cy, top };
            p.force = { 0, 0, -m_options.force_n };
            p.radius = 0.15 * e;
            p.duration = 0.1;
            params = p;
            break;
        }
        case ProbeCommand::Scalpel: {
            // Blade samples well above the tissue: the whole command path, no topology change.
            if (m_stroke_samples == 30) {
                protocol::EndStrokeParams end;
                end.stroke = m_stroke;
                m_control.send(end);
                ++m_stroke;
                m_stroke_samples = 0;
            }
            const double x = m_bounds.lo[0] + e * 0.02 * double(m_stroke_samples);
            protocol::ScalpelParams p;
            p.stroke = m_stroke;
            p.a = { x, cy - 0.1 * e, top + 0.5 * e };
            p.b = { x, cy + 0.1 * e, top + 0.5 * e };
            ++m_stroke_samples;
            params = p;
            break;
        }
        case ProbeCommand::Cut: {
            protocol::CutParams p;
            const double z = top + 0.5 * e;
            p.triangles.push_back(
                { protocol::Vector3 { cx, cy, z }, protocol::Vector3 { cx + 0.1 * e, cy, z },
                    protocol::Vector3 { cx, cy, z + 0.1 * e } });
            params = p;
            break;
        }
        }
        const std::int64_t id = m_control.send(params);
        m_command_sent[id] = Sent { Clock::now(), m_last_tick };
        m_command_acked[id] = m_command_sent[id].at;
        ++m_result.commands_sent;
    }

    void pump(std::chrono::milliseconds timeout) {
        zmq::pollitem_t items[] = { { m_control.socket().handle(), 0, ZMQ_POLLIN, 0 },
            { m_sub.handle(), 0, ZMQ_POLLIN, 0 } };
        zmq::poll(items, 2, std::max(timeout, std::chrono::milliseconds(0)));
        if ((items[1].revents & ZMQ_POLLIN) != 0) {
            for (int n = 0; n < 1000; ++n) {
                zmq::pollitem_t again { m_sub.handle(), 0, ZMQ_POLLIN, 0 };
                if (n > 0 && zmq::poll(&again, 1, std::chrono::milliseconds(0)) == 0) {
                    break;
                }
                on_stream(record::receive_message(m_sub));
            }
        }
        if ((items[0].revents & ZMQ_POLLIN) != 0) {
            while (auto reply = m_control.receive(std::chrono::milliseconds(0))) {
                on_reply(*reply);
            }
        }
    }

    void on_reply(const protocol::Reply& reply) {
        const auto now = Clock::now();
        if (!std::holds_alternative<std::int64_t>(reply.id)) {
            return;
        }
        const std::int64_t id = std::get<std::int64_t>(reply.id);
        if (auto it = m_rtt_sent.find(id); it != m_rtt_sent.end()) {
            if (m_measuring) {
                m_result.control_rtt_ms.push_back(ms_between(it->second, now));
            }
            m_rtt_sent.erase(it);
            return;
        }
        if (auto it = m_command_acked.find(id); it != m_command_acked.end()) {
            m_result.command_ack_ms.push_back(ms_between(it->second, now));
            m_command_acked.erase(it);
            if (!reply.ok()) {
                ++m_result.command_errors;
                m_command_sent.erase(id); // never visible
            }
        }
    }

    void on_stream(const protocol::Message& message) {
        const auto now = Clock::now();
        auto decoded = protocol::decode_stream(message);
        if (!decoded) {
            throw Error("stream", "malformed stream message: " + record::describe(decoded.error()));
        }
        const auto* frame = std::get_if<protocol::SurfaceFrame>(&decoded.value());
        if (frame == nullptr) {
            return;
        }
        const protocol::SurfaceHeader& h = frame->header;
        if (!m_have_frame) {
            m_bounds = bounds_of(frame->positions);
            m_have_frame = true;
        }
        if (m_measuring) {
            ++m_result.frames;
            m_result.step_ms.push_back(h.step.step_ms);
            if (m_last_frame_at) {
                m_result.frame_interval_ms.push_back(ms_between(*m_last_frame_at, now));
            }
            if (m_last_seq != 0 && h.seq != m_last_seq + 1) {
                ++m_result.gaps;
            }
        }
        m_last_frame_at = now;
        m_last_seq = h.seq;
        m_last_tick = h.tick;
        for (const protocol::RequestId& id : h.applied) {
            if (!std::holds_alternative<std::int64_t>(id)) {
                continue;
            }
            const auto it = m_command_sent.find(std::get<std::int64_t>(id));
            if (it == m_command_sent.end()) {
                continue;
            }
            m_result.visible_ms.push_back(ms_between(it->second.at, now));
            m_result.visible_ticks.push_back(double(h.tick - it->second.tick));
            ++m_result.commands_visible;
            m_command_sent.erase(it);
        }
    }

    struct Sent {
        Clock::time_point at;
        std::int64_t tick = 0; ///< last tick seen on the stream when sent
    };

    const ProbeOptions& m_options;
    const std::atomic<bool>& m_stop;
    zmq::context_t m_context { 1 };
    ControlClient m_control;
    zmq::socket_t m_sub;
    ProbeResult m_result;
    bool m_have_frame = false;
    bool m_measuring = false;
    Bounds m_bounds;
    std::optional<Clock::time_point> m_last_frame_at;
    std::uint64_t m_last_seq = 0;
    std::int64_t m_last_tick = 0;
    std::map<std::int64_t, Clock::time_point> m_rtt_sent;
    std::map<std::int64_t, Sent> m_command_sent; ///< not yet visible
    std::map<std::int64_t, Clock::time_point> m_command_acked; ///< not yet answered
    std::uint64_t m_stroke = 1;
    int m_stroke_samples = 0;
};

} // namespace

ProbeResult run_probe(const ProbeOptions& options, const std::atomic<bool>& stop) {
    if (!(options.duration_s > 0) || !(options.command_rate_hz > 0) || !(options.rtt_rate_hz > 0)) {
        throw InputError("--duration", "duration and rates must be > 0");
    }
    if (options.subscribers < 0 || options.subscribers > 64) {
        throw InputError("--subscribers", "must be in [0, 64]");
    }
    return Probe(options, stop).run();
}

} // namespace polycut::bench
