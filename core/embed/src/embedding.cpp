// Weights of the embedded vertices in their cells (embedding.hpp).
#include "polycut/embed/embedding.hpp"

#include "locate.hpp"
#include "polycut/basis/cell_geometry.hpp"
#include "polycut/basis/harmonic.hpp"
#include "polycut/basis/mean_value.hpp"
#include "polycut/basis/p1.hpp"
#include "polycut/basis/q1.hpp"
#include "polycut/common/error.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <map>
#include <memory>

namespace polycut::embed {

namespace {
/// Least-squares affine fit weights: w = P (P^T P)^-1 [X; 1], P = [X_i^T 1] (#n x 4), so that
/// sum_i w_i u_i is the fit's value at X (exact for affine u).
VecX affine_fit_weights(const std::vector<Vec3>& nodes, const Vec3& X) {
    MatX P(Index(nodes.size()), 4);
    for (std::size_t i = 0; i < nodes.size(); ++i)
        P.row(Index(i)) << nodes[i].transpose(), 1.0;
    const Eigen::Vector4d x(X.x(), X.y(), X.z(), 1.0);
    return P * (P.transpose() * P).ldlt().solve(x);
}

/// The diagonal of the bounding box of a cell's nodes [m].
double cell_diagonal(const std::vector<Vec3>& nodes) {
    Vec3 lo = nodes.front(), hi = nodes.front();
    for (const Vec3& p : nodes) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    return (hi - lo).norm();
}

/// A point this close to a node, relative to the cell's diagonal, is on it.
constexpr double kOnNode = 1e-9;

/// Whether w are usable interpolation weights of X over `nodes`: finite, a partition of unity
/// that reproduces X, none beyond kMaxWeight in size (mean value and trilinear weights inside a
/// cell lie in [0, 1]; a non-convex piece's may go somewhat negative).
bool sane_weights(const std::vector<Vec3>& nodes, const Vec3& X, const VecX& w) {
    constexpr double kMaxWeight = 10;
    if (!w.allFinite() || w.size() != Eigen::Index(nodes.size()) || w.size() == 0
        || w.cwiseAbs().maxCoeff() > kMaxWeight)
        return false;
    Vec3 x = Vec3::Zero();
    for (std::size_t k = 0; k < nodes.size(); ++k)
        x += w(Eigen::Index(k)) * nodes[k];
    constexpr double kTolerance = 1e-6; // of the cell's diagonal
    return std::abs(w.sum() - 1) <= kTolerance
        && (x - X).norm() <= kTolerance * cell_diagonal(nodes);
}

/// Trilinear weights of X in the hex (VTK order), by Newton on the Q1 map.
VecX q1_weights(const std::array<Vec3, 8>& hex, const Vec3& X) {
    Vec3 xi = Vec3::Zero();
    for (int it = 0; it < 30; ++it) {
        const Vec3 r = basis::q1_map(hex, xi) - X;
        const Eigen::Matrix<double, 8, 3> g = basis::q1_reference_gradients(xi);
        Mat3 J = Mat3::Zero();
        for (int i = 0; i < 8; ++i)
            J += hex[std::size_t(i)] * g.row(i);
        const Vec3 step = J.lu().solve(r);
        xi -= step;
        if (step.norm() < 1e-14)
            break;
    }
    return basis::q1_shape(xi);
}

/// The polyhedral basis of a cell, built once per cell.
struct PolyCell {
    std::unique_ptr<basis::MeanValueCell> mvc;
    std::unique_ptr<basis::HarmonicCell> harmonic;
    void evaluate(const Vec3& X, VecX& phi) const {
        if (mvc)
            mvc->evaluate(X, phi);
        else
            harmonic->evaluate(X, phi);
    }
};
} // namespace

Embedding embed_surface(const mesh::Mesh& mesh, std::vector<Vec3> positions,
    const std::vector<std::array<Index, 3>>& triangles, basis::PolyBasis poly) {
    if (positions.empty() || triangles.empty())
        throw InputError("embedded", "the surface has no triangles");
    std::vector<std::uint32_t> ids;
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (const Index v : triangles[t]) {
            if (v < 0 || std::size_t(v) >= positions.size())
                throw InputError("embedded",
                    "triangle " + std::to_string(t) + " names vertex " + std::to_string(v) + " of "
                        + std::to_string(positions.size()));
            ids.push_back(std::uint32_t(v));
        }
    Embedding e = embed_points(mesh, std::move(positions), poly);
    e.triangles = std::move(ids);
    return e;
}

Embedding embed_points(const mesh::Mesh& mesh, std::vector<Vec3> positions, basis::PolyBasis poly) {
    return embed_points(mesh, std::move(positions), {}, poly);
}

Embedding embed_points(const mesh::Mesh& mesh, std::vector<Vec3> positions,
    const std::vector<Vec3>& probes, basis::PolyBasis poly) {
    if (!probes.empty() && probes.size() != positions.size())
        throw InputError("embedded", "probes and positions differ in number");
    if (mesh.num_cells() == 0)
        throw InputError("embedded", "the simulation mesh has no cells");
    Embedding e;
    e.rest = std::move(positions);
    const detail::CellGrid grid(mesh);
    std::map<Index, PolyCell> poly_cells;
    std::vector<Index> candidates;
    e.offsets.push_back(0);
    VecX w;
    for (std::size_t v = 0; v < e.rest.size(); ++v) {
        const Vec3& X = e.rest[v];
        const Vec3& probe = probes.empty() ? X : probes[v];
        Index cell = kNone;
        grid.candidates(probe, candidates);
        for (const Index c : candidates)
            if (grid.contains(c, probe)) {
                cell = c;
                break;
            }
        const bool inside = cell != kNone;
        if (!inside) {
            double distance = 0;
            cell = grid.nearest(probe, distance);
            ++e.outside;
            e.max_outside_distance = std::max(e.max_outside_distance, distance);
        }
        const mesh::Cell& c = mesh.cells[std::size_t(cell)];
        const std::vector<Vec3> nodes = [&] {
            std::vector<Vec3> out;
            for (const Index n : c.nodes)
                out.push_back(mesh.rest[std::size_t(n)]);
            return out;
        }();
        if (c.shape == mesh::CellShape::Tet) {
            // Barycentric coordinates are affine: exact inside and extrapolated outside.
            w = basis::p1_shape({ nodes[0], nodes[1], nodes[2], nodes[3] }, X);
        } else if (!inside) {
            w = affine_fit_weights(nodes, X);
        } else if (c.shape == mesh::CellShape::Hex && nodes.size() == 8) {
            w = q1_weights(
                { nodes[0], nodes[1], nodes[2], nodes[3], nodes[4], nodes[5], nodes[6], nodes[7] },
                X);
        } else {
            PolyCell& pc = poly_cells[cell];
            if (!pc.mvc && !pc.harmonic) {
                const basis::CellGeometry g = basis::cell_geometry(mesh, cell);
                if (poly == basis::PolyBasis::MeanValue)
                    pc.mvc = std::make_unique<basis::MeanValueCell>(g);
                else
                    pc.harmonic = std::make_unique<basis::HarmonicCell>(g);
            }
            pc.evaluate(X, w);
        }
        // A point at (or a hair off) a corner of a polyhedron, where its basis is singular (the
        // mean value coordinates of a point 1e-10 of a cell beside a corner divide by nearly
        // zero): weights that are not finite, or finite but huge and cancelling. A skin vertex
        // on a node of a cell that a cut had split came out 2e7 m away (organ_embedded, cell
        // splitting, 4 frames). A point on a node takes that node; any other point whose
        // weights are not sane takes the cell's affine fit, exact for affine motions.
        if (!sane_weights(nodes, X, w)) {
            const auto at = std::min_element(nodes.begin(), nodes.end(),
                [&X](const Vec3& a, const Vec3& b) { return (a - X).norm() < (b - X).norm(); });
            if ((*at - X).norm() <= kOnNode * cell_diagonal(nodes)) {
                w = VecX::Zero(Eigen::Index(nodes.size()));
                w(at - nodes.begin()) = 1;
            } else {
                w = affine_fit_weights(nodes, X);
            }
        }
        for (Index k = 0; k < w.size(); ++k) {
            e.nodes.push_back(c.nodes[std::size_t(k)]);
            e.weights.push_back(w(k));
        }
        e.offsets.push_back(std::uint32_t(e.nodes.size()));
        e.cells.push_back(cell);
    }
    return e;
}

void reembed(Embedding& e, const mesh::Mesh& mesh, const std::vector<std::uint32_t>& vertices,
    basis::PolyBasis poly) {
    if (vertices.empty())
        return;
    std::vector<Vec3> positions, probes;
    for (const std::uint32_t v : vertices) {
        positions.push_back(e.rest[v]);
        probes.push_back(e.probes.empty() ? e.rest[v] : e.probes[v]);
    }
    const Embedding part = embed_points(mesh, std::move(positions), probes, poly);
    // New weights of the listed vertices, then the arrays rebuilt in vertex order.
    std::vector<std::uint32_t> slot(e.rest.size(), ~0u);
    for (std::size_t k = 0; k < vertices.size(); ++k)
        slot[vertices[k]] = std::uint32_t(k);
    std::vector<std::uint32_t> offsets { 0 };
    std::vector<Index> nodes;
    std::vector<double> weights;
    nodes.reserve(e.nodes.size());
    weights.reserve(e.weights.size());
    e.cells.resize(e.rest.size(), kNone);
    for (std::size_t v = 0; v < e.rest.size(); ++v) {
        if (slot[v] != ~0u) {
            const std::uint32_t k = slot[v];
            for (std::uint32_t j = part.offsets[k]; j < part.offsets[k + 1]; ++j) {
                nodes.push_back(part.nodes[j]);
                weights.push_back(part.weights[j]);
            }
            e.cells[v] = part.cells[k];
        } else if (v + 1 < e.offsets.size()) {
            for (std::uint32_t j = e.offsets[v]; j < e.offsets[v + 1]; ++j) {
                nodes.push_back(e.nodes[j]);
                weights.push_back(e.weights[j]);
            }
        }
        offsets.push_back(std::uint32_t(nodes.size()));
    }
    e.offsets = std::move(offsets);
    e.nodes = std::move(nodes);
    e.weights = std::move(weights);
    e.outside += part.outside;
    e.max_outside_distance = std::max(e.max_outside_distance, part.max_outside_distance);
}

Vec3 deformed_vertex(const Embedding& e, const std::vector<Vec3>& x, std::size_t v) {
    Vec3 p = Vec3::Zero();
    for (std::uint32_t k = e.offsets[v]; k < e.offsets[v + 1]; ++k)
        p += e.weights[k] * x[std::size_t(e.nodes[k])];
    return p;
}

void deform(const Embedding& e, const std::vector<Vec3>& x, std::vector<float>& out) {
    out.resize(3 * e.rest.size());
    for (std::size_t v = 0; v < e.rest.size(); ++v) {
        const Vec3 p = deformed_vertex(e, x, v);
        out[3 * v] = float(p.x());
        out[3 * v + 1] = float(p.y());
        out[3 * v + 2] = float(p.z());
    }
}

} // namespace polycut::embed
