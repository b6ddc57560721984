// sim::Simulation queries: surface, probes, mesh figures, state hash, VTU output.
#include "cell_stress.hpp"
#include "impl.hpp"
#include "polycut/common/error.hpp"
#include "polycut/cut/completeness.hpp"
#include "polycut/embed/embedding.hpp"
#include "polycut/geometry/affine_fit.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "polycut/mesh/io_vtu.hpp"
#include "polycut/mesh/validate.hpp"
#include "setup.hpp"

#include <Eigen/Dense>
#include <cstring>

namespace polycut::sim {

Surface Simulation::surface() const {
    Surface out;
    if (m_impl->embedded_current()) {
        m_impl->embedded_surface(out);
        return out;
    }
    out.topology_version = m_impl->topology_version;
    surface::gather_positions(m_impl->topology, m_impl->positions, out.positions);
    out.triangles = m_impl->topology.triangles;
    out.tags = m_impl->topology.tags;
    return out;
}

void Simulation::surface_positions(std::vector<float>& out) const {
    if (m_impl->embedded_current())
        return m_impl->embedded_positions(out);
    surface::gather_positions(m_impl->topology, m_impl->positions, out);
}

std::uint64_t Simulation::topology_version() const {
    return m_impl->topology_version;
}

const std::vector<Vec3>& Simulation::positions() const {
    return m_impl->positions;
}

namespace {
/// Barycentric coordinates of X in the tet (a, b, c, d).
Eigen::Vector4d barycentric(
    const Vec3& X, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    Mat3 T;
    T << b - a, c - a, d - a;
    const Vec3 l = T.lu().solve(X - a);
    return { 1.0 - l.sum(), l.x(), l.y(), l.z() };
}
} // namespace

Vec3 Simulation::probe_displacement(const std::string& name) const {
    const Impl& s = *m_impl;
    const scene::Probe* probe = nullptr;
    for (const auto& p : s.scene.probes)
        if (p.name == name)
            probe = &p;
    if (!probe)
        throw InputError("probe", "no probe named \"" + name + "\"");
    const Vec3& X = probe->point;
    if (s.dg)
        return dg_point_displacement(*s.dg, s.state.x, X); // stitched node or MLS (003 sec. 8)
    const mesh::Mesh& m = s.mesh;
    auto u = [&](Index n) { return Vec3(s.positions[std::size_t(n)] - m.rest[std::size_t(n)]); };
    // 1. A node at the probe: its displacement, exactly.
    const Index near = nearest_node(m, X);
    geometry::Aabb box;
    for (const Vec3& p : m.rest)
        box.extend(p);
    const double eps = 1e-9 * box.diagonal();
    if (near != kNone && (m.rest[std::size_t(near)] - X).norm() <= eps)
        return u(near);
    // 2. The cell containing the probe: P1 interpolation in a tet, the cell's affine fit else.
    for (Index c = 0; c < m.num_cells(); ++c) {
        const mesh::Cell& cell = m.cells[std::size_t(c)];
        if (cell.shape == mesh::CellShape::Tet) {
            const auto& n = cell.nodes;
            const Eigen::Vector4d l = barycentric(X, m.rest[std::size_t(n[0])],
                m.rest[std::size_t(n[1])], m.rest[std::size_t(n[2])], m.rest[std::size_t(n[3])]);
            if ((l.array() >= -1e-9).all()) {
                Vec3 out = Vec3::Zero();
                for (int k = 0; k < 4; ++k)
                    out += l[k] * u(n[std::size_t(k)]);
                return out;
            }
            continue;
        }
        const auto loops = m.cell_face_loops(c);
        bool inside = true;
        for (const auto& loop : loops) {
            const auto pts = geometry::gather(m.rest, loop);
            if ((X - geometry::polygon_centroid(pts)).dot(geometry::polygon_normal(pts)) > eps) {
                inside = false;
                break;
            }
        }
        if (!inside)
            continue;
        const auto rest = geometry::gather(m.rest, cell.nodes);
        const auto world = geometry::gather(s.positions, cell.nodes);
        const geometry::AffineFit fit = geometry::fit_affine(rest, world);
        return fit.A * X + fit.t - X;
    }
    // 3. Outside the tissue (e.g. cut away): the nearest node.
    return near != kNone ? u(near) : Vec3::Zero();
}

Index Simulation::cell_count() const {
    return m_impl->mesh.num_cells();
}

MeshStats Simulation::mesh_stats() const {
    const mesh::Mesh& m = m_impl->mesh;
    MeshStats st;
    st.nodes = m.num_nodes();
    st.cells = m.num_cells();
    st.boundary_triangles = Index(m_impl->topology.tags.size());
    st.rest_volume = m.rest_volume();
    st.components = m.count_components();
    st.surface_closed = mesh::check_boundary_surface(m).ok();
    const CutAreas a = cut_areas();
    st.cut_area = a.cut_area;
    st.swept_area = a.swept_area;
    st.swept_area_undone = a.swept_area_undone;
    if (m_impl->initial_element_cost > 0)
        st.model_growth = element_cost(m) / m_impl->initial_element_cost;
    return st;
}

CutAreas Simulation::cut_areas() const {
    return { cut::cut_face_area(m_impl->mesh), m_impl->swept_area, m_impl->swept_area_undone };
}

const MeshingSummary& Simulation::meshing_summary() const {
    return m_impl->meshing;
}

std::uint64_t Simulation::state_hash() const {
    // FNV-1a over positions, velocities and the topology counts.
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&](const void* data, std::size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < bytes; ++i) {
            h ^= p[i];
            h *= 1099511628211ull;
        }
    };
    const auto& st = m_impl->state;
    mix(st.x.data(), std::size_t(st.x.size()) * sizeof(double));
    mix(st.v.data(), std::size_t(st.v.size()) * sizeof(double));
    const Index counts[3]
        = { m_impl->mesh.num_nodes(), m_impl->mesh.num_cells(), m_impl->mesh.num_faces() };
    mix(counts, sizeof counts);
    return h;
}

void Simulation::write_vtu(const std::string& path) const {
    const Impl& s = *m_impl;
    const mesh::Mesh& m = s.mesh;
    mesh::Field disp { "displacement", MatX(m.num_nodes(), 3) };
    mesh::Field vel { "velocity", MatX::Zero(m.num_nodes(), 3) };
    mesh::Field node_cut { "cut", MatX::Zero(m.num_nodes(), 1) };
    for (Index i = 0; i < m.num_nodes(); ++i)
        disp.values.row(i) = (s.positions[std::size_t(i)] - m.rest[std::size_t(i)]).transpose();
    if (s.state.v.rows() == m.num_nodes()) // static scenes keep no velocity
        vel.values = s.state.v;
    // Cauchy stress of each cell from the rotation-free part of its affine fit [Pa] (small
    // strain, rotated back to world space), and its von Mises value [Pa].
    const auto mat = elasticity_material(s.scene);
    mesh::Field stress { "stress", MatX(m.num_cells(), 9) };
    mesh::Field vm { "von_mises", MatX(m.num_cells(), 1) };
    mesh::Field cell_cut { "cut", MatX::Zero(m.num_cells(), 1) };
    for (Index c = 0; c < m.num_cells(); ++c) {
        const auto& cell = m.cells[std::size_t(c)];
        Mat3 R;
        const Mat3 sigma = cell_stress(mat, s.scene.integrator.corotated, m, s.positions, c, &R);
        const Mat3 dev = sigma - sigma.trace() / 3.0 * Mat3::Identity();
        vm.values(c, 0) = std::sqrt(1.5 * dev.squaredNorm());
        const Mat3 world = R * sigma * R.transpose();
        for (int k = 0; k < 9; ++k)
            stress.values(c, k) = world(k / 3, k % 3); // row-major, as VTK's 9-component tensors
        // The cut tag: how many of the cell's faces lie on a cut surface; their nodes get 1.
        for (const Index f : cell.faces) {
            const auto& face = m.faces[std::size_t(f)];
            if (face.tag != mesh::FaceTag::Cut)
                continue;
            cell_cut.values(c, 0) += 1;
            for (const Index n : face.nodes)
                node_cut.values(n, 0) = 1;
        }
    }
    mesh::write_vtu(path, m, &s.positions, { disp, vel, node_cut }, { stress, vm, cell_cut });
}

} // namespace polycut::sim
