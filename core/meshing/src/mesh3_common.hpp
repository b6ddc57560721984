// Private to the meshing module (includes CGAL): the Mesh_3 run shared by the implicit and the
// polyhedral domains, and the conversion of the resulting complex into a polycut Mesh.
#pragma once

#include "polycut/common/error.hpp"
#include "polycut/mesh/mesh.hpp"
#include "polycut/meshing/options.hpp"

#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Random.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/optimize_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace polycut::meshing::detail {

/// Milliseconds since `start`.
inline double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

/// Runs Mesh_3 on a domain: refinement, then the optimisers the options select (lloyd, odt,
/// perturb, exude, in that order, without time limits so that the mesh does not depend on
/// speed). Every random choice CGAL makes comes from `rng` (the domain's generator, passed by
/// the caller) or from the default generator, reseeded here. Reports each phase to `sink`.
template <class C3t3, class Domain>
C3t3 run_mesh_3(const Domain& domain, const MeshingOptions& o, const ProgressSink& sink = {}) {
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
    C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, p::manifold(), p::no_lloyd(), p::no_odt(),
        p::no_perturb(), p::no_exude());
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
