// Server construction, the fixed-rate loop and its schedule (see server.hpp). The schedule is
// absolute: deadline k = anchor + k * period on steady_clock, so sleeping and polling jitter
// never accumulates into drift. A loop that falls more than one period behind (a long cut or
// scene load) re-anchors at the present instead of bursting ticks to catch up.
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "server_impl.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>
#include <unistd.h>

namespace polycut::server {

namespace {

std::string last_endpoint(zmq::socket_t& socket) {
    return socket.get(zmq::sockopt::last_endpoint);
}

std::string default_scene_dir(const ServerConfig& c) {
    if (!c.scene_dir.empty()) {
        return c.scene_dir;
    }
    if (c.scene_file) {
        const auto dir = std::filesystem::path(*c.scene_file).parent_path();
        return dir.empty() ? std::string(".") : dir.string();
    }
    return "assets/scenes";
}

SessionConfig session_config(const ServerConfig& c) {
    SessionConfig s;
    s.scene_dir = default_scene_dir(c);
    s.strokes = c.strokes;
    s.max_scene_bytes = c.limits.max_scene_bytes;
    s.cut_triangles_per_tick = c.limits.cut_triangles_per_tick;
    return s;
}

/// The default scene budget: a quarter of the machine's memory (other processes, the old scene
/// still ticking while a new one is built, and the estimate's own error need the rest).
ServerConfig with_default_budget(ServerConfig c) {
    if (c.limits.max_scene_bytes == 0) {
        const long pages = ::sysconf(_SC_PHYS_PAGES);
        const long page = ::sysconf(_SC_PAGESIZE);
        if (pages > 0 && page > 0) {
            c.limits.max_scene_bytes = std::uint64_t(pages) * std::uint64_t(page) / 4;
        }
    }
    return c;
}

} // namespace

Server::Impl::Impl(ServerConfig cfg, std::atomic<bool>& stop_flag)
    : config(with_default_budget(std::move(cfg)))
    , stop(stop_flag)
    , control(context, zmq::socket_type::router)
    , stream(context, zmq::socket_type::pub)
    , session(session_config(config))
    , reply_cache(config.reply_cache) {
    if (!(config.rate_hz > 0.0) || config.rate_hz > config.limits.max_rate_hz) {
        throw InputError(
            "--rate", "must be in (0, " + std::to_string(config.limits.max_rate_hz) + "] Hz");
    }
    rate_hz = config.rate_hz;
    running = !config.paused;
    if (config.scene_file) {
        session.load_scene_file(*config.scene_file);
    }
    if (config.curve_keys) {
        const CurveKeys keys = read_curve_keys(*config.curve_keys);
        zap = std::make_unique<ZapHandler>(context, keys.authorized);
        make_curve_server(control, keys);
        make_curve_server(stream, keys);
    } else if (!config.insecure) {
        for (const auto& [option, endpoint] : { std::pair { "--control", config.control },
                 std::pair { "--stream", config.stream } }) {
            if (!is_loopback_endpoint(endpoint)) {
                throw InputError(option,
                    endpoint
                        + " is reachable from other machines: give --curve-keys DIR (CURVE "
                          "encryption and a client allow-list), or --insecure");
            }
        }
    }
    control.set(zmq::sockopt::linger, 0);
    control.set(zmq::sockopt::maxmsgsize, static_cast<int64_t>(config.limits.max_frame_bytes));
    // A client reconnecting with the same ROUTING_ID takes over its identity (retries across a
    // reconnect hit the reply cache).
    control.set(zmq::sockopt::router_handover, 1);
    // Replies over a client's in-flight bound fail and are counted instead of vanishing.
    control.set(zmq::sockopt::router_mandatory, 1);
    control.set(zmq::sockopt::sndhwm, static_cast<int>(config.limits.max_in_flight));
    control.bind(config.control);
    stream.set(zmq::sockopt::linger, 0);
    stream.set(zmq::sockopt::sndhwm, config.stream_hwm);
    stream.bind(config.stream);
    control_endpoint = last_endpoint(control);
    stream_endpoint = last_endpoint(stream);
    if (config.record_commands) {
        std::optional<std::string> scene_abs;
        if (config.scene_file) {
            scene_abs = std::filesystem::absolute(*config.scene_file).string();
        }
        command_log = std::make_unique<CommandLog>(
            *config.record_commands, scene_abs, default_scene_dir(config));
    }
    start_time = Clock::now();
}

double Server::Impl::now_s() const {
    return std::chrono::duration<double>(Clock::now() - start_time).count();
}

void Server::Impl::set_rate(double hz) {
    rate_hz = hz;
    // Re-anchor at the current deadline: the new period applies from the next tick.
    anchor = next_deadline;
    ticks_since_anchor = 0;
}

void Server::Impl::run() {
    if (session.has_scene() && seq == 0) {
        publish_surface(sim::StepReport {}, true);
    }
    anchor = Clock::now();
    ticks_since_anchor = 0;
    next_deadline = anchor;
    while (!stop.load(std::memory_order_relaxed)) {
        // The loop never dies (DESIGN.md sec. 8): whatever a tick or a command throws is logged
        // and the service goes on with the state the failing call left (each call restores its
        // own state on failure).
        try {
            loop_once();
        } catch (const zmq::error_t& e) {
            if (e.num() == ETERM) {
                break; // the sockets are gone: nothing left to serve
            }
            ++errors;
            std::fprintf(stderr, "[error] polycut-server: %s (the server goes on)\n", e.what());
        } catch (const std::exception& e) {
            ++errors;
            std::fprintf(stderr, "[error] polycut-server: %s (the server goes on)\n", e.what());
        }
    }
    if (command_log) {
        command_log->end(session.tick());
    }
}

void Server::Impl::loop_once() {
    {
        finish_load(); // a scene built off the loop replaces the old one between ticks
        const auto now = Clock::now();
        const bool stepping = !pending_steps.empty();
        if (running && now >= next_deadline) {
            run_tick();
            ++ticks_since_anchor;
            next_deadline = anchor
                + std::chrono::duration_cast<Clock::duration>(
                    std::chrono::duration<double>(double(ticks_since_anchor) / rate_hz));
            const auto after = Clock::now();
            if (after - next_deadline > std::chrono::duration<double>(1.0 / rate_hz)) {
                // More than a whole period behind: skip the missed ticks, keep the period.
                anchor = after;
                ticks_since_anchor = 0;
                next_deadline = after;
            }
            service_control(0);
        } else if (!running && stepping) {
            run_tick();
            service_control(0);
        } else if (running) {
            const auto remaining = next_deadline - now;
            const long ms = static_cast<long>(
                std::chrono::duration_cast<std::chrono::milliseconds>(remaining).count());
            if (ms >= 1) {
                service_control(ms);
            } else {
                std::this_thread::sleep_until(next_deadline);
            }
        } else {
            service_control(100);
            // A resume starts a fresh schedule.
            anchor = Clock::now();
            ticks_since_anchor = 0;
            next_deadline = anchor;
        }
        housekeeping();
    }
}

void Server::Impl::run_tick() {
    const auto t0 = Clock::now();
    const double cpu0 = thread_cpu_ms();
    const sim::StepReport report = session.step();
    const double step_cpu_ms = thread_cpu_ms() - cpu0;
    publish_surface(report, false);
    publish_sweep_rejections();
    flush_rejections();
    const double tick_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count()
        + command_ms_since_tick;
    command_ms_since_tick = 0.0;
    ++ticks_total;
    const double t = now_s();
    recent_steps.push_back({ t, report.step_ms, step_cpu_ms });
    worst_tick_ms = std::max(worst_tick_ms, tick_ms);
    if (running && tick_ms > period_ms()) {
        ++ticks_over_budget;
        if (t - last_overrun_event_s >= 1.0) {
            last_overrun_event_s = t;
            char detail[128];
            std::snprintf(detail, sizeof detail, "{\"tick_ms\":%.3f,\"budget_ms\":%.3f}", tick_ms,
                period_ms());
            publish_event("overrun", detail, seq);
        }
    }
    finish_steps();
}

void Server::Impl::housekeeping() {
    const double t = now_s();
    while (!recent_steps.empty() && t - recent_steps.front().time_s > 1.0) {
        recent_steps.pop_front();
    }
    if (t - last_housekeeping_s < 0.25) {
        return;
    }
    last_housekeeping_s = t;
    std::vector<double> sample, cpu_sample;
    sample.reserve(recent_steps.size());
    cpu_sample.reserve(recent_steps.size());
    for (const RecentStep& step : recent_steps) {
        sample.push_back(step.wall_ms);
        cpu_sample.push_back(step.cpu_ms);
    }
    if (!sample.empty()) {
        step_p50_ms = percentile(sample, 50.0);
        step_p99_ms = percentile(sample, 99.0);
        step_cpu_p50_ms = percentile(cpu_sample, 50.0);
        step_cpu_p99_ms = percentile(cpu_sample, 99.0);
    }
    // Forget silent clients: their strokes and cached replies go with them.
    for (auto it = clients.begin(); it != clients.end();) {
        if (t - it->second.last_seen_s > config.client_ttl_s) {
            session.drop_client(it->first);
            reply_cache.drop_client(it->first);
            it = clients.erase(it);
        } else {
            ++it;
        }
    }
    session.expire(t);
    reply_cache.expire(t);
    if (t - last_log_s >= 1.0) {
        log_line();
        last_log_s = t;
        ticks_at_last_log = ticks_total;
    }
}

void Server::Impl::log_line() {
    if (!config.log_stats) {
        return;
    }
    const double elapsed = now_s() - last_log_s;
    const double measured = elapsed > 0 ? double(ticks_total - ticks_at_last_log) / elapsed : 0.0;
    std::fprintf(stderr,
        "[info] polycut-server: tick %lld %s rate %.1f/%.1f Hz step p50 %.2f p99 %.2f ms "
        "(cpu p50 %.2f p99 %.2f) over-budget %llu worst %.1f ms requests %llu errors %llu "
        "clients %zu dropped %llu\n",
        static_cast<long long>(session.tick()), running ? "running" : "paused", measured, rate_hz,
        step_p50_ms, step_p99_ms, step_cpu_p50_ms, step_cpu_p99_ms,
        static_cast<unsigned long long>(ticks_over_budget), worst_tick_ms,
        static_cast<unsigned long long>(requests), static_cast<unsigned long long>(errors),
        clients.size(), static_cast<unsigned long long>(stream_dropped));
}

Server::Server(ServerConfig config)
    : m_impl(std::make_unique<Impl>(std::move(config), m_stop)) { }

Server::~Server() = default;

std::string Server::control_endpoint() const {
    return m_impl->control_endpoint;
}
std::string Server::stream_endpoint() const {
    return m_impl->stream_endpoint;
}

void Server::run() {
    m_impl->run();
}

bool Server::scene_build_in_flight() const {
    return m_impl->pending_load.has_value() && !m_impl->pending_load->build->done();
}

} // namespace polycut::server
