// The cutting side of Session (issue 12): scalpel strokes, their sweep triangles queued per tick,
// `cut` and `end_stroke`, the cut budget's carried triangles, and how core/cut's typed result
// becomes a JSON-RPC answer or a `rejected` event. See server_session.cpp for the rest.
#include "polycut/protocol/sweep.hpp"
#include "server_session.hpp"
#include "server_session_detail.hpp"

#include <algorithm>

namespace polycut::server {

namespace {

using protocol::ErrorCode;
using protocol::make_error;
using protocol::RpcError;

using detail::done;
using detail::to_triangle;
using detail::to_vec;

} // namespace

void Session::flush_sweeps() {
    if (m_pending_sweep.empty() || !m_sim) {
        m_pending_sweep.clear();
        return;
    }
    std::vector<PendingSweep> pending;
    pending.swap(m_pending_sweep);
    // One cut per stroke (and per deferred `cut`), in order of their first pending triangle: a
    // stroke that cannot be cut loses only its own triangles. What the tick's cut budget leaves
    // over is carried, in order, to the next tick.
    std::vector<PendingSweep> carried;
    std::vector<bool> done(pending.size(), false);
    for (std::size_t first = 0; first < pending.size(); ++first) {
        if (done[first]) {
            continue;
        }
        const PendingSweep head = pending[first];
        std::vector<std::array<Vec3, 3>> sweep;
        bool ends = false;
        for (std::size_t k = first; k < pending.size(); ++k) {
            const PendingSweep& p = pending[k];
            if (!done[k] && p.client == head.client && p.stroke == head.stroke
                && p.from_cut == head.from_cut) {
                if (p.end) {
                    ends = true;
                } else {
                    sweep.push_back(p.triangle);
                }
                done[k] = true;
            }
        }
        const char* method = head.from_cut ? "cut" : "scalpel";
        std::size_t deferred = 0;
        if (!sweep.empty()) {
            const auto count = static_cast<std::uint32_t>(sweep.size());
            auto summary = run_cut(sweep, "/params");
            if (!summary) {
                m_rejections.push_back(
                    { head.client, method, head.stroke, count, summary.error() });
                continue; // the stroke is closed already if it ended; its finish goes too
            }
            deferred = static_cast<std::size_t>(summary->triangles_deferred);
            m_cut_since_step.push_back({ head.client, head.from_cut, head.stroke,
                count - static_cast<std::uint32_t>(deferred) });
            for (std::size_t k = sweep.size() - deferred; k < sweep.size(); ++k) {
                PendingSweep rest = head;
                rest.triangle = sweep[k];
                carried.push_back(std::move(rest));
            }
        }
        if (!ends) {
            continue;
        }
        if (deferred > 0) {
            PendingSweep end = head;
            end.end = true;
            carried.push_back(std::move(end));
            continue;
        }
        finish_sweep(head.client, head.from_cut, head.stroke);
    }
    carried.insert(carried.end(), m_pending_sweep.begin(), m_pending_sweep.end());
    m_pending_sweep = std::move(carried);
}

void Session::finish_sweep(const std::string& client, bool from_cut, std::uint64_t stroke) {
    const sim::CutSummary finish = m_sim->end_stroke();
    m_cells = static_cast<std::uint32_t>(m_sim->cell_count());
    if (!finish.ok()) {
        m_rejections.push_back({ client, from_cut ? "cut" : "end_stroke", stroke, 0,
            make_error(
                ErrorCode::CutRejected, from_cut ? "/params" : "/params/stroke", finish.reason) });
    }
}

std::size_t Session::pending_sweep_triangles() const {
    return static_cast<std::size_t>(std::count_if(m_pending_sweep.begin(), m_pending_sweep.end(),
        [](const PendingSweep& p) { return !p.end; }));
}

std::uint32_t Session::queue_sweep(Stroke& stroke, const protocol::Vector3& a,
    const protocol::Vector3& b, std::string_view client, std::uint64_t id) {
    // Consecutive samples a0b0 -> a1b1 sweep the quad (a0, b0, b1, a1): two triangles
    // (a0, b0, a1) and (b0, b1, a1); degenerate ones (the blade did not move) are skipped. A
    // move longer than Simulation::blade_max_advance() is swept as that many equal quads, the
    // blade interpolated linearly, so the tick's cut budget can defer the later ones.
    const Vec3 a0 = to_vec(stroke.a), b0 = to_vec(stroke.b), a1 = to_vec(a), b1 = to_vec(b);
    const double advance = std::max((a1 - a0).norm(), (b1 - b0).norm());
    const double step = m_sim->blade_max_advance();
    constexpr int kMaxQuads = 64; // a blade flung across the scene: bounded work
    const int quads = step > 0 && advance > step
        ? static_cast<int>(std::min<double>(kMaxQuads, std::ceil(advance / step)))
        : 1;
    std::uint32_t added = 0;
    Vec3 pa = a0, pb = b0;
    for (int q = 1; q <= quads; ++q) {
        const double s = double(q) / quads;
        const Vec3 qa = q == quads ? a1 : Vec3(a0 + s * (a1 - a0));
        const Vec3 qb = q == quads ? b1 : Vec3(b0 + s * (b1 - b0));
        const std::array<std::array<Vec3, 3>, 2> quad = { { { pa, pb, qa }, { pb, qb, qa } } };
        for (const auto& tri : quad) {
            if (!protocol::triangle_defect(to_triangle(tri))) {
                m_pending_sweep.push_back({ std::string(client), id, tri });
                ++added;
            }
        }
        pa = qa;
        pb = qb;
    }
    stroke.a = a;
    stroke.b = b;
    stroke.held = false;
    stroke.triangles += added;
    return added;
}

std::optional<RpcError> Session::take_rejection(std::string_view client, std::uint64_t stroke) {
    for (auto it = m_rejections.begin(); it != m_rejections.end(); ++it) {
        if (it->client == client && it->stroke == stroke && it->method != "cut") {
            RpcError error = it->error;
            m_rejections.erase(it);
            return error;
        }
    }
    return std::nullopt;
}

protocol::Expected<sim::CutSummary, RpcError> Session::run_cut(
    const std::vector<std::array<Vec3, 3>>& triangles, std::string_view pointer) {
    // The tick's triangle budget; at least one triangle per call, so every stroke advances.
    const std::uint32_t cap = m_config.cut_triangles_per_tick > 0
        ? std::max<std::uint32_t>(1, m_cut_triangles_left)
        : 0;
    const sim::CutSummary summary = m_sim->cut(triangles, static_cast<int>(cap));
    if (summary.ok()) {
        const auto used = static_cast<std::uint32_t>(triangles.size())
            - static_cast<std::uint32_t>(summary.triangles_deferred);
        m_cut_triangles_left -= std::min(m_cut_triangles_left, used);
    }
    m_cut_ms += summary.cut_ms;
    m_cells = static_cast<std::uint32_t>(summary.cells_after);
    switch (summary.status) {
    case sim::CutSummary::Status::Rejected: {
        // Where in the request: the triangle, and its corner when one is to blame.
        std::string at = protocol::pointer_append(
            pointer, static_cast<std::size_t>(summary.rejected_triangle));
        if (summary.rejected_corner >= 0) {
            at = protocol::pointer_append(at, static_cast<std::size_t>(summary.rejected_corner));
        }
        return make_error(ErrorCode::CutRejected, at, summary.reason);
    }
    case sim::CutSummary::Status::Failed:
        // The sim undid the cut: the mesh and state are as before, the loop goes on.
        return make_error(ErrorCode::CutRejected, std::string(pointer), "cut: " + summary.reason);
    default:
        return summary;
    }
}

ApplyOutcome Session::cut(const protocol::CutParams& p, std::string_view client) {
    std::vector<std::array<Vec3, 3>> world(p.triangles.size());
    for (std::size_t t = 0; t < p.triangles.size(); ++t) {
        for (std::size_t k = 0; k < 3; ++k) {
            world[t][k] = to_vec(p.triangles[t][k]);
        }
    }
    auto summary = run_cut(world, "/params/triangles");
    if (!summary) {
        return summary.error();
    }
    // Past the tick's cut budget the rest waits: cut over the next ticks, in order, with a
    // `rejected` event (method "cut") if it cannot be.
    const auto deferred = static_cast<std::size_t>(summary->triangles_deferred);
    for (std::size_t t = world.size() - deferred; t < world.size(); ++t) {
        m_pending_sweep.push_back({ std::string(client), 0, world[t], true, false });
    }
    // A `cut` is one whole sweep: once its last triangle is cut, the sweep is finished as a
    // stroke's is at end_stroke (face snapping cuts the faces it held back; without this they
    // waited for some scalpel stroke to end, ~4 % of a plane's cut on the block).
    if (deferred > 0) {
        PendingSweep end;
        end.client = std::string(client);
        end.from_cut = true;
        end.end = true;
        m_pending_sweep.push_back(std::move(end));
    } else {
        finish_sweep(std::string(client), true, 0);
    }
    if (deferred < world.size()) {
        m_cut_since_step.push_back(
            { std::string(client), true, 0, static_cast<std::uint32_t>(world.size() - deferred) });
    }
    return done(protocol::CutResult { effect_tick(), m_sim->topology_version(),
        static_cast<std::uint32_t>(world.size() - deferred),
        static_cast<std::uint32_t>(deferred) });
}

ApplyOutcome Session::scalpel(
    const protocol::ScalpelParams& p, std::string_view client, double now_s, bool reply_expected) {
    Stroke* stroke = m_strokes.find(client, p.stroke);
    if (stroke == nullptr) {
        Stroke& opened = m_strokes.open(client, p.stroke, now_s);
        opened.a = p.a;
        opened.b = p.b;
        return done(protocol::ScalpelResult { effect_tick(), 0 });
    }
    const Stroke previous = *stroke;
    stroke->last_used_s = now_s;
    // A blade that moved less than blade_min_advance since the last swept sample is held: the
    // next sample (or end_stroke) sweeps from the last swept one, so the cutter sees strips of
    // at least that width instead of one sliver per tick.
    const double advance = std::max(
        (to_vec(p.a) - to_vec(stroke->a)).norm(), (to_vec(p.b) - to_vec(stroke->b)).norm());
    if (advance < m_sim->blade_min_advance()) {
        stroke->held = true;
        stroke->held_a = p.a;
        stroke->held_b = p.b;
        return done(protocol::ScalpelResult { effect_tick(), 0 });
    }
    const std::uint32_t added = queue_sweep(*stroke, p.a, p.b, client, p.stroke);
    if (reply_expected && added > 0) {
        // A request wants the outcome: cut now. On failure the sample is taken back (the
        // stroke continues from the previous one), so the state is as before the request.
        flush_sweeps();
        if (auto own = take_rejection(client, p.stroke)) {
            *stroke = previous;
            return *own;
        }
    }
    return done(protocol::ScalpelResult { effect_tick(), added });
}

ApplyOutcome Session::end_stroke(const protocol::EndStrokeParams& p, std::string_view client) {
    Stroke* stroke = m_strokes.find(client, p.stroke);
    if (stroke == nullptr) {
        return make_error(ErrorCode::NotFound, "/params/stroke",
            "no open stroke " + std::to_string(p.stroke) + " for this client");
    }
    if (stroke->held) {
        queue_sweep(*stroke, stroke->held_a, stroke->held_b, client, p.stroke);
    }
    const std::uint32_t total = stroke->triangles;
    m_strokes.close(client, p.stroke);
    // The stroke's last sweep is applied now, then the stroke is finished (face snapping cuts
    // the faces it held back), so the reply's topology_version includes both; what the tick's
    // cut budget defers is cut, and the stroke finished, over the next ticks.
    PendingSweep end;
    end.client = std::string(client);
    end.stroke = p.stroke;
    end.end = true;
    m_pending_sweep.push_back(std::move(end));
    flush_sweeps();
    if (auto own = take_rejection(client, p.stroke)) {
        return *own;
    }
    std::uint32_t deferred = 0;
    for (const PendingSweep& q : m_pending_sweep) {
        deferred += !q.end && !q.from_cut && q.client == client && q.stroke == p.stroke ? 1 : 0;
    }
    return done(protocol::CutResult {
        effect_tick(), m_sim->topology_version(), total - deferred, deferred });
}

} // namespace polycut::server
