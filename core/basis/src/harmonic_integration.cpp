// Integration of harmonic cells (seed 001 sec. 6): a Gauss rule on a star tetrahedralization
// (from the centroid, or for non-convex cells from a point that sees every surface triangle),
// or Monte Carlo for comparison; and the boundary error of the MFS fit (001 sec. 5).
#include "harmonic_detail.hpp"
#include "polycut/common/error.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "star_rule.hpp"

#include <random>

namespace polycut::basis {
namespace {
/// Smallest signed distance from p to the planes of the outward triangles (positive: p
/// sees every triangle from inside, so the star tets from p are all positive).
double star_margin(
    const std::vector<Vec3>& pos, const std::vector<SurfaceTriangle>& tris, const Vec3& p) {
    double m = std::numeric_limits<double>::infinity();
    for (const auto& t : tris) {
        const Vec3& a = pos[std::size_t(t.nodes[0])];
        const Vec3 n = (pos[std::size_t(t.nodes[1])] - a)
                           .cross(pos[std::size_t(t.nodes[2])] - a)
                           .normalized();
        m = std::min(m, (a - p).dot(n));
    }
    return m;
}

/// A point of the kernel (the region that sees the whole surface), maximizing star_margin:
/// the centroid if it is well inside, else a grid search refined by pattern search.
Vec3 star_point(const std::vector<Vec3>& pos, const std::vector<SurfaceTriangle>& tris,
    const Vec3& centroid, double size) {
    if (star_margin(pos, tris, centroid) > 0.05 * size)
        return centroid;
    geometry::Aabb box;
    for (const auto& p : pos)
        box.extend(p);
    Vec3 best = centroid;
    double best_m = star_margin(pos, tris, centroid);
    const int g = 8;
    for (int i = 0; i <= g; ++i)
        for (int j = 0; j <= g; ++j)
            for (int k = 0; k <= g; ++k) {
                const Vec3 p = box.lo + box.extent().cwiseProduct(Vec3(i, j, k) / g);
                const double m = star_margin(pos, tris, p);
                if (m > best_m) {
                    best_m = m;
                    best = p;
                }
            }
    for (double step = 0.5 * size / g; step > 1e-4 * size; step *= 0.5) {
        bool moved = true;
        while (moved) {
            moved = false;
            for (int d = 0; d < 6; ++d) {
                Vec3 p = best;
                p[d / 2] += d % 2 ? step : -step;
                const double m = star_margin(pos, tris, p);
                if (m > best_m) {
                    best_m = m;
                    best = p;
                    moved = true;
                }
            }
        }
    }
    if (!(best_m > 1e-9 * size))
        throw MeshError(kNone, kNone,
            "harmonic cell is not star-shaped; no tetrahedralization point for integration");
    return best;
}
} // namespace

CellIntegration HarmonicCell::integrate(const HarmonicIntegration& integration) const {
    const Impl& c = *m_impl;
    CellIntegration out;
    if (integration.rule == HarmonicRule::Gauss) {
        std::vector<std::array<Index, 3>> tris;
        for (const auto& t : c.triangles)
            tris.push_back(t.nodes);
        const Vec3 apex
            = c.convex ? c.centroid : star_point(c.group_pos, c.triangles, c.centroid, c.size);
        detail::star_rule(
            c.group_pos, tris, apex, integration.gauss_degree, out.points, out.weights);
    } else {
        if (integration.monte_carlo_samples < 1)
            throw InputError("/monte_carlo_samples", "must be positive");
        geometry::Aabb box;
        for (const auto& p : c.group_pos)
            box.extend(p);
        std::mt19937_64 rng(integration.seed);
        std::uniform_real_distribution<double> uni(0.0, 1.0);
        while (int(out.points.size()) < integration.monte_carlo_samples) {
            const Vec3 p = box.lo + box.extent().cwiseProduct(Vec3(uni(rng), uni(rng), uni(rng)));
            const bool inside = c.convex ? c.max_plane_distance(p) < 0 : c.winding(p) > 0.5;
            if (inside)
                out.points.push_back(p);
        }
        out.weights.assign(out.points.size(), c.volume / double(out.points.size()));
    }
    out.gradients.resize(out.points.size());
    out.lumped_volume = VecX::Zero(num_nodes());
    VecX phi;
    for (std::size_t q = 0; q < out.points.size(); ++q) {
        evaluate(out.points[q], phi, &out.gradients[q]);
        out.lumped_volume += out.weights[q] * phi;
    }
    return out;
}

HarmonicBoundaryError HarmonicCell::boundary_error(int per_edge) const {
    const Impl& c = *m_impl;
    const std::size_t ng = c.group_pos.size();
    double sum_err = 0, sum_data = 0, worst = 0;
    VecX g, b, fvals;
    auto accumulate = [&](const Vec3& x, const VecX& data) {
        c.evaluate_groups(x, g, nullptr);
        sum_err += (g - data).squaredNorm();
        sum_data += data.squaredNorm();
        worst = std::max(worst, (g - data).lpNorm<Eigen::Infinity>());
    };
    double mean_edge = 0;
    int edges = 0;
    for (std::size_t f = 0; f < c.faces.size(); ++f) {
        const auto& gl = c.face_groups[f];
        for (std::size_t i = 0; i < gl.size(); ++i) {
            const Index a = gl[i], e = gl[(i + 1) % gl.size()];
            mean_edge += (c.group_pos[std::size_t(e)] - c.group_pos[std::size_t(a)]).norm();
            ++edges;
            // each edge is seen from both faces; test points offset by half a step from the
            // collocation points' pattern
            for (int j = 0; j < per_edge; ++j) {
                const double t = (j + 0.5) / per_edge;
                b = VecX::Zero(Index(ng));
                b[a] += 1 - t;
                b[e] += t;
                accumulate(
                    (1 - t) * c.group_pos[std::size_t(a)] + t * c.group_pos[std::size_t(e)], b);
            }
        }
    }
    mean_edge /= std::max(edges, 1);
    const double h = mean_edge / per_edge;
    for (std::size_t f = 0; f < c.faces.size(); ++f) {
        const auto& face = c.faces[f];
        const auto& gl = c.face_groups[f];
        for (const auto& q : detail::polygon_grid(face.polygon(), h / face.scale(), 0.0)) {
            const Vec3 x = face.to_3d(q + Eigen::Vector2d(0.31, 0.17) * (h / face.scale()));
            if (!detail::inside_polygon(face.polygon(), face.to_2d(x)))
                continue;
            fvals.resize(Index(gl.size()));
            face.evaluate(x, fvals);
            b = VecX::Zero(Index(ng));
            for (std::size_t v = 0; v < gl.size(); ++v)
                b[gl[v]] += fvals[Index(v)];
            accumulate(x, b);
        }
    }
    return { std::sqrt(sum_err / std::max(sum_data, 1e-300)), worst };
}

CellIntegration integrate_harmonic(const std::vector<Vec3>& nodes,
    const std::vector<std::vector<Index>>& loops, const HarmonicIntegration& integration,
    const HarmonicOptions& options) {
    return HarmonicCell(nodes, loops, options).integrate(integration);
}

CellIntegration integrate_harmonic(const mesh::Mesh& mesh, Index cell,
    const HarmonicIntegration& integration, const HarmonicOptions& options) {
    try {
        return HarmonicCell(cell_geometry(mesh, cell), options).integrate(integration);
    } catch (const MeshError& e) {
        throw MeshError(cell, e.face(), e.problem());
    }
}

} // namespace polycut::basis
