// Session: the protocol's commands applied to sim::Simulation (see server_session.hpp).
#include "server_session.hpp"

#include "polycut/common/error.hpp"
#include "polycut/protocol/sweep.hpp"
#include "polycut/scene/scene.hpp"
#include "polycut/sim/estimate.hpp"
#include "server_session_detail.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <type_traits>

namespace polycut::server {

namespace {

using protocol::ErrorCode;
using protocol::make_error;
using protocol::RpcError;

using detail::done;
using detail::to_vec;

/// A file-based geometry in an inline scene may only name a file under the scene directory.
std::optional<RpcError> check_inline_paths(const scene::Scene& s) {
    using Kind = scene::Geometry::Kind;
    if (s.geometry.kind != Kind::SurfaceFile && s.geometry.kind != Kind::MeshFile
        && !((s.geometry.kind == Kind::HexSlice || s.geometry.kind == Kind::Octree)
            && !s.geometry.path.empty())) {
        return std::nullopt;
    }
    const std::filesystem::path p(s.geometry.path);
    bool escapes = p.is_absolute() || p.has_root_name() || p.has_root_directory();
    for (const auto& part : p) {
        escapes = escapes || part == "..";
    }
    if (escapes) {
        return make_error(ErrorCode::SceneError,
            s.geometry.kind == Kind::HexSlice ? "/params/scene/geometry/surface"
                                              : "/params/scene/geometry/path",
            "an inline scene may only name files relative to the server's scene directory");
    }
    return std::nullopt;
}

/// One stderr line on what meshing did for a scene being loaded (repair and tet quality), so an
/// operator sees a repaired or sliver-ridden organ without the runner; the wire reply is unchanged.
void log_meshing(const std::string& scene_name, const sim::MeshingSummary& m) {
    if (!m.meshed) {
        return;
    }
    const std::string repair = m.has_repair ? "; repair " + m.repair_summary : std::string();
    // The quality line ends in a warning when the tets include slivers.
    std::fprintf(stderr,
        "[info] polycut-server: scene \"%s\" meshed (%s) in %.0f ms%s; quality %s\n",
        scene_name.c_str(), m.source.c_str(), m.total_ms, repair.c_str(),
        m.quality_summary.c_str());
}

/// A scene that could not be read or built, as -32001 pointing into the request: at
/// /params/name for a named scene (the file's own location in the reason), into
/// /params/scene for an inline one.
RpcError scene_error(const std::exception& e, bool named) {
    if (const auto* scene = dynamic_cast<const SceneError*>(&e)) {
        if (named) {
            return make_error(ErrorCode::SceneError, "/params/name",
                "scene file invalid at " + scene->where() + ": " + scene->problem());
        }
        return make_error(
            ErrorCode::SceneError, "/params/scene" + scene->where(), scene->problem());
    }
    const std::string pointer = named ? "/params/name" : "/params/scene";
    if (dynamic_cast<const Error*>(&e) != nullptr) {
        return make_error(ErrorCode::SceneError, pointer, e.what());
    }
    return make_error(
        ErrorCode::SceneError, pointer, std::string("the scene could not be built: ") + e.what());
}

} // namespace

Session::Session(SessionConfig config)
    : m_config(std::move(config))
    , m_strokes(m_config.strokes)
    , m_cut_triangles_left(m_config.cut_triangles_per_tick) { }

Session::~Session() = default;

bool Session::is_mutation(protocol::Method method) {
    using M = protocol::Method;
    switch (method) {
    case M::LoadScene:
    case M::Reset:
    case M::ApplyForce:
    case M::RemoveForce:
    case M::Grab:
    case M::MoveGrab:
    case M::Release:
    case M::Cut:
    case M::Scalpel:
    case M::EndStroke:
    case M::ToolCreate:
    case M::ToolMove:
    case M::ToolRemove:
        return true;
    default:
        return false;
    }
}

void Session::load_scene_file(const std::string& path) {
    scene::Scene scene = scene::load_scene(path);
    if (auto why = sim::over_budget(scene, m_config.max_scene_bytes)) {
        throw SceneError("/geometry", *why);
    }
    std::string name
        = scene.name.empty() ? std::filesystem::path(path).stem().string() : scene.name;
    auto sim = std::make_unique<sim::Simulation>(std::move(scene));
    sim->prepare_cutting(); // not in the first cut's tick
    install(std::move(sim), std::move(name));
}

std::unique_ptr<sim::Simulation> Session::install(
    std::unique_ptr<sim::Simulation> sim, std::string name) {
    std::unique_ptr<sim::Simulation> old = std::exchange(m_sim, std::move(sim));
    m_scene_name = std::move(name);
    log_meshing(m_scene_name, m_sim->meshing_summary());
    m_cells = static_cast<std::uint32_t>(m_sim->cell_count());
    m_forces.clear();
    m_grabs.clear();
    m_tools.clear();
    m_strokes.clear();
    m_pending_sweep.clear();
    m_cut_since_step.clear(); // cuts of the old scene: its next step never comes
    return old;
}

std::int64_t Session::tick() const {
    return m_sim ? m_sim->tick() : 0;
}
double Session::sim_time() const {
    return m_sim ? m_sim->time() : 0.0;
}
std::uint64_t Session::topology_version() const {
    return m_sim ? m_sim->topology_version() : 0;
}

ApplyOutcome Session::apply(
    const protocol::Params& params, std::string_view client, double now_s, bool reply_expected) {
    using protocol::Method;
    const Method method = protocol::method_of(params);
    if (method != Method::LoadScene && !m_sim) {
        return make_error(ErrorCode::SimulationError, "", "no scene is loaded (call load_scene)");
    }
    if (method == Method::LoadScene || method == Method::Reset) {
        m_pending_sweep.clear(); // the state they would cut is discarded anyway
    } else if (method != Method::Scalpel) {
        // Keep arrival order: queued blade sweeps happen before any later command.
        flush_sweeps();
    }
    try {
        return std::visit(
            [&](const auto& p) -> ApplyOutcome {
                using T = std::decay_t<decltype(p)>;
                if constexpr (std::is_same_v<T, protocol::LoadSceneParams>) {
                    return load_scene(p);
                } else if constexpr (std::is_same_v<T, protocol::ResetParams>) {
                    return reset();
                } else if constexpr (std::is_same_v<T, protocol::ApplyForceParams>) {
                    return apply_force(p);
                } else if constexpr (std::is_same_v<T, protocol::RemoveForceParams>) {
                    return remove_force(p);
                } else if constexpr (std::is_same_v<T, protocol::GrabParams>) {
                    return grab(p);
                } else if constexpr (std::is_same_v<T, protocol::MoveGrabParams>) {
                    return move_grab(p);
                } else if constexpr (std::is_same_v<T, protocol::ReleaseParams>) {
                    return release(p);
                } else if constexpr (std::is_same_v<T, protocol::CutParams>) {
                    return cut(p, client);
                } else if constexpr (std::is_same_v<T, protocol::ScalpelParams>) {
                    return scalpel(p, client, now_s, reply_expected);
                } else if constexpr (std::is_same_v<T, protocol::EndStrokeParams>) {
                    return end_stroke(p, client);
                } else if constexpr (std::is_same_v<T, protocol::ToolCreateParams>) {
                    return tool_create(p);
                } else if constexpr (std::is_same_v<T, protocol::ToolMoveParams>) {
                    return tool_move(p);
                } else if constexpr (std::is_same_v<T, protocol::ToolRemoveParams>) {
                    return tool_remove(p);
                } else {
                    return make_error(ErrorCode::InternalError, "/method",
                        "not a simulation command: " + std::string(protocol::method_name(method)));
                }
            },
            params);
    } catch (const std::exception& e) {
        // The sim promises InputError without change; anything else is a bug, never a crash.
        return make_error(ErrorCode::InternalError, "", e.what());
    }
}

sim::StepReport Session::step() {
    if (!m_sim) {
        return {};
    }
    sim::StepReport report;
    try {
        const double cut_before = m_cut_ms;
        flush_sweeps();
        const double cut_ms = m_cut_ms - cut_before;
        report = m_sim->step();
        report.cut_ms = cut_ms;
        m_cut_triangles_left = m_config.cut_triangles_per_tick;
        if (report.cut_undone) {
            // The cuts of this tick made the model unsound and are gone: their strokes hear it.
            for (const StrokeCut& cut : m_cut_since_step) {
                m_rejections.push_back(
                    { cut.client, cut.from_cut ? "cut" : "scalpel", cut.stroke, cut.triangles,
                        make_error(ErrorCode::CutRejected, "/params",
                            "the cut was undone: the step after it failed ("
                                + (report.warnings.empty() ? std::string("unstable")
                                                           : report.warnings.front())
                                + ")") });
            }
            m_cells = static_cast<std::uint32_t>(m_sim->cell_count());
        }
        if (report.topology_changed) {
            m_cells = static_cast<std::uint32_t>(m_sim->cell_count());
        }
        prune_expired_forces();
    } catch (const std::exception& e) {
        // Session::step never throws (the server loop must go on); a failure here is a bug.
        report.warnings.push_back(std::string("tick failed: ") + e.what());
        report.rolled_back = true;
    }
    m_cut_since_step.clear();
    return report;
}

void Session::prune_expired_forces() {
    const double t = m_sim->time();
    std::erase_if(m_forces, [&](const auto& entry) {
        return entry.second.expires > 0 && t > entry.second.expires + 1e-12;
    });
}

void Session::drop_client(std::string_view client) {
    m_strokes.drop_client(client);
}
void Session::expire(double now_s) {
    m_strokes.expire(now_s);
}

protocol::Expected<PreparedScene, RpcError> Session::prepare_scene(
    const protocol::LoadSceneParams& p) const {
    try {
        if (p.name) {
            const auto path = std::filesystem::path(m_config.scene_dir) / (*p.name + ".json");
            std::error_code ec;
            if (!std::filesystem::is_regular_file(path, ec)) {
                return make_error(ErrorCode::SceneError, "/params/name",
                    "no scene named \"" + *p.name + "\" in the server's scene directory");
            }
            scene::Scene scene = scene::load_scene(path.string());
            if (auto why = sim::over_budget(scene, m_config.max_scene_bytes)) {
                return make_error(ErrorCode::SceneError, "/params/name", *why);
            }
            return PreparedScene { std::move(scene), *p.name, true };
        }
        scene::Scene scene = scene::parse_scene(*p.scene_json, m_config.scene_dir);
        if (auto bad = check_inline_paths(scene)) {
            return *bad;
        }
        if (auto why = sim::over_budget(scene, m_config.max_scene_bytes)) {
            return make_error(ErrorCode::SceneError, "/params/scene/geometry", *why);
        }
        return PreparedScene { std::move(scene), "inline", false };
    } catch (const std::exception& e) {
        return scene_error(e, p.name.has_value());
    }
}

BuiltScene Session::build_scene(PreparedScene prepared) {
    const bool named = prepared.named;
    try {
        auto sim = std::make_unique<sim::Simulation>(std::move(prepared.scene));
        sim->prepare_cutting(); // here, off the loop, not in the first cut's tick
        return sim;
    } catch (const std::exception& e) {
        return scene_error(e, named);
    }
}

Applied Session::install_scene(std::unique_ptr<sim::Simulation> sim, std::string name,
    std::unique_ptr<sim::Simulation>* replaced) {
    std::unique_ptr<sim::Simulation> old = install(std::move(sim), std::move(name));
    if (replaced != nullptr) {
        *replaced = std::move(old);
    }
    protocol::SceneResult r;
    r.tick = 0;
    r.name = m_scene_name;
    r.topology_version = m_sim->topology_version();
    const sim::Surface surface = m_sim->surface();
    r.vertex_count = static_cast<std::uint32_t>(surface.positions.size() / 3);
    r.triangle_count = static_cast<std::uint32_t>(surface.triangles.size() / 3);
    r.cell_count = m_cells;
    return Applied { r, true, "load" };
}

ApplyOutcome Session::load_scene(const protocol::LoadSceneParams& p) {
    auto prepared = prepare_scene(p);
    if (!prepared) {
        return prepared.error();
    }
    std::string name = prepared->name;
    BuiltScene built = build_scene(std::move(prepared).value());
    if (!built) {
        return built.error();
    }
    return install_scene(std::move(built).value(), std::move(name));
}

ApplyOutcome Session::reset() {
    m_sim->reset();
    m_cells = static_cast<std::uint32_t>(m_sim->cell_count());
    m_forces.clear();
    m_grabs.clear();
    m_tools.clear();
    m_strokes.clear();
    m_pending_sweep.clear();
    return Applied { protocol::RunState { 0, false, 0.0 }, true, "reset" };
}

ApplyOutcome Session::apply_force(const protocol::ApplyForceParams& p) {
    sim::ForceSpec spec;
    spec.point = to_vec(p.point);
    spec.force = to_vec(p.force);
    spec.radius = p.radius;
    spec.duration = p.duration.value_or(0.0);
    ForceEntry entry;
    try {
        entry.sim_id = m_sim->add_force(spec);
    } catch (const InputError& e) {
        return make_error(ErrorCode::InvalidParams, "/params/" + e.where(), e.problem());
    } catch (const StateError& e) {
        return make_error(ErrorCode::SimulationError, "/params/" + e.where(), e.problem());
    }
    entry.expires = p.duration ? m_sim->time() + *p.duration : 0.0;
    entry.spec
        = { p.point[0], p.point[1], p.point[2], p.force[0], p.force[1], p.force[2], p.radius };
    const std::uint64_t id = m_next_id++;
    m_forces.emplace(id, entry);
    return done(protocol::Created { id, effect_tick() });
}

ApplyOutcome Session::remove_force(const protocol::RemoveForceParams& p) {
    auto it = m_forces.find(p.id);
    if (it == m_forces.end()) {
        return make_error(
            ErrorCode::NotFound, "/params/id", "no active force with id " + std::to_string(p.id));
    }
    m_sim->remove_force(it->second.sim_id);
    m_forces.erase(it);
    return done(protocol::Ack { effect_tick() });
}

ApplyOutcome Session::grab(const protocol::GrabParams& p) {
    sim::GrabSpec spec;
    spec.point = to_vec(p.point);
    spec.stiffness = p.stiffness.value_or(protocol::kDefaultGrabStiffness);
    // Absent radius: the single material point nearest `point` (the sim falls back to the
    // nearest node when none lies within the radius, and refuses a point far from the material).
    spec.radius = p.radius.value_or(1e-9);
    GrabEntry entry;
    try {
        entry.sim_id = m_sim->grab(spec);
    } catch (const InputError& e) {
        return make_error(ErrorCode::InvalidParams, "/params/" + e.where(), e.problem());
    } catch (const StateError& e) {
        return make_error(ErrorCode::SimulationError, "/params/" + e.where(), e.problem());
    }
    entry.target = p.point;
    entry.spec = { p.point[0], p.point[1], p.point[2], spec.stiffness, spec.radius };
    const std::uint64_t id = m_next_id++;
    m_grabs.emplace(id, entry);
    return done(protocol::Created { id, effect_tick() });
}

ApplyOutcome Session::move_grab(const protocol::MoveGrabParams& p) {
    auto it = m_grabs.find(p.id);
    if (it == m_grabs.end()) {
        return make_error(
            ErrorCode::NotFound, "/params/id", "no active grab with id " + std::to_string(p.id));
    }
    try {
        if (!m_sim->move_grab(it->second.sim_id, to_vec(p.target))) {
            return make_error(ErrorCode::NotFound, "/params/id",
                "grab " + std::to_string(p.id) + " is gone from the simulation");
        }
    } catch (const InputError& e) {
        return make_error(ErrorCode::InvalidParams, "/params/target", e.problem());
    }
    it->second.target = p.target;
    return done(protocol::Ack { effect_tick() });
}

ApplyOutcome Session::release(const protocol::ReleaseParams& p) {
    auto it = m_grabs.find(p.id);
    if (it == m_grabs.end()) {
        return make_error(
            ErrorCode::NotFound, "/params/id", "no active grab with id " + std::to_string(p.id));
    }
    m_sim->release(it->second.sim_id);
    m_grabs.erase(it);
    return done(protocol::Ack { effect_tick() });
}

std::uint64_t Session::state_hash() const {
    // FNV-1a over the session's state on top of the simulation's own hash.
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](const void* data, std::size_t bytes) {
        const auto* c = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < bytes; ++i) {
            h ^= c[i];
            h *= 1099511628211ull;
        }
    };
    auto mix_value = [&](const auto& v) { mix(&v, sizeof v); };
    if (m_sim) {
        mix_value(m_sim->state_hash());
        mix_value(m_sim->tick());
        mix_value(m_sim->topology_version());
    }
    mix_value(m_next_id);
    for (const auto& [id, f] : m_forces) {
        mix_value(id);
        mix_value(f.expires);
        mix(f.spec.data(), sizeof f.spec);
    }
    for (const auto& [id, g] : m_grabs) {
        mix_value(id);
        mix(g.target.data(), sizeof g.target);
        mix(g.spec.data(), sizeof g.spec);
    }
    for (const auto& [id, t] : m_tools) {
        mix_value(id);
        mix(t.pose.data(), sizeof t.pose);
    }
    for (const PendingSweep& pending : m_pending_sweep) {
        mix(pending.client.data(), pending.client.size());
        mix_value(pending.stroke);
        mix_value(pending.from_cut);
        mix_value(pending.end);
        for (const Vec3& p : pending.triangle) {
            mix(p.data(), 3 * sizeof(double));
        }
    }
    for (const auto& [key, s] : m_strokes.entries()) {
        mix(key.first.data(), key.first.size());
        mix_value(key.second);
        mix(s.a.data(), sizeof s.a);
        mix(s.b.data(), sizeof s.b);
        mix_value(s.held);
        mix(s.held_a.data(), sizeof s.held_a);
        mix(s.held_b.data(), sizeof s.held_b);
        mix_value(s.triangles);
    }
    return h;
}

} // namespace polycut::server
