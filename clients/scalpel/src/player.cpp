// Script player (see player.hpp).
#include "player.hpp"

#include "control_client.hpp"
#include "polycut/protocol/protocol.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>
#include <unistd.h>
#include <zmq.hpp>

namespace polycut::scalpel {

namespace {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double percentile(std::vector<double> v, double q) {
    if (v.empty()) {
        return 0.0;
    }
    std::sort(v.begin(), v.end());
    const double pos = q / 100.0 * double(v.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(pos));
    const std::size_t hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (pos - double(lo)) * (v[hi] - v[lo]);
}

double round3(double x) {
    return std::round(x * 1000.0) / 1000.0;
}

/// The connection and everything measured on it.
class Session {
public:
    explicit Session(const PlayOptions& options)
        : m_options(options)
        , m_control(m_context, zmq::socket_type::dealer)
        , m_stream(m_context, zmq::socket_type::sub) {
        m_control.set(zmq::sockopt::linger, 0);
        m_control.set(zmq::sockopt::routing_id, "scalpel-" + std::to_string(::getpid()));
        m_control.connect(options.server);
        m_stream.set(zmq::sockopt::linger, 0);
        m_stream.set(zmq::sockopt::rcvhwm, 1000);
    }

    /// Sends a request; returns its id.
    std::int64_t send(const protocol::Params& params) {
        const std::int64_t id = ++m_next_id;
        protocol::Request request { protocol::RequestId { id }, params };
        record::send_message(m_control, protocol::encode_request(request));
        m_pending[id] = Pending { protocol::method_of(params), Clock::now() };
        ++m_sent;
        return id;
    }

    /// Waits for the reply to `id`, reading everything else meanwhile.
    std::optional<protocol::Reply> wait_for(std::int64_t id) {
        const auto deadline
            = Clock::now() + std::chrono::duration<double>(m_options.reply_timeout_s);
        while (true) {
            if (auto it = m_done.find(id); it != m_done.end()) {
                protocol::Reply r = it->second;
                m_done.erase(it);
                return r;
            }
            if (Clock::now() >= deadline) {
                return std::nullopt;
            }
            pump(std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()));
        }
    }

    /// Reads replies and stream frames for up to `timeout` (returns early on traffic).
    void pump(std::chrono::milliseconds timeout) {
        zmq::pollitem_t items[]
            = { { m_control.handle(), 0, ZMQ_POLLIN, 0 }, { m_stream.handle(), 0, ZMQ_POLLIN, 0 } };
        zmq::poll(items, m_subscribed ? 2 : 1, std::max(timeout, std::chrono::milliseconds(0)));
        if ((items[0].revents & ZMQ_POLLIN) != 0) {
            while (read_reply()) { }
        }
        if (m_subscribed && (items[1].revents & ZMQ_POLLIN) != 0) {
            for (int n = 0; n < 1000 && read_stream(); ++n) { }
        }
    }

    void subscribe(const std::string& endpoint) {
        m_stream.connect(endpoint);
        m_stream.set(zmq::sockopt::subscribe, protocol::kSurfaceTopic);
        m_subscribed = true;
    }

    std::size_t outstanding() const { return m_pending.size(); }

    json summary(const Script& script, double duration_s, const json& server_stats) const {
        json errors = json::array();
        for (const auto& e : m_error_samples) {
            errors.push_back(e);
        }
        json out = { { "script", script.name }, { "commands_sent", m_sent },
            { "replies", m_replies }, { "errors", m_errors }, { "error_samples", errors },
            { "unanswered", m_pending.size() },
            { "ack_latency_ms",
                { { "count", m_latencies.size() }, { "p50", round3(percentile(m_latencies, 50)) },
                    { "p99", round3(percentile(m_latencies, 99)) },
                    { "max", round3(percentile(m_latencies, 100)) } } },
            { "topology_versions_seen",
                std::vector<std::uint64_t>(
                    m_topology_versions.begin(), m_topology_versions.end()) },
            { "sweep_triangles", m_sweep_triangles },
            { "ticks",
                { { "first", m_first_tick }, { "last", m_last_tick },
                    { "frames_received", m_frames }, { "seq_gaps", m_seq_gaps } } },
            { "duration_s", round3(duration_s) } };
        if (!server_stats.is_null()) {
            out["server"] = server_stats;
        }
        return out;
    }

    int errors() const { return static_cast<int>(m_errors + m_pending.size()); }

private:
    struct Pending {
        protocol::Method method;
        Clock::time_point sent;
    };

    bool read_reply() {
        zmq::message_t first;
        if (!m_control.recv(first, zmq::recv_flags::dontwait)) {
            return false;
        }
        protocol::Message frames;
        frames.emplace_back(first.data<char>(), first.size());
        if (first.more()) {
            for (auto& f : record::receive_message(m_control)) {
                frames.push_back(std::move(f));
            }
        }
        const auto now = Clock::now();
        if (frames.empty()) {
            return true;
        }
        const auto id = protocol::peek_reply_id(frames.front());
        if (!id || !std::holds_alternative<std::int64_t>(id.value())) {
            ++m_errors;
            return true;
        }
        const std::int64_t key = std::get<std::int64_t>(id.value());
        auto it = m_pending.find(key);
        if (it == m_pending.end()) {
            return true; // a late duplicate
        }
        const protocol::Method method = it->second.method;
        m_latencies.push_back(
            std::chrono::duration<double, std::milli>(now - it->second.sent).count());
        m_pending.erase(it);
        ++m_replies;
        auto reply = protocol::decode_reply(frames, method);
        if (!reply) {
            ++m_errors;
            note_error(method, reply.error());
            return true;
        }
        if (const auto* error = std::get_if<protocol::RpcError>(&reply->outcome)) {
            ++m_errors;
            note_error(method, *error);
        } else {
            note_result(std::get<protocol::Result>(reply->outcome));
        }
        m_done.emplace(key, std::move(reply.value()));
        // Keep only replies someone may still wait for.
        while (m_done.size() > 64) {
            m_done.erase(m_done.begin());
        }
        return true;
    }

    void note_error(protocol::Method method, const protocol::RpcError& e) {
        if (m_error_samples.size() < 8) {
            m_error_samples.push_back({ { "method", std::string(protocol::method_name(method)) },
                { "code", static_cast<int>(e.code) }, { "message", e.message },
                { "pointer", e.pointer }, { "reason", e.reason } });
        }
    }

    void note_result(const protocol::Result& result) {
        if (const auto* c = std::get_if<protocol::CutResult>(&result)) {
            m_topology_versions.insert(c->topology_version);
            see_tick(c->tick);
        } else if (const auto* s = std::get_if<protocol::ScalpelResult>(&result)) {
            m_sweep_triangles += s->triangles;
            see_tick(s->tick);
        } else if (const auto* scene = std::get_if<protocol::SceneResult>(&result)) {
            m_topology_versions.insert(scene->topology_version);
        }
    }

    void see_tick(std::int64_t tick) {
        if (m_first_tick < 0) {
            m_first_tick = tick;
        }
        m_last_tick = std::max(m_last_tick, tick);
    }

    bool read_stream() {
        zmq::message_t topic;
        if (!m_stream.recv(topic, zmq::recv_flags::dontwait)) {
            return false;
        }
        protocol::Message frames;
        frames.emplace_back(topic.data<char>(), topic.size());
        bool more = topic.more();
        while (more) {
            zmq::message_t part;
            (void)m_stream.recv(part, zmq::recv_flags::none);
            frames.emplace_back(part.data<char>(), part.size());
            more = part.more();
        }
        if (frames.size() < 2) {
            return true;
        }
        const json header = json::parse(frames[1], nullptr, false);
        if (!header.is_object()) {
            return true;
        }
        ++m_frames;
        const auto seq = header.value("seq", std::uint64_t { 0 });
        if (m_last_seq != 0 && seq != m_last_seq + 1) {
            ++m_seq_gaps;
        }
        m_last_seq = seq;
        m_topology_versions.insert(header.value("topology_version", std::uint64_t { 0 }));
        see_tick(header.value("tick", std::int64_t { 0 }));
        return true;
    }

    PlayOptions m_options;
    zmq::context_t m_context { 1 };
    zmq::socket_t m_control;
    zmq::socket_t m_stream;
    bool m_subscribed = false;
    std::int64_t m_next_id = 0;
    std::map<std::int64_t, Pending> m_pending;
    std::map<std::int64_t, protocol::Reply> m_done;
    std::vector<double> m_latencies;
    std::vector<json> m_error_samples;
    std::set<std::uint64_t> m_topology_versions;
    std::uint64_t m_sent = 0, m_replies = 0, m_errors = 0, m_frames = 0, m_seq_gaps = 0;
    std::uint64_t m_last_seq = 0, m_sweep_triangles = 0;
    std::int64_t m_first_tick = -1, m_last_tick = -1;
};

/// Puts a bound id into the params of remove_force, move_grab, release.
void fill_id(protocol::Params& params, std::uint64_t id) {
    if (auto* p = std::get_if<protocol::RemoveForceParams>(&params)) {
        p->id = id;
    } else if (auto* m = std::get_if<protocol::MoveGrabParams>(&params)) {
        m->id = id;
    } else if (auto* r = std::get_if<protocol::ReleaseParams>(&params)) {
        r->id = id;
    }
}

} // namespace

std::string play(const Script& script, const PlayOptions& options, int& errors_out) {
    Session session(options);
    const auto hello_id = session.send(protocol::HelloParams { "polycut-scalpel", "polycut/1" });
    const auto hello = session.wait_for(hello_id);
    if (!hello || !hello->ok()) {
        throw std::runtime_error("no hello reply from " + options.server);
    }
    const auto& h = std::get<protocol::HelloResult>(std::get<protocol::Result>(hello->outcome));
    if (options.subscribe) {
        session.subscribe(h.stream);
    }
    std::map<std::string, std::uint64_t> ids;
    const auto start = Clock::now();
    auto at = [&](double t) {
        return start
            + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t));
    };
    for (const Action& action : script.actions) {
        while (Clock::now() < at(action.t)) {
            session.pump(
                std::chrono::duration_cast<std::chrono::milliseconds>(at(action.t) - Clock::now()));
        }
        protocol::Params params = action.params;
        if (!action.ref.empty()) {
            auto it = ids.find(action.ref);
            if (it == ids.end()) {
                continue; // its creation failed; the error is already counted
            }
            fill_id(params, it->second);
        }
        const auto id = session.send(params);
        if (action.wait || !action.bind_as.empty()) {
            const auto reply = session.wait_for(id);
            if (reply && reply->ok() && !action.bind_as.empty()) {
                const auto& result = std::get<protocol::Result>(reply->outcome);
                if (const auto* created = std::get_if<protocol::Created>(&result)) {
                    ids[action.bind_as] = created->id;
                }
            }
        }
    }
    while (Clock::now() < at(script.end_t)) {
        session.pump(
            std::chrono::duration_cast<std::chrono::milliseconds>(at(script.end_t) - Clock::now()));
    }
    const auto drain_until = Clock::now() + std::chrono::duration<double>(options.reply_timeout_s);
    while (session.outstanding() > 0 && Clock::now() < drain_until) {
        session.pump(std::chrono::milliseconds(20));
    }
    const double duration_s = std::chrono::duration<double>(Clock::now() - start).count();
    json server_stats;
    const auto stats_id = session.send(protocol::GetStatsParams {});
    if (const auto stats = session.wait_for(stats_id); stats && stats->ok()) {
        const auto& s = std::get<protocol::Stats>(std::get<protocol::Result>(stats->outcome));
        server_stats = { { "tick", s.tick }, { "topology_version", s.topology_version },
            { "ticks_over_budget", s.ticks_over_budget },
            { "worst_tick_ms", round3(s.worst_tick_ms) }, { "step_ms_p50", round3(s.step_ms_p50) },
            { "step_ms_p99", round3(s.step_ms_p99) }, { "triangle_count", s.triangle_count },
            { "cell_count", s.cell_count } };
    }
    if (options.shutdown_after) {
        const auto shutdown_id = session.send(protocol::ShutdownParams {});
        session.wait_for(shutdown_id);
    }
    errors_out = session.errors();
    return session.summary(script, duration_s, server_stats).dump();
}

bool send_shutdown(const PlayOptions& options) {
    Session session(options);
    const auto id = session.send(protocol::ShutdownParams {});
    const auto reply = session.wait_for(id);
    return reply && reply->ok();
}

} // namespace polycut::scalpel
