// The control channel: receiving (frame cap, drain), rate limiting, decoding, the reply cache,
// dispatch to the session and the run state, and replies. Bad input of any kind is answered
// with a JSON-RPC error (or, for notifications, counted and published as a `rejected` event)
// and never reaches the simulation (docs/protocol.md "Errors").
#include "polycut/common/error.hpp"
#include "server_impl.hpp"

#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>

namespace polycut::server {

namespace {

using protocol::ErrorCode;
using protocol::make_error;
using protocol::Method;

constexpr std::string_view kServerName = "polycut-server 0.1.0";
/// Messages handled per service_control call, so a flood cannot starve the tick.
constexpr int kMaxMessagesPerService = 256;
/// `rejected` events published per flush (one per client, the first clients first); the rest
/// are counted in get_stats.events_suppressed, so a flood of bad notifications from many
/// clients cannot push surface frames out of the subscribers' queues.
constexpr std::size_t kMaxRejectedEventsPerFlush = 4;
/// A refused (busy) message is parsed for its id only up to this size [bytes]; a larger one is
/// answered with "id": null (JSON-RPC 2.0: the id could not be determined cheaply).
constexpr std::size_t kBusyPeekBytes = 1024;
/// Clients counted by get_stats.clients: seen within this window [s].
constexpr double kActiveClientWindow = 10.0;

bool is_cached_method(Method m) {
    return m == Method::Cut || m == Method::EndStroke || m == Method::ApplyForce
        || m == Method::Grab || m == Method::ToolCreate;
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
        // A signal may land on another thread (ZeroMQ's I/O threads): wake up at least every
        // 50 ms to see the stop flag.
        zmq::poll(&item, 1, std::chrono::milliseconds(std::min(timeout_ms, 50L)));
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
        const auto t1 = Clock::now();
        command_ms_since_tick += std::chrono::duration<double, std::milli>(t1 - t0).count();
        if (running && t1 >= next_deadline) {
            break; // the tick is due: the rest waits in the socket (issue 14 item 1)
        }
    }
    flush_rejections();
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
        it = clients
                 .emplace(identity,
                     ClientInfo {
                         t, config.limits.max_message_rate, double(config.limits.max_json_bytes) })
                 .first;
    }
    ClientInfo& c = it->second;
    // Token bucket: max_message_rate per second, bursts up to one second's worth.
    const double dt = t - c.last_seen_s;
    c.tokens
        = std::min(config.limits.max_message_rate, c.tokens + dt * config.limits.max_message_rate);
    // JSON byte bucket: json_bytes_per_tick per tick at the current rate, up to one message of
    // max_json_bytes.
    c.json_bytes = std::min(double(config.limits.max_json_bytes),
        c.json_bytes + dt * double(config.limits.json_bytes_per_tick) * rate_hz);
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
    // Every message counts against the budgets, valid or not, before any parsing.
    const double json_size = routed.body.empty() ? 0.0 : double(routed.body.front().size());
    const bool within_json_limit = json_size <= double(config.limits.max_json_bytes);
    if (client.tokens < 1.0) {
        refuse_busy(routed, identity,
            "more than " + std::to_string(config.limits.max_message_rate)
                + " messages per second; retry later");
        return;
    }
    if (within_json_limit && client.json_bytes < json_size) {
        refuse_busy(routed, identity,
            "JSON byte budget of " + std::to_string(config.limits.json_bytes_per_tick)
                + " bytes per tick used up; retry later");
        return;
    }
    client.tokens -= 1.0;
    if (within_json_limit) {
        client.json_bytes -= json_size; // an oversize frame is refused unparsed (-32005)
    }

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
            reject_notification(identity, bad.method, bad.error);
        }
        return;
    }
    dispatch(routed.envelope, decoded.value());
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
            reject_notification(identity, protocol::method_name(method), error);
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
    if (method == Method::LoadScene) {
        start_load(envelope, request); // answered once the scene is built (server_load.cpp)
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
            announce_scene(done.scene_reason);
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

void Server::Impl::refuse_busy(
    const protocol::Routed& routed, const std::string& identity, const std::string& reason) {
    ++busy;
    const auto error = make_error(ErrorCode::Busy, "", reason);
    protocol::RequestId id = nullptr;
    if (!routed.body.empty() && routed.body.front().size() <= kBusyPeekBytes) {
        // Small enough to read the id (and whether it is a notification) for next to nothing.
        protocol::Limits peek = config.limits;
        peek.max_frames_per_message = std::numeric_limits<std::uint32_t>::max();
        auto decoded = protocol::decode_request(routed.body, peek);
        if (decoded && !decoded->id) {
            reject_notification(identity, protocol::method_name(decoded->method()), error);
            return;
        }
        if (!decoded && !decoded.error().reply_expected) {
            reject_notification(identity, decoded.error().method, error);
            return;
        }
        id = decoded ? *decoded->id : decoded.error().id;
    }
    reply_error(routed.envelope, id, error);
}

void Server::Impl::reply(const protocol::Message& envelope, protocol::Message body) {
    // Never block: ROUTER_MANDATORY makes a send to a peer whose queue holds max_in_flight
    // replies fail (EAGAIN) and a send to a vanished peer throw (EHOSTUNREACH) instead of
    // dropping silently; both are counted in replies_dropped.
    try {
        if (envelope.empty()) {
            return;
        }
        if (!control.send(zmq::buffer(envelope.front()),
                zmq::send_flags::sndmore | zmq::send_flags::dontwait)) {
            ++replies_dropped;
            return;
        }
        for (std::size_t k = 1; k < envelope.size(); ++k) {
            const auto& frame = envelope[k];
            control.send(zmq::buffer(frame), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
        }
        for (std::size_t k = 0; k < body.size(); ++k) {
            const auto flags = k + 1 < body.size()
                ? zmq::send_flags::sndmore | zmq::send_flags::dontwait
                : zmq::send_flags::dontwait;
            control.send(zmq::buffer(body[k]), flags);
        }
    } catch (const zmq::error_t& e) {
        ++replies_dropped;
        if (e.num() != EHOSTUNREACH) {
            std::fprintf(stderr, "[warn] polycut-server: reply not sent: %s\n", e.what());
        }
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

void Server::Impl::reject_notification(
    const std::string& identity, std::string_view method, const protocol::RpcError& error) {
    ++errors;
    auto [it, fresh] = pending_rejections.try_emplace(identity);
    ++it->second.count;
    if (!fresh) {
        ++events_coalesced;
        return;
    }
    nlohmann::json detail
        = { { "method", std::string(method) }, { "code", static_cast<int>(error.code) },
              { "pointer", error.pointer }, { "reason", error.reason } };
    it->second.detail_json = detail.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void Server::Impl::flush_rejections() {
    std::size_t published = 0;
    for (auto& [identity, pending] : pending_rejections) {
        if (published == kMaxRejectedEventsPerFlush) {
            events_suppressed += pending.count;
            continue;
        }
        // `count`: this rejection and the ones from the same client folded into it.
        std::string detail = pending.detail_json;
        detail.pop_back(); // the closing brace
        detail += ",\"count\":" + std::to_string(pending.count) + "}";
        publish_event("rejected", detail, 0);
        ++published;
    }
    pending_rejections.clear();
}

protocol::HelloResult Server::Impl::hello() const {
    protocol::HelloResult h;
    h.server = std::string(kServerName);
    h.limits = config.limits;
    for (const Method m : protocol::kAllMethods) {
        h.capabilities.emplace_back(protocol::method_name(m));
    }
    h.capabilities.emplace_back("binary_frames");
    if (zap) {
        h.capabilities.emplace_back("curve");
    }
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
    s.replies_dropped = replies_dropped;
    s.events_coalesced = events_coalesced;
    s.events_suppressed = events_suppressed;
    s.busy = busy;
    s.tools = session.active_tools();
    s.contacts = session.contacts();
    s.contact_ms = session.has_scene() ? session.simulation().contact_ms() : 0.0;
    if (session.has_scene()) {
        const sim::CutAreas a = session.simulation().cut_areas();
        s.cut_area = a.cut_area;
        s.swept_area = a.swept_area;
        s.swept_area_undone = a.swept_area_undone;
        s.cut_completeness = a.completeness();
    }
    return s;
}

} // namespace polycut::server
