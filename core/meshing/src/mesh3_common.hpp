// Private to the meshing module (includes CGAL): the Mesh_3 run shared by the implicit and the
// polyhedral domains, and the conversion of the resulting complex into a polycut Mesh.
#pragma once

#include "polycut/common/error.hpp"
#include "polycut/mesh/mesh.hpp"
#include "polycut/meshing/options.hpp"

#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_error_code.h>
#include <CGAL/Random.h>
#include <CGAL/exceptions.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/optimize_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace polycut::meshing::detail {

/// Milliseconds since `start`.
inline double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

/// Vertices Mesh_3's refinement may insert for a domain inside a box of `box_volume` [m^3] at
/// `cell_size` [m]: 20 x box_volume / cell_size^3 + 100,000. A well-posed domain takes ~0.4 x
/// box_volume / cell_size^3 (organ_20k: 18k vertices, 48k box cells), so only a refinement that
/// keeps inserting without converging reaches it. (One that stalls instead, as on the wrap of an
/// open box at a quarter of its size, found by tests/fuzz surface_readers, is stopped by the time
/// limit of run_mesh_3.)
inline std::size_t mesh_3_vertex_cap(double box_volume, double cell_size) {
    const double cells = box_volume / (cell_size * cell_size * cell_size);
    return std::size_t(std::min(20 * (std::isfinite(cells) ? cells : 0.0), 1e8)) + 100000;
}

/// Sets `stop` once `seconds` have passed, unless destroyed first (Mesh_3's refinement checks
/// it between steps: CGAL's pointer_to_stop_atomic_boolean).
class StopWatchdog {
public:
    StopWatchdog(std::atomic<bool>& stop, double seconds)
        : m_thread([this, &stop, seconds] {
            std::unique_lock<std::mutex> lock(m_mutex);
            if (!m_done.wait_for(
                    lock, std::chrono::duration<double>(seconds), [&] { return m_over; }))
                stop.store(true, std::memory_order_release);
        }) { }
    ~StopWatchdog() {
        {
            const std::lock_guard<std::mutex> lock(m_mutex);
            m_over = true;
        }
        m_done.notify_all();
        m_thread.join();
    }
    StopWatchdog(const StopWatchdog&) = delete;
    StopWatchdog& operator=(const StopWatchdog&) = delete;

private:
    std::mutex m_mutex;
    std::condition_variable m_done;
    bool m_over = false;
    std::thread m_thread; // last: started once the rest is made
};

/// Runs Mesh_3 on a domain: refinement, then the optimisers the options select (lloyd, odt,
/// perturb, exude, in that order, without time limits so that the mesh does not depend on
/// speed). Every random choice CGAL makes comes from `rng` (the domain's generator, passed by
/// the caller) or from the default generator, reseeded here. Reports each phase to `sink`.
/// `box_volume` [m^3] bounds the refinement (mesh_3_vertex_cap). Throws InputError (where
/// "cell_size") when the refinement reaches that cap or CGAL reports a failure (an assertion
/// such as "a facet is not in conflict with its refinement point", seen on thin wraps).
template <class C3t3, class Domain>
C3t3 run_mesh_3(const Domain& domain, const MeshingOptions& o, double box_volume,
    const ProgressSink& sink = {}) {
    using Criteria = CGAL::Mesh_criteria_3<typename C3t3::Triangulation>;
    namespace p = CGAL::parameters;
    CGAL::get_default_random() = CGAL::Random(o.seed);
    const double size = o.cell_size;
    // edge_size only matters for domains with 1D features (sharp surface edges).
    const Criteria criteria(p::edge_size = size, p::facet_angle = o.facet_angle,
        p::facet_size = size, p::facet_distance = o.effective_facet_distance(),
        p::cell_radius_edge_ratio = o.cell_radius_edge_ratio, p::cell_size = size);
    auto report = [&](const char* phase, const C3t3& c3t3, auto start) {
        if (sink)
            sink(std::string("Mesh_3 ") + phase + ": "
                + std::to_string(c3t3.number_of_cells_in_complex()) + " tets, "
                + std::to_string(long(ms_since(start))) + " ms");
    };
    // manifold(): the boundary of the cells in the complex is a 2-manifold, which the cutter
    // and validate() rely on.
    auto start = std::chrono::steady_clock::now();
    const std::size_t cap = mesh_3_vertex_cap(box_volume, size);
    CGAL::Mesh_error_code code = CGAL::CGAL_MESH_3_NO_ERROR;
    const auto failed = [&](const std::string& what) {
        return InputError("cell_size",
            "CGAL Mesh_3 could not mesh this domain at cell_size " + std::to_string(size)
                + " m: " + what
                + ". A surface with parts much thinner than the cell size (a wrap of an open "
                  "or thin-walled surface) does this: a smaller cell_size, or a wrap with a "
                  "larger offset, may mesh it");
    };
    const double expected = 0.4 * box_volume / (size * size * size);
    const double seconds = o.refine_time_limit > 0
        ? o.refine_time_limit
        : 10 + 1e-3 * (std::isfinite(expected) ? std::min(expected, 1e9) : 0.0);
    std::atomic<bool> stop { false };
    C3t3 c3t3;
    try {
        const StopWatchdog watchdog(stop, seconds);
        c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, p::manifold(), p::no_lloyd(), p::no_odt(),
            p::no_perturb(), p::no_exude(),
            p::mesh_3_options(p::maximal_number_of_vertices = cap, p::pointer_to_error_code = &code,
                p::pointer_to_stop_atomic_boolean = &stop));
    } catch (const CGAL::Failure_exception& e) {
        const std::string message = e.message().empty() ? e.expression() : e.message();
        throw failed("CGAL failed (" + message + ")");
    }
    if (code == CGAL::CGAL_MESH_3_MAXIMAL_NUMBER_OF_VERTICES_REACHED)
        throw failed("the refinement did not converge (stopped at " + std::to_string(cap)
            + " vertices, 20 x the bounding box volume over cell_size^3 + 100,000)");
    if (code == CGAL::CGAL_MESH_3_STOPPED)
        throw failed("the refinement did not finish in " + std::to_string(seconds)
            + " s (10 s + 1 ms per expected vertex, MeshingOptions::refine_time_limit)");
    report("refine", c3t3, start);
    if (o.lloyd) {
        start = std::chrono::steady_clock::now();
        CGAL::lloyd_optimize_mesh_3(c3t3, domain, p::max_iteration_number = 20);
        report("lloyd", c3t3, start);
    }
    if (o.odt) {
        start = std::chrono::steady_clock::now();
        CGAL::odt_optimize_mesh_3(c3t3, domain, p::max_iteration_number = 20);
        report("odt", c3t3, start);
    }
    if (o.perturb) {
        start = std::chrono::steady_clock::now();
        CGAL::perturb_mesh_3(c3t3, domain, p::sliver_bound = o.sliver_bound);
        report("perturb", c3t3, start);
    }
    if (o.exude) {
        start = std::chrono::steady_clock::now();
        CGAL::exude_mesh_3(c3t3, p::sliver_bound = o.sliver_bound);
        report("exude", c3t3, start);
    }
    return c3t3;
}

/// The cells in the complex as tetrahedra, with the vertices they use numbered by first use
/// (so unreferenced vertices are dropped and the order is deterministic).
template <class C3t3> mesh::Mesh to_mesh(const C3t3& c3t3, const std::string& what) {
    using Vertex_handle = typename C3t3::Vertex_handle;
    std::map<Vertex_handle, Index> ids;
    std::vector<Vec3> rest;
    std::vector<std::array<Index, 4>> tets;
    tets.reserve(std::size_t(c3t3.number_of_cells_in_complex()));
    for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
        std::array<Index, 4> tet {};
        for (int i = 0; i < 4; ++i) {
            const Vertex_handle v = c->vertex(i);
            const auto [it, inserted] = ids.try_emplace(v, Index(rest.size()));
            if (inserted) {
                const auto& p = v->point();
                rest.emplace_back(
                    CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
            }
            tet[std::size_t(i)] = it->second;
        }
        tets.push_back(tet);
    }
    if (tets.empty())
        throw MeshError(-1, -1, what + ": CGAL Mesh_3 produced no tetrahedra");
    return mesh::Mesh::from_tets(std::move(rest), tets);
}

} // namespace polycut::meshing::detail
