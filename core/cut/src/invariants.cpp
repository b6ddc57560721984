#include "polycut/cut/invariants.hpp"

#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/mesh/validate.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace polycut::cut {

double convexity_violation(const mesh::Mesh& m, Index c) {
    geometry::Aabb box;
    for (Index n : m.cells[std::size_t(c)].nodes)
        box.extend(m.rest[std::size_t(n)]);
    const double diag = box.diagonal();
    double worst = 0;
    for (const auto& loop : m.cell_face_loops(c)) {
        const auto pts = geometry::gather(m.rest, loop);
        const Vec3 nrm = geometry::polygon_normal(pts);
        const Vec3 ctr = geometry::polygon_centroid(pts);
        for (Index n : m.cells[std::size_t(c)].nodes)
            worst = std::max(worst, (m.rest[std::size_t(n)] - ctr).dot(nrm));
    }
    return diag > 0 ? worst / diag : 0;
}

std::string open_cell_problem(const mesh::Mesh& m, Index c) {
    std::vector<std::pair<Index, Index>> edges;
    const auto loops = m.cell_face_loops(c);
    if (loops.size() < 4)
        return "only " + std::to_string(loops.size()) + " faces";
    for (const auto& loop : loops)
        for (std::size_t k = 0; k < loop.size(); ++k)
            edges.emplace_back(loop[k], loop[(k + 1) % loop.size()]);
    std::sort(edges.begin(), edges.end());
    const auto edge = [](const std::pair<Index, Index>& e) {
        return "edge (" + std::to_string(e.first) + ", " + std::to_string(e.second) + ")";
    };
    for (std::size_t i = 0; i < edges.size(); ++i) {
        if (i + 1 < edges.size() && edges[i] == edges[i + 1])
            return edge(edges[i]) + " is used twice in the same direction (a flipped face)";
        if (!std::binary_search(
                edges.begin(), edges.end(), std::make_pair(edges[i].second, edges[i].first)))
            return edge(edges[i]) + " has no opposite edge (the cell is open)";
    }
    return {};
}

CutInvariants check_cut_invariants(
    const mesh::Mesh& m, double volume_before, const InvariantOptions& opt) {
    CutInvariants r;
    std::ostringstream problem;
    auto fail = [&](const std::string& what) {
        if (problem.tellp() == 0)
            problem << what;
    };
    r.volume_before = volume_before;
    r.cells = m.num_cells();
    r.nodes = m.num_nodes();
    for (const Vec3& x : m.rest)
        r.finite = r.finite && x.allFinite();
    if (!r.finite)
        fail("non-finite rest position");

    double vmin = std::numeric_limits<double>::infinity(), vmax = 0;
    for (Index c = 0; c < m.num_cells(); ++c) {
        const auto loops = m.cell_face_loops(c);
        const double v = geometry::polyhedron_volume(m.rest, loops);
        r.volume += v;
        vmin = std::min(vmin, v);
        vmax = std::max(vmax, v);
        if (!(v > 0)) {
            ++r.nonpositive_cells;
            fail("cell " + std::to_string(c) + " has volume " + std::to_string(v));
        }
        const double worst = convexity_violation(m, c);
        r.max_convexity_violation = std::max(r.max_convexity_violation, worst);
        if (worst > opt.convex_tol) {
            ++r.nonconvex_cells;
            if (opt.require_convex)
                fail("cell " + std::to_string(c) + " is not convex (violation "
                    + std::to_string(worst) + " of its diagonal)");
        }
    }
    r.min_volume_ratio = vmax > 0 ? vmin / vmax : 0;
    r.volume_error = volume_before != 0 ? std::abs(r.volume - volume_before) / volume_before : 0;
    if (!(r.volume_error <= opt.volume_tol)) {
        std::ostringstream msg;
        msg << "rest volume changed by " << r.volume_error << " (relative)";
        fail(msg.str());
    }

    mesh::ValidationOptions vo;
    vo.planarity_tol = opt.planarity_tol;
    // Coarsening behind a crack front takes collinear nodes out of every face; they stay in the
    // node table, unused (the elastic model gives them no DOFs).
    vo.allow_unused_nodes = true;
    vo.require_convex = false;
    vo.check_boundary = false;
    const auto issues = mesh::check_mesh(m, vo);
    r.mesh_issues = Index(issues.size());
    if (!issues.empty())
        fail(std::string("mesh: ") + mesh::kind_name(issues.front().kind) + ": "
            + issues.front().message);

    const auto surface = mesh::check_boundary_surface(m);
    r.surface_closed = surface.ok();
    r.surface_components = surface.components;
    if (!surface.ok())
        fail("boundary surface not closed/oriented: " + std::to_string(surface.boundary_edges)
            + " open, " + std::to_string(surface.nonmanifold_edges) + " non-manifold, "
            + std::to_string(surface.misoriented_edges) + " misoriented edges (face "
            + std::to_string(surface.first_bad_face) + ")");
    r.components = m.count_components();
    r.first_problem = problem.str();
    return r;
}

} // namespace polycut::cut
