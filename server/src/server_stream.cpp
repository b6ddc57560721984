// The stream (PUB): a `surface` frame after every tick, with triangles and tags when the
// topology changed since the last frame; `event` messages. Sends never block (a small
// high-water mark and ZMQ_DONTWAIT; a slow subscriber loses frames and sees a gap in seq). The
// last published frame is kept so get_surface answers exactly what frame `seq` carried (zguide
// Clone pattern, docs/protocol.md "Late joiners and gaps").
#include "server_impl.hpp"

#include <nlohmann/json.hpp>

namespace polycut::server {

void Server::Impl::publish_surface(const sim::StepReport& report, bool force_topology) {
    if (!session.has_scene()) {
        return;
    }
    const sim::Simulation& sim = session.simulation();
    const std::uint64_t version = sim.topology_version();
    const bool topology = force_topology || topology_pending || version != published_topology;
    if (topology) {
        sim::Surface surface = sim.surface();
        last_positions = std::move(surface.positions);
        last_triangles = std::move(surface.triangles);
        last_tags = std::move(surface.tags);
        published_topology = version;
        topology_pending = false;
    } else {
        sim.surface_positions(last_positions);
    }
    protocol::SurfaceHeader h;
    h.seq = ++seq;
    h.tick = sim.tick();
    h.sim_time = sim.time();
    h.topology_version = version;
    h.vertex_count = static_cast<std::uint32_t>(last_positions.size() / 3);
    h.triangle_count = static_cast<std::uint32_t>(last_triangles.size() / 3);
    h.has_topology = topology;
    h.step.step_ms = report.step_ms;
    h.step.solver_iterations = static_cast<std::uint32_t>(std::max(0, report.solver_iterations));
    h.step.residual = report.residual;
    h.step.warnings = report.warnings;
    h.cut_deferred = static_cast<std::uint32_t>(session.pending_sweep_triangles());
    h.contacts = session.contacts();
    h.applied = std::move(applied);
    applied.clear();
    const std::span<const std::uint32_t> triangles = topology
        ? std::span<const std::uint32_t>(last_triangles)
        : std::span<const std::uint32_t>();
    const std::span<const std::uint8_t> tags
        = topology ? std::span<const std::uint8_t>(last_tags) : std::span<const std::uint8_t>();
    send_stream(protocol::encode_surface(h, last_positions, triangles, tags));
    last_header = std::move(h);

    if (topology && !force_topology) {
        nlohmann::json detail = { { "topology_version", version },
            { "triangle_count", last_header.triangle_count },
            { "vertex_count", last_header.vertex_count }, { "cut_ms", session.take_cut_ms() } };
        if (last_cut_id) {
            detail["request"] = nlohmann::json::parse(protocol::to_json_text(*last_cut_id));
        }
        publish_event("topology", detail.dump(), seq);
    }
    last_cut_id.reset();
    if (!report.warnings.empty()) {
        nlohmann::json detail
            = { { "message", report.warnings.front() }, { "count", report.warnings.size() } };
        publish_event(
            "warning", detail.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), seq);
    }
}

void Server::Impl::publish_event(
    std::string kind, std::string detail_json, std::uint64_t event_seq) {
    protocol::Event e;
    e.kind = std::move(kind);
    e.tick = session.tick();
    e.seq = event_seq;
    e.event_seq = ++events_published;
    e.detail_json = std::move(detail_json);
    send_stream(protocol::encode_event(e));
}

void Server::Impl::send_stream(const protocol::Message& message) {
    try {
        for (std::size_t k = 0; k < message.size(); ++k) {
            const auto flags = k + 1 < message.size()
                ? zmq::send_flags::sndmore | zmq::send_flags::dontwait
                : zmq::send_flags::dontwait;
            if (!stream.send(zmq::buffer(message[k]), flags)) {
                // Only the first frame can be refused; a PUB then drops the whole message.
                ++stream_dropped;
                return;
            }
        }
    } catch (const zmq::error_t&) {
        ++stream_dropped;
    }
}

protocol::SurfaceSnapshot Server::Impl::snapshot() const {
    protocol::SurfaceSnapshot s;
    s.header = last_header;
    s.header.has_topology = true;
    s.header.applied.clear();
    s.positions = last_positions;
    s.triangles = last_triangles;
    s.tags = last_tags;
    return s;
}

} // namespace polycut::server
