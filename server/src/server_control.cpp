// The control channel: receiving (frame cap, drain), rate limiting, decoding, the reply cache,
// dispatch to the session and the run state, and replies. Bad input of any kind is answered
// with a JSON-RPC error (or, for notifications, counted and published as a `rejected` event)
// and never reaches the simulation (docs/protocol.md "Errors").
#include "polycut/common/error.hpp"
#include "server_impl.hpp"

#include <cstdio>
#include <nlohmann/json.hpp>

namespace polycut::server {

namespace {

using protocol::ErrorCode;
using protocol::make_error;
using protocol::Method;

constexpr std::string_view kServerName = "polycut-server 0.1.0";
/// Messages handled per service_control call, so a flood cannot starve the tick.
constexpr int kMaxMessagesPerService = 256;
/// Clients counted by get_stats.clients: seen within this window [s].
constexpr double kActiveClientWindow = 10.0;

bool is_cached_method(Method m) {
    return m == Method::Cut || m == Method::EndStroke || m == Method::ApplyForce
        || m == Method::Grab;
}

std::string hex64(std::uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

} // namespace

void Server::Impl::service_control(long timeout_ms) {
    zmq::pollitem_t item { control.handle(), 0, ZMQ_POLLIN, 0 };
    try {
        zmq::poll(&item, 1, std::chrono::milliseconds(timeout_ms));
    } catch (const zmq::error_t& e) {
        if (e.num() == EINTR) {
            return; // a signal: the loop checks its stop flag
        }
        throw;
    }
    if ((item.revents & ZMQ_POLLIN) == 0) {
        return;
    }
    for (int n = 0; n < kMaxMessagesPerService && !stop.load(std::memory_order_relaxed); ++n) {
        protocol::Message frames;
        std::size_t total = 0;
        if (!receive(frames, total)) {
            break;
        }
        const auto t0 = Clock::now();
        handle(std::move(frames), total);
        command_ms_since_tick
            += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    }
}

bool Server::Impl::receive(protocol::Message& frames, std::size_t& total_frames) {
    // Keep the identity, a possible REQ delimiter and one frame past the limit (so the decoder
    // reports -32005); drain the rest so the next message starts clean.
    const std::size_t keep = std::size_t(config.limits.max_frames_per_message) + 3;
    total_frames = 0;
    bool more = true;
    while (more) {
        zmq::message_t part;
        zmq::recv_result_t got;
        try {
            got = control.recv(
                part, total_frames == 0 ? zmq::recv_flags::dontwait : zmq::recv_flags::none);
        } catch (const zmq::error_t& e) {
            if (e.num() == EINTR && total_frames == 0) {
                return false;
            }
            if (e.num() == EINTR) {
                continue; // the rest of a multipart message is already queued
            }
            throw;
        }
        if (!got) {
            return false; // nothing queued
        }
        ++total_frames;
        if (frames.size() < keep) {
            frames.emplace_back(part.data<char>(), part.size());
        }
        more = part.more();
    }
    return true;
}

ClientInfo& Server::Impl::touch_client(const std::string& identity) {
    const double t = now_s();
    auto it = clients.find(identity);
    if (it == clients.end()) {
        if (clients.size() >= config.max_clients) {
            auto oldest = clients.begin();
            for (auto c = clients.begin(); c != clients.end(); ++c) {
                if (c->second.last_seen_s < oldest->second.last_seen_s) {
                    oldest = c;
                }
            }
            session.drop_client(oldest->first);
            reply_cache.drop_client(oldest->first);
            clients.erase(oldest);
        }
        it = clients.emplace(identity, ClientInfo { t, config.limits.max_message_rate }).first;
    }
    ClientInfo& c = it->second;
    // Token bucket: max_message_rate per second, bursts up to one second's worth.
    c.tokens = std::min(config.limits.max_message_rate,
        c.tokens + (t - c.last_seen_s) * config.limits.max_message_rate);
    c.last_seen_s = t;
    return c;
}

void Server::Impl::handle(protocol::Message frames, std::size_t total_frames) {
    ++requests;
    protocol::Routed routed = protocol::split_envelope(std::move(frames));
    if (routed.envelope.empty()) {
        ++errors;
        return; // cannot happen on a ROUTER; nothing to answer to
    }
    const std::string identity = routed.envelope.front();
    ClientInfo& client = touch_client(identity);

    const std::size_t body_frames = total_frames - routed.envelope.size();
    auto decoded = protocol::decode_request(routed.body, config.limits);
    if (!decoded) {
        protocol::RequestError& bad = decoded.error();
        if (bad.error.code == ErrorCode::PayloadTooLarge
            && body_frames > config.limits.max_frames_per_message) {
            bad.error.reason = "message has " + std::to_string(body_frames)
                + " frames; the limit is " + std::to_string(config.limits.max_frames_per_message);
        }
        if (bad.reply_expected) {
            reply_error(routed.envelope, bad.id, bad.error);
        } else {
            reject_notification("", bad.error);
        }
        return;
    }
    const protocol::Request& request = decoded.value();
    if (client.tokens < 1.0) {
        const auto busy = make_error(ErrorCode::Busy, "",
            "more than " + std::to_string(config.limits.max_message_rate)
                + " requests per second; retry later");
        if (request.id) {
            reply_error(routed.envelope, *request.id, busy);
        } else {
            reject_notification(protocol::method_name(request.method()), busy);
        }
        return;
    }
    client.tokens -= 1.0;
    dispatch(routed.envelope, request);
}

void Server::Impl::dispatch(const protocol::Message& envelope, const protocol::Request& request) {
    const Method method = request.method();
    const std::string& identity = envelope.front();
    const bool cacheable = is_cached_method(method) && request.id
        && !std::holds_alternative<std::nullptr_t>(*request.id);
    const std::string id_text = request.id ? protocol::to_json_text(*request.id) : std::string();
    if (cacheable) {
        if (const protocol::Message* cached = reply_cache.find(identity, id_text)) {
            reply(envelope, *cached);
            return;
        }
    }
    auto answer = [&](protocol::Result result) {
        if (!request.id) {
            return;
        }
        protocol::Message body = protocol::encode_result(*request.id, result);
        if (cacheable) {
            reply_cache.store(identity, id_text, body, now_s());
        }
        reply(envelope, std::move(body));
    };
    auto fail = [&](const protocol::RpcError& error) {
        if (!request.id) {
            reject_notification(protocol::method_name(method), error);
            return;
        }
        ++errors;
        protocol::Message body = protocol::encode_error(*request.id, error);
        if (cacheable) {
            reply_cache.store(identity, id_text, body, now_s());
        }
        reply(envelope, std::move(body));
    };

    if (shutting_down) {
        fail(make_error(ErrorCode::StateConflict, "", "the server is shutting down"));
        return;
    }
    if (Session::is_mutation(method)) {
        const std::int64_t tick_before = session.tick();
        ApplyOutcome outcome
            = session.apply(request.params, identity, now_s(), request.id.has_value());
        publish_sweep_rejections();
        if (!outcome) {
            fail(outcome.error());
            return;
        }
        if (command_log) {
            command_log->record(tick_before, identity, request);
        }
        if (request.id) {
            applied.push_back(*request.id);
        }
        Applied& done = outcome.value();
        if (method == Method::Cut || method == Method::Scalpel) {
            last_cut_id = request.id;
        }
        if (done.scene_changed) {
            if (auto* state = std::get_if<protocol::RunState>(&done.result)) {
                *state = run_state();
            }
            // The new scene's first frame (tick 0, full topology) goes out now, so the stream
            // and get_surface describe it before the first step.
            publish_surface(sim::StepReport {}, true);
            nlohmann::json detail
                = { { "name", session.scene_name() }, { "reason", done.scene_reason } };
            publish_event("scene", detail.dump(), seq);
        }
        answer(std::move(done.result));
        return;
    }
    switch (method) {
    case Method::Hello:
        answer(hello());
        return;
    case Method::Pause:
        running = false;
        answer(run_state());
        return;
    case Method::Resume:
        running = true;
        answer(run_state());
        return;
    case Method::Step: {
        if (running) {
            fail(make_error(
                ErrorCode::StateConflict, "", "step runs only while paused; pause first"));
            return;
        }
        if (!session.has_scene()) {
            fail(
                make_error(ErrorCode::SimulationError, "", "no scene is loaded (call load_scene)"));
            return;
        }
        const auto& p = std::get<protocol::StepParams>(request.params);
        pending_steps.push_back(PendingStep { envelope, request.id, p.ticks });
        return; // answered by finish_steps after the last tick
    }
    case Method::SetRate:
        set_rate(std::get<protocol::SetRateParams>(request.params).hz);
        answer(run_state());
        return;
    case Method::GetSurface:
        if (!session.has_scene() || seq == 0) {
            fail(
                make_error(ErrorCode::SimulationError, "", "no scene is loaded (call load_scene)"));
            return;
        }
        answer(snapshot());
        return;
    case Method::GetStats:
        answer(stats());
        return;
    case Method::Shutdown:
        answer(protocol::Ack { session.tick() });
        shutting_down = true;
        stop.store(true, std::memory_order_relaxed);
        return;
    default:
        fail(make_error(ErrorCode::InternalError, "/method", "unhandled method"));
        return;
    }
}

void Server::Impl::finish_steps() {
    if (pending_steps.empty()) {
        return;
    }
    PendingStep& front = pending_steps.front();
    if (front.remaining > 0) {
        --front.remaining;
    }
    if (front.remaining == 0) {
        if (front.id) {
            protocol::RunState state = run_state();
            state.running = running;
            reply(front.envelope, protocol::encode_result(*front.id, state));
        }
        pending_steps.pop_front();
    }
}

void Server::Impl::reply(const protocol::Message& envelope, protocol::Message body) {
    // A ROUTER drops messages to peers that are gone or over their HWM; never block.
    try {
        for (const auto& frame : envelope) {
            control.send(zmq::buffer(frame), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
        }
        for (std::size_t k = 0; k < body.size(); ++k) {
            const auto flags = k + 1 < body.size()
                ? zmq::send_flags::sndmore | zmq::send_flags::dontwait
                : zmq::send_flags::dontwait;
            control.send(zmq::buffer(body[k]), flags);
        }
    } catch (const zmq::error_t& e) {
        std::fprintf(stderr, "[warn] polycut-server: reply not sent: %s\n", e.what());
    }
}

void Server::Impl::reply_error(const protocol::Message& envelope, const protocol::RequestId& id,
    const protocol::RpcError& error) {
    ++errors;
    reply(envelope, protocol::encode_error(id, error));
}

void Server::Impl::publish_sweep_rejections() {
    for (const SweepRejection& r : session.take_rejections()) {
        ++errors;
        nlohmann::json detail = { { "method", r.method },
            { "code", static_cast<int>(r.error.code) }, { "pointer", r.error.pointer },
            { "reason", r.error.reason }, { "triangles", r.triangles } };
        if (r.method != "cut") {
            detail["stroke"] = r.stroke;
        }
        publish_event(
            "rejected", detail.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), 0);
    }
}

void Server::Impl::reject_notification(std::string_view method, const protocol::RpcError& error) {
    ++errors;
    nlohmann::json detail
        = { { "method", std::string(method) }, { "code", static_cast<int>(error.code) },
              { "pointer", error.pointer }, { "reason", error.reason } };
    publish_event(
        "rejected", detail.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), 0);
}

protocol::HelloResult Server::Impl::hello() const {
    protocol::HelloResult h;
    h.server = std::string(kServerName);
    h.limits = config.limits;
    for (const Method m : protocol::kAllMethods) {
        h.capabilities.emplace_back(protocol::method_name(m));
    }
    h.capabilities.emplace_back("binary_frames");
    h.stream = stream_endpoint;
    h.tick = session.tick();
    h.rate_hz = rate_hz;
    h.running = running;
    if (session.has_scene()) {
        h.scene = session.scene_name();
    }
    return h;
}

protocol::RunState Server::Impl::run_state() const {
    return protocol::RunState { session.tick(), running, rate_hz };
}

protocol::Stats Server::Impl::stats() const {
    protocol::Stats s;
    s.tick = session.tick();
    s.sim_time = session.sim_time();
    s.running = running;
    s.rate_hz = rate_hz;
    s.seq = seq;
    s.topology_version = session.topology_version();
    s.vertex_count = static_cast<std::uint32_t>(last_positions.size() / 3);
    s.triangle_count = static_cast<std::uint32_t>(last_triangles.size() / 3);
    s.cell_count = session.has_scene() ? session.cell_count() : 0;
    s.ticks_over_budget = ticks_over_budget;
    s.worst_tick_ms = worst_tick_ms;
    s.step_ms_p50 = step_p50_ms;
    s.step_ms_p99 = step_p99_ms;
    s.requests = requests;
    s.errors = errors;
    const double t = now_s();
    for (const auto& [identity, info] : clients) {
        s.clients += t - info.last_seen_s <= kActiveClientWindow ? 1 : 0;
    }
    s.forces = session.active_forces();
    s.grabs = session.active_grabs();
    s.state_hash = hex64(session.state_hash());
    s.stream_dropped = stream_dropped;
    s.open_strokes = static_cast<std::uint32_t>(session.open_strokes());
    s.cached_replies = static_cast<std::uint32_t>(reply_cache.size());
    s.client_states = static_cast<std::uint32_t>(clients.size());
    return s;
}

} // namespace polycut::server
