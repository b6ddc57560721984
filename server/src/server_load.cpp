// load_scene off the loop thread (issue 14 item 3; docs/decisions/0060). The cheap checks (name,
// parse, inline paths, memory budget) run on the loop thread and are answered at once. The build
// (meshing, assembly) runs on a SceneBuild worker while the loop goes on ticking, streaming and
// answering for the old scene. Between ticks the loop installs the built scene, answers the
// request and records it in the command log at that tick, so a replay (which loads
// synchronously at the recorded tick) reaches the same state.
#include "polycut/common/error.hpp"
#include "server_impl.hpp"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace polycut::server {

using protocol::ErrorCode;
using protocol::make_error;
using protocol::Method;

void Server::Impl::answer_error(const protocol::Message& envelope,
    const std::optional<protocol::RequestId>& id, Method method, const protocol::RpcError& error) {
    if (!id) {
        reject_notification(envelope.front(), protocol::method_name(method), error);
        return;
    }
    reply_error(envelope, *id, error);
}

void Server::Impl::start_load(const protocol::Message& envelope, const protocol::Request& request) {
    if (pending_load) {
        // One build at a time: a superseding load could not stop the running build (meshing
        // and assembly have no cancellation points), so two would hold memory and a core.
        const double ms
            = std::chrono::duration<double, std::milli>(Clock::now() - pending_load->started)
                  .count();
        char reason[192];
        std::snprintf(reason, sizeof reason,
            "scene \"%s\" is being built (for %.0f ms); load again once its load_scene is "
            "answered",
            pending_load->name.c_str(), ms);
        answer_error(envelope, request.id, Method::LoadScene,
            make_error(ErrorCode::StateConflict, "", reason));
        return;
    }
    auto prepared = session.prepare_scene(std::get<protocol::LoadSceneParams>(request.params));
    if (!prepared) {
        answer_error(envelope, request.id, Method::LoadScene, prepared.error());
        return;
    }
    PendingLoad load;
    load.envelope = envelope;
    load.request = request;
    load.name = prepared->name;
    load.tick_requested = session.tick();
    load.started = Clock::now();
    load.build = std::make_unique<SceneBuild>(std::move(prepared).value());
    pending_load = std::move(load);
}

void Server::Impl::finish_load() {
    if (!pending_load || !pending_load->build->done()) {
        return;
    }
    PendingLoad load = std::move(*pending_load);
    pending_load.reset();
    BuiltScene built = load.build->take();
    if (!built) {
        answer_error(load.envelope, load.request.id, Method::LoadScene, built.error());
        return; // the old scene goes on untouched
    }
    const auto t0 = Clock::now();
    const bool had_scene = session.has_scene();
    const std::int64_t tick_before = session.tick();
    std::unique_ptr<sim::Simulation> replaced;
    Applied done = session.install_scene(std::move(built).value(), load.name, &replaced);
    if (command_log) {
        command_log->record(tick_before, load.envelope.front(), load.request);
    }
    if (load.request.id) {
        applied.push_back(*load.request.id);
    }
    auto& result = std::get<protocol::SceneResult>(done.result);
    result.build_ms = load.build->build_ms();
    for (const sim::BuildPart& part : session.simulation().build_report().parts) {
        if (part.built) {
            result.build_parts.push_back({ part.name, part.ms, std::max(0L, part.rss_kb) });
        }
    }
    if (had_scene) {
        result.replaced_tick = tick_before;
    }
    announce_scene(done.scene_reason, std::move(replaced));
    const double install_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    command_ms_since_tick += install_ms;
    std::fprintf(stderr,
        "[info] polycut-server: scene \"%s\" built in %.0f ms off the loop, installed in %.1f ms "
        "(replaced tick %lld)\n",
        load.name.c_str(), result.build_ms, install_ms, static_cast<long long>(tick_before));
    if (load.request.id) {
        reply(load.envelope, protocol::encode_result(*load.request.id, done.result));
    }
}

void Server::Impl::announce_scene(
    const std::string& reason, std::unique_ptr<sim::Simulation> replaced) {
    // The new scene's first frame (tick 0, full topology) goes out now, so the stream and
    // get_surface describe it before the first step.
    publish_surface(sim::StepReport {}, true);
    nlohmann::json detail = { { "name", session.scene_name() }, { "reason", reason } };
    publish_event("scene", detail.dump(), seq);
    // The old scene is freed and the free pages go back to the system (glibc keeps them
    // otherwise: RSS stayed at its peak after a reload), off the loop.
    disposal.dispose(std::move(replaced));
}

} // namespace polycut::server
