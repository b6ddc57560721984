// sim::Simulation::sample_displacements, model_stats and energy: the displacement field at many
// rest points (a trade study compares runs on different meshes as fields, issue 17 item 1), the
// sizes of what the scene built, and the energy the extremes tests watch (item 4).
#include "impl.hpp"
#include "polycut/geometry/affine_fit.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace polycut::sim {

namespace {

/// Uniform grid of cell bounds: the cells whose rest box holds a point, without a scan of
/// the mesh per point.
class CellGrid {
public:
    explicit CellGrid(const std::vector<geometry::Aabb>& boxes) {
        for (const auto& b : boxes)
            m_all.extend(b);
        const double cells = std::max<double>(1.0, double(boxes.size()));
        const Vec3 size = (m_all.hi - m_all.lo).cwiseMax(1e-12);
        // About one cell per grid bucket.
        const double h = std::cbrt(size.prod() / cells);
        for (int a = 0; a < 3; ++a)
            m_n[a] = std::clamp(int(std::ceil(size[a] / h)), 1, 256);
        m_h = size.cwiseQuotient(Vec3(m_n[0], m_n[1], m_n[2]));
        m_bucket.assign(std::size_t(m_n[0]) * std::size_t(m_n[1]) * std::size_t(m_n[2]), {});
        for (std::size_t c = 0; c < boxes.size(); ++c) {
            if (boxes[c].empty())
                continue;
            const auto lo = index(boxes[c].lo), hi = index(boxes[c].hi);
            for (int k = lo[2]; k <= hi[2]; ++k)
                for (int j = lo[1]; j <= hi[1]; ++j)
                    for (int i = lo[0]; i <= hi[0]; ++i)
                        m_bucket[flat(i, j, k)].push_back(Index(c));
        }
    }
    /// Cells whose bucket holds X (empty outside the mesh's bounds).
    const std::vector<Index>& candidates(const Vec3& X) const {
        static const std::vector<Index> kNoCells;
        if (((X - m_all.lo).array() < -1e-9 * m_all.diagonal()).any()
            || ((X - m_all.hi).array() > 1e-9 * m_all.diagonal()).any())
            return kNoCells;
        const auto i = index(X);
        return m_bucket[flat(i[0], i[1], i[2])];
    }

private:
    std::array<int, 3> index(const Vec3& X) const {
        std::array<int, 3> out {};
        for (int a = 0; a < 3; ++a)
            out[std::size_t(a)]
                = std::clamp(int(std::floor((X[a] - m_all.lo[a]) / m_h[a])), 0, m_n[a] - 1);
        return out;
    }
    std::size_t flat(int i, int j, int k) const {
        return (std::size_t(k) * std::size_t(m_n[1]) + std::size_t(j)) * std::size_t(m_n[0])
            + std::size_t(i);
    }
    geometry::Aabb m_all;
    int m_n[3] = { 1, 1, 1 };
    Vec3 m_h = Vec3::Ones();
    std::vector<std::vector<Index>> m_bucket;
};

} // namespace

void Simulation::sample_displacements(const std::vector<Vec3>& points, std::vector<Vec3>& u,
    std::vector<std::uint8_t>& inside) const {
    const Impl& s = *m_impl;
    const mesh::Mesh& m = s.mesh;
    u.assign(points.size(), Vec3::Zero());
    inside.assign(points.size(), 0);
    std::vector<geometry::Aabb> boxes(std::size_t(m.num_cells()));
    for (Index c = 0; c < m.num_cells(); ++c)
        for (Index n : m.cells[std::size_t(c)].nodes)
            boxes[std::size_t(c)].extend(m.rest[std::size_t(n)]);
    const CellGrid grid(boxes);
    geometry::Aabb all;
    for (const auto& b : boxes)
        all.extend(b);
    const double eps = 1e-9 * all.diagonal();
    auto disp = [&](Index n) { return Vec3(s.positions[std::size_t(n)] - m.rest[std::size_t(n)]); };
    for (std::size_t p = 0; p < points.size(); ++p) {
        const Vec3& X = points[p];
        for (Index c : grid.candidates(X)) {
            const geometry::Aabb& b = boxes[std::size_t(c)];
            if (((X - b.lo).array() < -eps).any() || ((X - b.hi).array() > eps).any())
                continue;
            const mesh::Cell& cell = m.cells[std::size_t(c)];
            if (s.dg && cell.shape == mesh::CellShape::Tet) {
                // DG: the cell's own polynomial field (a tet's barycentric test first).
                const auto& n = cell.nodes;
                const Vec3& a = m.rest[std::size_t(n[0])];
                Mat3 T;
                T << m.rest[std::size_t(n[1])] - a, m.rest[std::size_t(n[2])] - a,
                    m.rest[std::size_t(n[3])] - a;
                const Vec3 l = T.lu().solve(X - a);
                if (!(1.0 - l.sum() >= -1e-9 && (l.array() >= -1e-9).all()))
                    continue;
                u[p] = s.dg->model->displacement(s.state.x, c, X);
                inside[p] = 1;
                break;
            }
            if (cell.shape == mesh::CellShape::Tet) {
                // P1 interpolation, exact for the tet's field.
                const auto& n = cell.nodes;
                const Vec3& a = m.rest[std::size_t(n[0])];
                Mat3 T;
                T << m.rest[std::size_t(n[1])] - a, m.rest[std::size_t(n[2])] - a,
                    m.rest[std::size_t(n[3])] - a;
                const Vec3 l = T.lu().solve(X - a);
                const double l0 = 1.0 - l.sum();
                if (!(l0 >= -1e-9 && (l.array() >= -1e-9).all()))
                    continue;
                u[p] = l0 * disp(n[0]) + l.x() * disp(n[1]) + l.y() * disp(n[2])
                    + l.z() * disp(n[3]);
                inside[p] = 1;
                break;
            }
            // Inside all face planes (convex cells, cut cells of the polyhedral methods), or
            // else inside by the winding number (non-convex cells: hex_slice, merged slivers);
            // the field is read from the cell's affine fit.
            const auto loops = m.cell_face_loops(c);
            bool in = true;
            for (const auto& loop : loops) {
                const auto pts = geometry::gather(m.rest, loop);
                if ((X - geometry::polygon_centroid(pts)).dot(geometry::polygon_normal(pts))
                    > eps) {
                    in = false;
                    break;
                }
            }
            if (!in && cell.shape == mesh::CellShape::Polyhedron)
                in = geometry::polyhedron_winding(m.rest, loops, X) > 0.45;
            if (!in)
                continue;
            if (s.dg) {
                u[p] = s.dg->model->displacement(s.state.x, c, X); // the cell's DG field
                inside[p] = 1;
                break;
            }
            const auto rest = geometry::gather(m.rest, cell.nodes);
            const auto world = geometry::gather(s.positions, cell.nodes);
            const geometry::AffineFit fit = geometry::fit_affine(rest, world);
            u[p] = fit.A * X + fit.t - X;
            inside[p] = 1;
            break;
        }
    }
}

Energy Simulation::energy() const {
    return m_impl->energy();
}

Energy Simulation::Impl::energy() const {
    const Impl& s = *this;
    Energy e;
    const elasticity::Model& stepped
        = s.dg ? static_cast<const elasticity::Model&>(*s.dg->model) : *s.model;
    const VecX& m = stepped.row_mass();
    const Vec3 g = s.scene.loads.gravity;
    for (Index i = 0; i < Index(s.state.x.rows()) && i < Index(m.size()); ++i)
        e.kinetic += 0.5 * m(i) * s.state.v.row(i).squaredNorm();
    // -G . (x - X0), G the model's gravity load (for DG it acts on each cell's mean only).
    VecX load = VecX::Zero(3 * stepped.num_rows());
    stepped.add_gravity(g, load);
    MatX3 X0;
    stepped.rest_rows(X0);
    if (X0.rows() == s.state.x.rows()) {
        const MatX3 u = s.state.x - X0;
        e.gravity = -load.dot(flat(u));
    }
    e.elastic = stepped.elastic_energy(s.state.x,
        s.scene.integrator.corotated ? elasticity::ForceMode::Corotated
                                     : elasticity::ForceMode::Linear);
    return e;
}

ModelStats Simulation::model_stats() const {
    const Impl& s = *m_impl;
    ModelStats st;
    std::vector<std::uint8_t> used(s.mesh.rest.size(), 0);
    for (const mesh::Cell& c : s.mesh.cells)
        for (Index n : c.nodes)
            used[std::size_t(n)] = 1;
    st.dofs = 3 * Index(std::count(used.begin(), used.end(), std::uint8_t(1)));
    if (s.dg) {
        st.dofs = 3 * s.dg->model->num_coefficients(); // DG: DOFs are per cell, not per node
        st.free_dofs = s.dg->model->num_free_dofs();
        st.nonzeros = Index(s.dg->model->make_matrix().nonZeros());
    } else {
        st.free_dofs = s.model->num_free_dofs();
        st.nonzeros = Index(s.model->make_matrix().nonZeros());
    }
    for (const mesh::Cell& c : s.mesh.cells) {
        st.tets += c.shape == mesh::CellShape::Tet ? 1 : 0;
        st.hexes += c.shape == mesh::CellShape::Hex ? 1 : 0;
        st.polyhedra += c.shape == mesh::CellShape::Polyhedron ? 1 : 0;
    }
    return st;
}

} // namespace polycut::sim
