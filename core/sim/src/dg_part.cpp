// The DG side of sim::Simulation (dg_part.hpp).
#include "dg_part.hpp"

#include "polycut/common/error.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "setup.hpp"

#include <Eigen/Dense>
#include <algorithm>

namespace polycut::sim {

dg::DgOptions dg_options(const scene::Scene& s) {
    dg::DgOptions o;
    o.degree = s.basis.degree;
    o.flux = s.dg.flux == "bz" ? dg::Flux::BabuskaZlamal : dg::Flux::InteriorPenalty;
    o.penalty = s.dg.penalty;
    o.dirichlet_penalty = s.dg.dirichlet_penalty;
    o.lambda_penalty
        = s.dg.lambda_penalty == "normal" ? dg::LambdaPenalty::Normal : dg::LambdaPenalty::Full;
    return o;
}

namespace {
/// Whether the region selects every node of a boundary face.
bool face_selected(const scene::Selector& where, const mesh::Mesh& m, const mesh::Face& face) {
    return std::all_of(face.nodes.begin(), face.nodes.end(),
        [&](Index n) { return scene::selects(where, m.rest[std::size_t(n)]); });
}
} // namespace

DgDirichlet dg_dirichlet_faces(const scene::Scene& s, const mesh::Mesh& m) {
    DgDirichlet out;
    for (std::size_t i = 0; i < s.fixed.size(); ++i) {
        const scene::Fixed& fx = s.fixed[i];
        const std::string where = "/fixed/" + std::to_string(i);
        if (fx.at_node)
            throw SceneError(where,
                "method \"dg\" imposes fixed regions weakly on boundary faces; a single node "
                "cannot be fixed (select a region)");
        const std::uint8_t axes = std::uint8_t(
            (fx.components[0] ? 1 : 0) | (fx.components[1] ? 2 : 0) | (fx.components[2] ? 4 : 0));
        Index count = 0;
        for (Index f = 0; f < m.num_faces(); ++f) {
            const mesh::Face& face = m.faces[std::size_t(f)];
            if (face.boundary() && face_selected(fx.where, m, face)) {
                out.faces.push_back(f);
                out.axes.push_back(axes);
                ++count;
            }
        }
        if (count == 0)
            throw SceneError(where,
                "selects no boundary face of the mesh (method \"dg\" fixes the boundary faces "
                "whose nodes the region selects)");
    }
    return out;
}

namespace {
VecX dg_scene_loads(const scene::Scene& s, const mesh::Mesh& m, const dg::DgModel& model,
    const dg::Stitching& stitching) {
    VecX out = VecX::Zero(3 * model.num_coefficients());
    // Point and uniform forces act on nodes: through the stitching's adjoint.
    scene::Scene nodal = s;
    nodal.loads.forces.clear();
    nodal.loads.pressures.clear();
    for (const scene::Force& f : s.loads.forces)
        if (f.kind == scene::Force::Kind::Point || f.distribution == "uniform")
            nodal.loads.forces.push_back(f);
    if (!nodal.loads.forces.empty()) {
        VecX c;
        stitching.loads(scene_loads(nodal, m), c);
        out += c;
    }
    // Area forces: a uniform traction F / A on the selected boundary faces; pressures: -p n.
    for (std::size_t i = 0; i < s.loads.forces.size(); ++i) {
        const scene::Force& f = s.loads.forces[i];
        if (f.kind == scene::Force::Kind::Point || f.distribution == "uniform")
            continue;
        std::vector<Index> faces;
        double area = 0;
        for (Index k = 0; k < m.num_faces(); ++k) {
            const mesh::Face& face = m.faces[std::size_t(k)];
            if (!face.boundary() || !face_selected(f.region, m, face))
                continue;
            faces.push_back(k);
            area += geometry::polygon_area(geometry::gather(m.rest, face.nodes));
        }
        if (!(area > 0))
            throw SceneError("/loads/forces/" + std::to_string(i),
                "selects no boundary face of the mesh (\"area\" distribution)");
        out += model.traction_load(faces, f.force / area);
    }
    for (std::size_t i = 0; i < s.loads.pressures.size(); ++i) {
        const scene::Pressure& pr = s.loads.pressures[i];
        long count = 0;
        for (Index k = 0; k < m.num_faces(); ++k) {
            const mesh::Face& face = m.faces[std::size_t(k)];
            if (!face.boundary() || !face_selected(pr.region, m, face))
                continue;
            ++count;
            const Vec3 n = geometry::polygon_normal(geometry::gather(m.rest, face.nodes));
            out += model.traction_load({ k }, -pr.pressure * n);
        }
        if (count == 0)
            throw SceneError(
                "/loads/pressure/" + std::to_string(i), "selects no boundary face of the mesh");
    }
    return out;
}
} // namespace

std::unique_ptr<DgPart> make_dg_part(const scene::Scene& s, const mesh::Mesh& m) {
    auto part = std::make_unique<DgPart>();
    DgDirichlet fixed = dg_dirichlet_faces(s, m);
    part->model = std::make_unique<dg::DgModel>(
        m, elasticity_material(s), dg_options(s), std::move(fixed.faces), std::move(fixed.axes));
    part->stitching = std::make_unique<dg::Stitching>(*part->model);
    part->scene_load = dg_scene_loads(s, m, *part->model, *part->stitching);
    return part;
}

namespace {

/// Rest points that determine a polynomial of degree <= 2 on a cell: its nodes, the midpoints
/// of all node pairs and its centroid.
std::vector<Vec3> fit_points(const mesh::Mesh& m, Index c, const Vec3& centroid) {
    const auto& nodes = m.cells[std::size_t(c)].nodes;
    std::vector<Vec3> pts;
    for (std::size_t a = 0; a < nodes.size(); ++a) {
        pts.push_back(m.rest[std::size_t(nodes[a])]);
        for (std::size_t b = a + 1; b < nodes.size(); ++b)
            pts.push_back(0.5 * (m.rest[std::size_t(nodes[a])] + m.rest[std::size_t(nodes[b])]));
    }
    pts.push_back(centroid);
    return pts;
}

/// Rows (nb x 3) of the field `rows_old` of old cell `o`, re-expressed on new cell c's basis.
MatX3 refit(const dg::DgModel& old_model, const MatX3& field_old, Index o,
    const dg::DgModel& new_model, const mesh::Mesh& m, Index c) {
    const dg::CellBasis& bo = old_model.basis(o);
    const dg::CellBasis& bn = new_model.basis(c);
    const std::vector<Vec3> pts = fit_points(m, c, bn.center);
    MatX Phi(Index(pts.size()), bn.size());
    MatX U(Index(pts.size()), 3);
    const auto rows_o = field_old.middleRows(old_model.offset(o), bo.size());
    for (std::size_t k = 0; k < pts.size(); ++k) {
        Phi.row(Index(k)) = bn.values(pts[k]).transpose();
        U.row(Index(k)) = bo.values(pts[k]).transpose() * rows_o;
    }
    return Phi.colPivHouseholderQr().solve(U);
}

} // namespace

std::unique_ptr<DgPart> dg_after_cut(const DgPart& old, const scene::Scene& s, const mesh::Mesh& m,
    const cut::CutReport& report, MatX3& x, MatX3& v) {
    const dg::DgModel& om = *old.model;
    // Source (old id) of every cell of the edited mesh.
    const Index n_cells = m.num_cells();
    std::vector<Index> source(std::size_t(n_cells), kNone);
    if (report.cell_map.empty()) {
        for (Index c = 0; c < std::min(n_cells, report.cells_before); ++c)
            source[std::size_t(c)] = c;
    } else {
        for (std::size_t o = 0; o < report.cell_map.size(); ++o)
            if (const Index c = report.cell_map[o]; c != kNone && c < n_cells)
                source[std::size_t(c)] = Index(o);
    }
    for (const cut::CellOrigin& origin : report.new_cells)
        if (origin.cell >= 0 && origin.cell < n_cells)
            source[std::size_t(origin.cell)] = origin.parent;
    std::vector<std::uint8_t> changed(std::size_t(n_cells), 0);
    for (Index c : report.changed_cells)
        if (c >= 0 && c < n_cells)
            changed[std::size_t(c)] = 1;

    auto part = make_dg_part(s, m);
    const dg::DgModel& nm = *part->model;
    const MatX3 u_old = x - om.rest();
    MatX3 u_new(nm.num_coefficients(), 3), v_new(nm.num_coefficients(), 3);
    for (Index c = 0; c < n_cells; ++c) {
        const Index o = source[std::size_t(c)];
        const int nb = nm.basis(c).size();
        if (o == kNone || o >= om.num_cells())
            throw Error("cut", "cell " + std::to_string(c) + " has no cell it came from");
        if (!changed[std::size_t(c)] && om.basis(o).size() == nb) {
            u_new.middleRows(nm.offset(c), nb) = u_old.middleRows(om.offset(o), nb);
            v_new.middleRows(nm.offset(c), nb) = v.middleRows(om.offset(o), nb);
            continue;
        }
        u_new.middleRows(nm.offset(c), nb) = refit(om, u_old, o, nm, m, c);
        v_new.middleRows(nm.offset(c), nb) = refit(om, v, o, nm, m, c);
    }
    x = nm.rest() + u_new;
    v = v_new;
    return part;
}

Vec3 dg_point_displacement(const DgPart& dg, const MatX3& x, const Vec3& X) {
    const mesh::Mesh& m = dg.model->mesh();
    MatX3 u;
    dg.stitching->displacements(x, u);
    const Index near = nearest_node(m, X);
    geometry::Aabb box;
    for (const Vec3& p : m.rest)
        box.extend(p);
    if (near != kNone && (m.rest[std::size_t(near)] - X).norm() <= 1e-9 * box.diagonal())
        return u.row(near).transpose(); // 003 eq. 17
    const dg::MlsEmbedding mls(*dg.model, { X }); // 003 eq. 18-19
    MatX3 out;
    mls.displacements(u, out);
    return out.row(0).transpose();
}

} // namespace polycut::sim
