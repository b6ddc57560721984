#include "polycut/cut/world_to_rest.hpp"

#include "checks.hpp"
#include "polycut/geometry/polygon.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

namespace polycut::cut {

WorldToRest::WorldToRest(const mesh::Mesh& mesh)
    : m_mesh(mesh) { }

void WorldToRest::refit_displaced(const MatX3& u) {
    std::vector<Vec3> world(m_mesh.rest.size());
    for (std::size_t i = 0; i < world.size(); ++i)
        world[i] = m_mesh.rest[i] + u.row(Eigen::Index(i)).transpose();
    refit(world);
}

void WorldToRest::copy_cell(std::size_t c) {
    const auto& nodes = m_mesh.cells[c].nodes;
    const int n = int(nodes.size());
    if (c >= m_slot.size()) {
        m_slot.resize(c + 1, 0);
        m_count.resize(c + 1, 0);
        m_room.resize(c + 1, 0);
    }
    if (n > m_room[c]) { // a new slot at the end (the old one is dropped at the next repack)
        m_slot[c] = m_pool.size();
        m_room[c] = n;
        m_pool.resize(m_pool.size() + std::size_t(n));
    }
    m_count[c] = n;
    std::copy(nodes.begin(), nodes.end(), m_pool.begin() + std::ptrdiff_t(m_slot[c]));
}

void WorldToRest::refresh_flat() {
    const std::size_t nc = m_mesh.cells.size();
    if (m_flat_ok && m_slot.size() <= nc) {
        for (std::size_t c = m_slot.size(); c < nc; ++c) // appended since
            copy_cell(c);
        std::size_t used = 0;
        for (int k : m_count)
            used += std::size_t(k);
        if (m_pool.size() <= 2 * used + 4096)
            return;
    }
    // The whole copy sized first, then filled in one pass (cell by cell it grew four arrays
    // 26k times: ~20 ms on the 5k organ, all of it in the first cut's tick).
    m_slot.resize(nc);
    m_count.resize(nc);
    m_room.resize(nc);
    std::size_t total = 0;
    for (std::size_t c = 0; c < nc; ++c) {
        const int n = int(m_mesh.cells[c].nodes.size());
        m_slot[c] = total;
        m_count[c] = m_room[c] = n;
        total += std::size_t(n);
    }
    m_pool.resize(total);
    for (std::size_t c = 0; c < nc; ++c) {
        const auto& nodes = m_mesh.cells[c].nodes;
        std::copy(nodes.begin(), nodes.end(), m_pool.begin() + std::ptrdiff_t(m_slot[c]));
    }
    m_flat_ok = true;
}

void WorldToRest::prepare() {
    refresh_flat();
}

void WorldToRest::cells_changed(std::span<const Index> changed, bool renumbered) {
    if (!m_flat_ok)
        return; // nothing copied yet: refit_near() copies the whole mesh
    if (renumbered || m_slot.size() > m_mesh.cells.size()) {
        m_flat_ok = false;
        return;
    }
    for (Index c : changed)
        if (c >= 0 && std::size_t(c) < m_slot.size())
            copy_cell(std::size_t(c));
}

bool WorldToRest::refit_near(
    std::span<const Vec3> world, const geometry::Aabb& region, std::size_t max_cells) {
    refresh_flat();
    if (detail::incremental_checks())
        for (std::size_t c = 0; c < m_mesh.cells.size(); ++c) {
            const auto& nodes = m_mesh.cells[c].nodes;
            if (!std::equal(nodes.begin(), nodes.end(), m_pool.begin() + std::ptrdiff_t(m_slot[c]),
                    m_pool.begin() + std::ptrdiff_t(m_slot[c]) + m_count[c]))
                throw std::logic_error("WorldToRest: the flat node lists differ from the mesh "
                                       "at cell "
                    + std::to_string(c) + " (cells_changed() missed)");
        }
    m_near.clear();
    const Index* pool = m_pool.data();
    for (std::size_t c = 0; c < m_slot.size(); ++c) {
        geometry::Aabb box;
        const Index* p = pool + m_slot[c];
        for (int k = 0; k < m_count[c]; ++k)
            box.extend(world[std::size_t(p[k])]);
        if (box.overlaps(region))
            m_near.emplace_back(Index(c), box);
    }
    if (m_near.size() > max_cells) {
        m_near.clear();
        refit(world, false);
        return false;
    }
    m_near_only = true;
    m_bucket_start.clear(); // the grid is stale: map_point() and locate() need refit()
    return true;
}

void WorldToRest::refit(std::span<const Vec3> world, bool with_fits) {
    m_near_only = false;
    // O(mesh) but allocation-free after the first call: the grid is called once per cut.
    m_world.assign(world.begin(), world.end());
    const std::size_t nc = m_mesh.cells.size();
    m_fit.assign(with_fits ? nc : 0, {});
    m_inverse.assign(with_fits ? nc : 0, Mat3::Identity());
    m_box.assign(nc, {});
    m_all = {};
    std::vector<Vec3> X, x;
    for (std::size_t c = 0; c < nc; ++c) {
        geometry::Aabb& box = m_box[c];
        for (Index n : m_mesh.cells[c].nodes)
            box.extend(m_world[std::size_t(n)]);
        m_all.extend(box);
        if (!with_fits)
            continue;
        X.clear();
        x.clear();
        for (Index n : m_mesh.cells[c].nodes) {
            X.push_back(m_mesh.rest[std::size_t(n)]);
            x.push_back(m_world[std::size_t(n)]);
        }
        m_fit[c] = geometry::fit_affine(X, x);
        const double det = m_fit[c].A.determinant();
        m_inverse[c] = std::abs(det) > 1e-12 ? Mat3(m_fit[c].A.inverse()) : Mat3::Identity();
    }
    // Uniform grid with about one bucket per cell, stored compressed (bucket b holds
    // m_bucket_cells[m_bucket_start[b] .. m_bucket_start[b + 1]]): counted, then filled.
    const Vec3 ext = m_all.empty() ? Vec3::Ones() : Vec3(m_all.extent().cwiseMax(1e-12));
    const double h = std::cbrt(ext.prod() / double(std::max<std::size_t>(nc, 1)));
    for (int k = 0; k < 3; ++k)
        m_dims[k] = std::clamp(int(std::ceil(ext[k] / h)), 1, 256);
    m_step = ext.cwiseQuotient(m_dims.cast<double>());
    const std::size_t nb = std::size_t(m_dims.prod());
    m_bucket_start.assign(nb + 1, 0);
    auto each_bucket = [&](std::size_t c, auto&& f) {
        const auto lo = bucket(m_box[c].lo), hi = bucket(m_box[c].hi);
        for (int k = lo.z(); k <= hi.z(); ++k)
            for (int j = lo.y(); j <= hi.y(); ++j)
                for (int i = lo.x(); i <= hi.x(); ++i)
                    f(std::size_t(i + m_dims.x() * (j + m_dims.y() * k)));
    };
    for (std::size_t c = 0; c < nc; ++c)
        each_bucket(c, [&](std::size_t b) { ++m_bucket_start[b + 1]; });
    for (std::size_t b = 0; b < nb; ++b)
        m_bucket_start[b + 1] += m_bucket_start[b];
    m_bucket_cells.resize(std::size_t(m_bucket_start[nb]));
    m_fill.assign(m_bucket_start.begin(), m_bucket_start.end() - 1);
    for (std::size_t c = 0; c < nc; ++c)
        each_bucket(c, [&](std::size_t b) { m_bucket_cells[std::size_t(m_fill[b]++)] = Index(c); });
}

Eigen::Vector3i WorldToRest::bucket(const Vec3& x) const {
    Eigen::Vector3i b;
    for (int k = 0; k < 3; ++k)
        b[k] = std::clamp(int(std::floor((x[k] - m_all.lo[k]) / m_step[k])), 0, m_dims[k] - 1);
    return b;
}

std::vector<Index> WorldToRest::candidates(const geometry::Aabb& box) const {
    std::vector<Index> out;
    if (m_near_only) {
        for (const auto& [c, cell_box] : m_near)
            if (cell_box.overlaps(box))
                out.push_back(c);
        return out;
    }
    if (m_bucket_start.size() < 2 || !box.overlaps(m_all))
        return out;
    const auto lo = bucket(box.lo), hi = bucket(box.hi);
    for (int k = lo.z(); k <= hi.z(); ++k)
        for (int j = lo.y(); j <= hi.y(); ++j)
            for (int i = lo.x(); i <= hi.x(); ++i) {
                const std::size_t b = std::size_t(i + m_dims.x() * (j + m_dims.y() * k));
                for (Index e = m_bucket_start[b]; e < m_bucket_start[b + 1]; ++e)
                    if (const Index c = m_bucket_cells[std::size_t(e)];
                        m_box[std::size_t(c)].overlaps(box))
                        out.push_back(c);
            }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

double WorldToRest::depth_outside(Index c, const Vec3& X) const {
    // Largest signed distance of X outside the cell's face planes (<= 0 inside a convex cell).
    double worst = -std::numeric_limits<double>::infinity();
    for (Index f : m_mesh.cells[std::size_t(c)].faces) {
        const auto pts = geometry::gather(m_mesh.rest, m_mesh.face_loop(f, c));
        worst = std::max(
            worst, (X - geometry::polygon_centroid(pts)).dot(geometry::polygon_normal(pts)));
    }
    return worst;
}

Index WorldToRest::locate(const Vec3& x) const {
    geometry::Aabb box;
    box.extend(x);
    Index best = kNone;
    double best_depth = std::numeric_limits<double>::infinity();
    for (Index c : candidates(box)) {
        const Vec3 X = m_inverse[std::size_t(c)] * (x - m_fit[std::size_t(c)].t);
        const double d = depth_outside(c, X);
        if (d < best_depth) {
            best_depth = d;
            best = c;
        }
    }
    if (best != kNone)
        return best;
    // Outside every deformed box: the cell with the nearest deformed box.
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t c = 0; c < m_box.size(); ++c) {
        const Vec3 d = (m_box[c].lo - x).cwiseMax(x - m_box[c].hi).cwiseMax(0.0);
        if (d.norm() < nearest) {
            nearest = d.norm();
            best = Index(c);
        }
    }
    return best;
}

Vec3 WorldToRest::map_point(const Vec3& x) const {
    const Index c = locate(x);
    if (c == kNone)
        return x;
    return m_inverse[std::size_t(c)] * (x - m_fit[std::size_t(c)].t);
}

std::optional<Triangle> WorldToRest::fit_triangle(
    const Triangle& w, std::span<const Vec3> world, double max_edge) const {
    const double longest
        = std::max({ (w[1] - w[0]).norm(), (w[2] - w[1]).norm(), (w[0] - w[2]).norm() });
    const int n = std::clamp(max_edge > 0 ? int(std::ceil(longest / max_edge)) : 2, 2, 16);
    // A point counts as inside a cell within this fraction of the cell's rest size (the
    // piecewise fits of neighbouring polyhedra leave hairline gaps between them).
    constexpr double kInside = 1e-3;
    // Per cell met: the inverse of its affine fit and the fit's translation, or nothing when
    // its nodes do not span 3D.
    std::map<Index, std::optional<std::pair<Mat3, Vec3>>> fits;
    const auto fit_of = [&](Index c) -> const std::optional<std::pair<Mat3, Vec3>>& {
        const auto [it, fresh] = fits.try_emplace(c);
        if (!fresh)
            return it->second;
        std::vector<Vec3> X, x;
        for (Index v : m_mesh.cells[std::size_t(c)].nodes) {
            X.push_back(m_mesh.rest[std::size_t(v)]);
            x.push_back(world[std::size_t(v)]);
        }
        const geometry::AffineFit fit = geometry::fit_affine(X, x);
        if (fit.ok && std::abs(fit.A.determinant()) > 1e-12)
            it->second.emplace(fit.A.inverse(), fit.t);
        return it->second;
    };
    // Least squares X(u, v) = X0 + u E1 + v E2 over the lattice points inside the tissue.
    Eigen::Matrix3d N = Eigen::Matrix3d::Zero(); // sum of p p^T, p = (1, u, v)
    Eigen::Matrix3d B = Eigen::Matrix3d::Zero(); // sum of p X^T
    int inside = 0;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i + j <= n; ++i) {
            const double u = double(i) / n, v = double(j) / n;
            const Vec3 x = (1 - u - v) * w[0] + u * w[1] + v * w[2];
            geometry::Aabb box;
            box.extend(x);
            double best = std::numeric_limits<double>::infinity();
            Index best_cell = kNone;
            Vec3 image = Vec3::Zero();
            for (Index c : candidates(box)) {
                const auto& f = fit_of(c);
                if (!f)
                    continue;
                const Vec3 X = f->first * (x - f->second);
                const double d = depth_outside(c, X);
                if (d < best) {
                    best = d;
                    best_cell = c;
                    image = X;
                }
            }
            if (best_cell == kNone)
                continue;
            geometry::Aabb rest_box;
            for (Index node : m_mesh.cells[std::size_t(best_cell)].nodes)
                rest_box.extend(m_mesh.rest[std::size_t(node)]);
            if (!(best <= kInside * rest_box.diagonal()))
                continue;
            const Eigen::Vector3d p(1, u, v);
            N += p * p.transpose();
            B += p * image.transpose();
            ++inside;
        }
    if (inside < 3)
        return std::nullopt;
    // The points inside must span the triangle's parameters in both directions (the whole
    // triangle's (u, v) have variances 1/18 and covariance -1/36): a sliver of them along an
    // edge would extrapolate the rest of the triangle from a line.
    constexpr double kMinSpread = 1e-3;
    const Eigen::Vector2d mean = N.block<2, 1>(1, 0) / N(0, 0);
    const Eigen::Matrix2d cov = N.block<2, 2>(1, 1) / N(0, 0) - mean * mean.transpose();
    if (!(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues().minCoeff()
            >= kMinSpread))
        return std::nullopt;
    const Eigen::Matrix3d C = N.ldlt().solve(B); // rows: X0, E1, E2
    const Vec3 X0 = C.row(0).transpose(), E1 = C.row(1).transpose(), E2 = C.row(2).transpose();
    return Triangle { X0, X0 + E1, X0 + E2 };
}

std::vector<Triangle> WorldToRest::map_triangle(const Triangle& w, double max_edge) const {
    int n = 1;
    if (max_edge > 0) {
        const double longest
            = std::max({ (w[1] - w[0]).norm(), (w[2] - w[1]).norm(), (w[0] - w[2]).norm() });
        n = std::clamp(int(std::ceil(longest / max_edge)), 1, 64);
    }
    // Barycentric lattice points (i, j) with i + j <= n, mapped once each.
    std::vector<Vec3> mapped(std::size_t((n + 1) * (n + 2) / 2));
    auto id = [n](int i, int j) { return std::size_t(j * (n + 1) - j * (j - 1) / 2 + i); };
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i + j <= n; ++i) {
            const double a = double(i) / n, b = double(j) / n;
            mapped[id(i, j)] = map_point((1 - a - b) * w[0] + a * w[1] + b * w[2]);
        }
    std::vector<Triangle> out;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i + j < n; ++i) {
            out.push_back({ mapped[id(i, j)], mapped[id(i + 1, j)], mapped[id(i, j + 1)] });
            if (i + j + 1 < n)
                out.push_back(
                    { mapped[id(i + 1, j)], mapped[id(i + 1, j + 1)], mapped[id(i, j + 1)] });
        }
    return out;
}

} // namespace polycut::cut
