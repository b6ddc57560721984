// Point location for the embedding (locate.hpp).
#include "locate.hpp"

#include "polycut/geometry/polygon.hpp"

#include <cmath>
#include <limits>

namespace polycut::embed::detail {

CellGrid::CellGrid(const mesh::Mesh& mesh)
    : m_mesh(&mesh) {
    const Index nc = mesh.num_cells();
    m_cell_lo.assign(std::size_t(nc), Vec3::Constant(std::numeric_limits<double>::infinity()));
    m_cell_hi.assign(std::size_t(nc), Vec3::Constant(-std::numeric_limits<double>::infinity()));
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    double mean_size = 0;
    for (Index c = 0; c < nc; ++c) {
        for (const Index n : mesh.cells[std::size_t(c)].nodes) {
            m_cell_lo[std::size_t(c)]
                = m_cell_lo[std::size_t(c)].cwiseMin(mesh.rest[std::size_t(n)]);
            m_cell_hi[std::size_t(c)]
                = m_cell_hi[std::size_t(c)].cwiseMax(mesh.rest[std::size_t(n)]);
        }
        lo = lo.cwiseMin(m_cell_lo[std::size_t(c)]);
        hi = hi.cwiseMax(m_cell_hi[std::size_t(c)]);
        mean_size += (m_cell_hi[std::size_t(c)] - m_cell_lo[std::size_t(c)]).maxCoeff();
    }
    mean_size /= std::max<Index>(nc, 1);
    // About one cell per bin.
    m_lo = lo;
    for (int k = 0; k < 3; ++k) {
        m_dims[k]
            = std::clamp(int(std::ceil((hi[k] - lo[k]) / std::max(mean_size, 1e-12))), 1, 256);
        m_step[k] = std::max((hi[k] - lo[k]) / m_dims[k], 1e-12);
    }
    m_bins.resize(std::size_t(m_dims.prod()));
    for (Index c = 0; c < nc; ++c) {
        const Eigen::Vector3i a = bin_of(m_cell_lo[std::size_t(c)]),
                              b = bin_of(m_cell_hi[std::size_t(c)]);
        for (int i = a.x(); i <= b.x(); ++i)
            for (int j = a.y(); j <= b.y(); ++j)
                for (int k = a.z(); k <= b.z(); ++k)
                    m_bins[std::size_t((k * m_dims.y() + j) * m_dims.x() + i)].push_back(c);
    }
}

Eigen::Vector3i CellGrid::bin_of(const Vec3& p) const {
    Eigen::Vector3i b;
    for (int k = 0; k < 3; ++k)
        b[k] = std::clamp(int(std::floor((p[k] - m_lo[k]) / m_step[k])), 0, m_dims[k] - 1);
    return b;
}

void CellGrid::candidates(const Vec3& p, std::vector<Index>& out) const {
    out.clear();
    const Eigen::Vector3i b = bin_of(p);
    for (const Index c : m_bins[std::size_t((b.z() * m_dims.y() + b.y()) * m_dims.x() + b.x())]) {
        const double pad = 1e-9 * (m_cell_hi[std::size_t(c)] - m_cell_lo[std::size_t(c)]).norm();
        if ((p.array() >= m_cell_lo[std::size_t(c)].array() - pad).all()
            && (p.array() <= m_cell_hi[std::size_t(c)].array() + pad).all())
            out.push_back(c);
    }
}

Index CellGrid::nearest(const Vec3& p, double& distance) const {
    Index best = kNone;
    distance = std::numeric_limits<double>::infinity();
    for (Index c = 0; c < Index(m_cell_lo.size()); ++c) {
        const Vec3 q = p.cwiseMax(m_cell_lo[std::size_t(c)]).cwiseMin(m_cell_hi[std::size_t(c)]);
        const double d = (p - q).norm();
        if (d < distance) {
            distance = d;
            best = c;
        }
    }
    return best;
}

bool CellGrid::contains(Index cell, const Vec3& p) const {
    const double tol = 1e-9 * (m_cell_hi[std::size_t(cell)] - m_cell_lo[std::size_t(cell)]).norm();
    for (const auto& loop : m_mesh->cell_face_loops(cell)) {
        const auto pts = geometry::gather(m_mesh->rest, loop);
        if ((p - geometry::polygon_centroid(pts)).dot(geometry::polygon_normal(pts)) > tol)
            return false;
    }
    return true;
}

} // namespace polycut::embed::detail
